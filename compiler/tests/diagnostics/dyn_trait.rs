trait Shape {
    fn area(&self) -> f32;
}

fn total(s: &dyn Shape) -> f32 {
    s.area()
}

fn trax_main() {}
