fn name() -> String {
    loop {}
}

fn trax_main() {}
