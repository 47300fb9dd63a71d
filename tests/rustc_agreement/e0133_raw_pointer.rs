// Dereferencing a raw pointer outside `unsafe`.
fn trax_main() {
    let x = 7u32;
    let p = &x as *const u32;
    let y = *p; //~ E0133
    println!("{}", y);
}
