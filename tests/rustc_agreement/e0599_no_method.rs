// A method that does not exist.
struct Sphere {
    r: f32,
}

fn trax_main() {
    let s = Sphere { r: 1.0 };
    println!("{}", s.volume()); //~ E0599
}
