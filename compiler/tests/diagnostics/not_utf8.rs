fn trax_main() {
    // café in Latin-1
    let x = 1;
}
