trait Area {
    fn area(&self) -> f32;
}
struct Sq(f32);
fn show<T: Area>(t: &T) -> f32 {
    t.area()
}
fn trax_main() {
    let s = Sq(2.0);
    let a = show(&s);
}
