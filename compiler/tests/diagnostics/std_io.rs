use std::io::Write;

fn trax_main() {}
