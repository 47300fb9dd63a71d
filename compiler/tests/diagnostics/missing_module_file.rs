mod nowhere;

fn trax_main() {}
