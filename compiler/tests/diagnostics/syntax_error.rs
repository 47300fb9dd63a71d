fn trax_main() {
    let x = ;
}
