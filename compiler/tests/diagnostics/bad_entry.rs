fn trax_main(x: u32) {}
