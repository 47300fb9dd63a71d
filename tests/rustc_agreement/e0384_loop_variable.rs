// A `for` loop binding is immutable.
fn trax_main() {
    let mut sum = 0u32;
    for i in 0..4u32 {
        i += 1; //~ E0384
        sum += i;
    }
    println!("{}", sum);
}
