fn trax_main() {
    let p = (1, 2);
}
