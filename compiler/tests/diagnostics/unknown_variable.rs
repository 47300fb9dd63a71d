fn trax_main() {
    let x = y + 1;
}
