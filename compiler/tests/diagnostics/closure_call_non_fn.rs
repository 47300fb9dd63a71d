// Only closures and named functions can be called.
fn trax_main() {
    let k = 3;
    let y = k(2);
}
