fn f(x: u32) -> u32 {
    x?
}

fn trax_main() {}
