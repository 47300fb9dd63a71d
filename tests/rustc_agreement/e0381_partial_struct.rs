// A variable declared without a value and read.
fn trax_main() {
    let t: f32;
    let d = t * 2.0; //~ E0381
    println!("{}", d);
}
