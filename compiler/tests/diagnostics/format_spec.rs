fn trax_main() {
    let x = 1.5f32;
    println!("{:p}", &x);
}
