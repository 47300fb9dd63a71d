struct P {
    x: f32,
}

fn trax_main() {
    let p = P { x: 1.0 };
    let y = p.y;
}
