// Closures are not evaluated at compile time.
const C: i32 = {
    let f = |x: i32| x;
    f(1)
};

fn trax_main() {}
