// `*` on a value that is not a pointer.
fn trax_main() {
    let x = 3u32;
    let y = *x; //~ E0614
    println!("{}", y);
}
