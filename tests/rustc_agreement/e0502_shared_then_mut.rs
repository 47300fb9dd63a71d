// A shared borrow still in use when the value is borrowed mutably.
fn bump(a: &mut [u32; 4]) {
    a[0] += 1;
}

fn trax_main() {
    let mut a = [1u32, 2, 3, 4];
    let first = &a[0];
    bump(&mut a); //~ E0502
    println!("{}", first);
}
