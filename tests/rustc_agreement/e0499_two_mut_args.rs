// Two `&mut` of one variable passed to one call.
fn swap_add(a: &mut u32, b: &mut u32) {
    *a += *b;
    *b += 1;
}

fn trax_main() {
    let mut x = 1u32;
    swap_add(&mut x, &mut x); //~ E0499
    println!("{}", x);
}
