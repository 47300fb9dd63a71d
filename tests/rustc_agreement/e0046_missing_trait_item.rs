// An impl missing a method of its trait.
trait Shape {
    fn area(&self) -> f32;
    fn name(&self) -> u32;
}

struct Disk(f32);

impl Shape for Disk { //~ E0046
    fn area(&self) -> f32 {
        3.14 * self.0 * self.0
    }
}

fn trax_main() {
    println!("{}", Disk(1.0).area());
}
