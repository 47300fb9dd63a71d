fn trax_main() {
    let f = |x: i32| x + 1;
}
