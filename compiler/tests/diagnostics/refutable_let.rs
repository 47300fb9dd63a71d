enum Shape {
    Circle(f32),
    Empty,
}

fn trax_main() {
    let s = Shape::Empty;
    let Shape::Circle(r) = s;
}
