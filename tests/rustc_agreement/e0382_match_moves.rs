// A `match` that binds by value moves the matched value.
enum Shape {
    Sphere(Radius),
    Empty,
}

struct Radius(f32);

fn trax_main() {
    let s = Shape::Sphere(Radius(1.0));
    let r = match s {
        Shape::Sphere(r) => r.0,
        Shape::Empty => 0.0,
    };
    if let Shape::Sphere(q) = s { //~ E0382
        println!("{}", q.0);
    }
    println!("{}", r);
}
