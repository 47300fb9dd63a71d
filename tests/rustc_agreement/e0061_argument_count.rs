// Too few arguments.
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

fn trax_main() {
    println!("{}", lerp(0.0, 1.0)); //~ E0061
}
