// C passes a struct by value differently (on the stack, or through a hidden pointer).
struct Pair {
    a: f32,
    b: f32,
}

extern "C" {
    fn sum(p: Pair) -> f32;
}

fn trax_main() {
    let _ = unsafe { sum(Pair { a: 1.0, b: 2.0 }) };
}
