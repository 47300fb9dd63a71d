enum Mode {
    Fast,
    Slow,
}

fn trax_main() {}
