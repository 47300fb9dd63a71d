fn helper(x: u32) -> u32 {
    if x > 3 {
        x * 2
    } else {
        x
    }

fn trax_main() {
    println!("{}", helper(4));
}
