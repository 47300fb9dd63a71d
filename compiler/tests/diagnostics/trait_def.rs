trait Shape {
    fn area(&self) -> f32;
}

fn trax_main() {}
