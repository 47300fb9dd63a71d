fn trax_main() {
    let x: f32 = 1;
}
