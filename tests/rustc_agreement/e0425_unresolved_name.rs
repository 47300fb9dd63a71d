// A name that is not defined.
fn trax_main() {
    let a = 1u32;
    println!("{}", a + bias); //~ E0425
}
