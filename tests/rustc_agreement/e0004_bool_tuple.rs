// A tuple of bools with one combination missing.
fn both(a: bool, b: bool) -> u32 {
    match (a, b) { //~ E0004
        (true, true) => 3,
        (true, false) => 2,
        (false, true) => 1,
    }
}

fn trax_main() {
    println!("{}", both(false, false));
}
