fn check(v: u32) {
    if v > 3 {
        panic!("bad id {} of {}", v);
    }
}

fn trax_main() {
    check(4);
}
