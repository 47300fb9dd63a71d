// Assigning through a shared reference.
struct Camera {
    fov: f32,
}

fn widen(c: &Camera) {
    c.fov = 90.0; //~ E0594
}

fn trax_main() {
    let c = Camera { fov: 45.0 };
    widen(&c);
    println!("{}", c.fov);
}
