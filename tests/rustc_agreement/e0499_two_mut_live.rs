// Two mutable borrows of one array live at once.
fn trax_main() {
    let mut a = [0u32; 4];
    let p = &mut a;
    let q = &mut a; //~ E0499
    p[0] = 1;
    q[1] = 2;
    println!("{:?}", a);
}
