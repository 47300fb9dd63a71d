fn f() -> u32 {
    3
}

static X: u32 = f();

fn trax_main() {
    let y = X;
}
