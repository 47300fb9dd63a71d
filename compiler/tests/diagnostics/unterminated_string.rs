fn trax_main() {
    let s = "abc;
    println!("{}", s);
}
