// Assigning twice to an immutable variable.
fn trax_main() {
    let x = 3u32;
    println!("{}", x);
    x = 4; //~ E0384
    println!("{}", x);
}
