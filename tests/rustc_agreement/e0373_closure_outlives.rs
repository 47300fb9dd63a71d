// A closure returned from a function borrows a local.
fn adder(k: u32) -> impl Fn(u32) -> u32 {
    |x| x + k //~ E0373
}

fn trax_main() {
    println!("{}", adder(2)(3));
}
