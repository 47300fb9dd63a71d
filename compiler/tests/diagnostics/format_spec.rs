fn trax_main() {
    let x = 1.5f32;
    println!("{:.2}", x);
}
