trait Shape {
    fn area(&self) -> f32;
    fn twice(&self) -> f32 {
        2.0 * self.area()
    }
}

struct Square(f32);

impl Shape for Square {
    fn area(&self) -> f32 {
        self.0 * self.0
    }
}

fn biggest<T: PartialOrd + Copy>(a: T, b: T) -> T {
    if a > b {
        a
    } else {
        b
    }
}

fn trax_main() {
    let s = Square(trax::rand());
    trax::store_f32(0, biggest(s.twice(), 1.0));
    trax::store_u32(4, biggest(trax::global_id(), 3));
}
