// A refutable pattern in `let`.
enum Hit {
    Surface(f32),
    Miss,
}

fn trax_main() {
    let h = Hit::Miss;
    let Hit::Surface(t) = h; //~ E0005
    println!("{}", t);
}
