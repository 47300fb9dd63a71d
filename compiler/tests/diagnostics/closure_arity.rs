// A closure passed to `F: Fn(i32) -> i32` must take one argument.
fn apply<F: Fn(i32) -> i32>(f: F, x: i32) -> i32 {
    f(x)
}

fn trax_main() {
    let y = apply(|a, b| a + b, 1);
}
