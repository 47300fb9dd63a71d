// A float where an integer is declared.
fn trax_main() {
    let x: u32 = 1.5; //~ E0308
    println!("{}", x);
}
