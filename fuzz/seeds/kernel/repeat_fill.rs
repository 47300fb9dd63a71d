// A local array above the compiler's in-place fill threshold, filled and read back.
fn trax_main() {
    let mut a = [7u32; 2048];
    a[3] = 1;
    let mut s = 0u32;
    for v in a.iter() {
        s += *v;
    }
    println!("{}", s);
}
