fn trax_main() {
    let s = String::from("hit");
    let v = Vec::<u32>::new();
    println!("{} {}", s, v.len());
}
