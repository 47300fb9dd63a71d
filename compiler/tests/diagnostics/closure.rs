// Iterator adapters taking closures are not values in TRaX-Rust (use the loop body).
fn trax_main() {
    let v = [1, 2, 3];
    let mut s = 0;
    for x in v.iter().map(|x| x * 2) {
        s += x;
    }
}
