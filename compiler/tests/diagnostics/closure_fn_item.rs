// A named function is not a closure value (no function pointers).
fn apply<F: Fn(i32) -> i32>(f: F, x: i32) -> i32 {
    f(x)
}

fn square(x: i32) -> i32 {
    x * x
}

fn trax_main() {
    let y = apply(square, 3);
}
