// The example: `let r = &v[0]; v[0] = 5; *r`.
fn trax_main() {
    let mut v = [1u32, 2, 3];
    let r = &v[0];
    v[0] = 5; //~ E0506
    println!("{}", *r);
}
