// Boxed closures need the heap and trait objects.
fn trax_main() {
    let b: Box<dyn Fn(i32) -> i32> = Box::new(|x| x);
}
