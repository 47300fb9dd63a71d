// Assigning to a field that is borrowed.
struct Pixel {
    r: f32,
    g: f32,
}

fn trax_main() {
    let mut p = Pixel { r: 0.5, g: 0.25 };
    let red = &p.r;
    p.r = 1.0; //~ E0506
    println!("{} {}", red, p.g);
}
