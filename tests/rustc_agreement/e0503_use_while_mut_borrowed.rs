// Using a value while it is mutably borrowed.
fn trax_main() {
    let mut x = 10u32;
    let m = &mut x;
    let y = x + 1; //~ E0503
    *m += 1;
    println!("{} {}", x, y);
}
