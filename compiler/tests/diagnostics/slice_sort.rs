fn trax_main() {
    let mut a = [3u32, 1, 2];
    a.sort();
    println!("{:?}", a);
}
