#[derive(Clone, Copy)]
struct P {
    x: f32,
}

fn trax_main() {
    let a = P { x: 1.0 };
    let b = a + a;
}
