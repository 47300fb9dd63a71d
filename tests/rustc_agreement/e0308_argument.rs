// An argument of the wrong type.
fn scale(v: f32, k: f32) -> f32 {
    v * k
}

fn trax_main() {
    let n = 3u32;
    println!("{}", scale(1.0, n)); //~ E0308
}
