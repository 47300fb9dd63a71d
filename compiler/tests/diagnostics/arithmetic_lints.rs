const BIG: u8 = 200;

fn div(x: i32) -> i32 {
    x / 0
}

fn add() -> u8 {
    BIG + BIG
}

fn local() -> u8 {
    let x = 255u8;
    x + 1
}

fn shift(x: u32) -> u32 {
    x << 32
}

fn index() -> u32 {
    let a = [1u32, 2, 3];
    a[3]
}

fn negate() -> i32 {
    -i32::MIN
}

fn compound(mut x: i32) -> i32 {
    x %= 0;
    x
}

fn trax_main() {
    // Not linted (as in rustc): a branch a constant condition never takes, a wrapping call.
    if false {
        println!("{}", 1 / 0);
    }
    println!("{}", BIG.wrapping_add(BIG));
    println!("{} {} {} {} {} {} {}", div(1), add(), local(), shift(2), index(), negate(), compound(3));
}
