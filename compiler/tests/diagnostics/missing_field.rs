struct P {
    x: f32,
    y: f32,
}

fn trax_main() {
    let p = P { x: 1.0 };
}
