fn a() -> u32 {
    let x: u32 = -1;
    x
}

fn b() -> u32 {
    -1 as u32
}

fn trax_main() {
    println!("{} {}", a(), b());
}
