// A generic function called with a type that lacks the bound.
trait Area {
    fn area(&self) -> f32;
}

struct Square(f32);

fn total<T: Area>(a: &T, b: &T) -> f32 {
    a.area() + b.area()
}

fn trax_main() {
    let s = Square(2.0);
    println!("{}", total(&s, &s)); //~ E0277
}
