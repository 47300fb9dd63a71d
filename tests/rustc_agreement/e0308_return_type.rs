// A function returning the wrong type.
fn area(w: u32, h: u32) -> f32 {
    w * h //~ E0308
}

fn trax_main() {
    println!("{}", area(2, 3));
}
