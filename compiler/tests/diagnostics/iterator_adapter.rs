fn trax_main() {
    let a = [1.0f32, 2.0];
    let mut s = 0.0;
    for x in a.iter().map(|v| v * 2.0) {
        s += x;
    }
}
