// Mutating an array while iterating over it.
fn trax_main() {
    let mut a = [1u32, 2, 3];
    for x in a.iter() {
        a[0] += *x; //~ E0506
    }
    println!("{:?}", a);
}
