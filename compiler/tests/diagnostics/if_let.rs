fn trax_main() {
    let x = 3;
    if let 3 = x {}
}
