// Returning a closure needs `impl Trait`, which TRaX-Rust does not have.
fn make(k: i32) -> impl Fn(i32) -> i32 {
    move |x| x + k
}

fn trax_main() {
    let f = make(3);
}
