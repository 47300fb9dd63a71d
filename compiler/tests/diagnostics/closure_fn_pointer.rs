// Function pointer types are outside TRaX-Rust.
fn square(x: i32) -> i32 {
    x * x
}

fn trax_main() {
    let p: fn(i32) -> i32 = square;
}
