trait Shape {
    fn area(&self) -> f32;
    fn name(&self) -> u32 {
        0
    }
}

struct Square {
    side: f32,
}

impl Shape for Square {
    fn name(&self) -> u32 {
        1
    }
}

fn trax_main() {}
