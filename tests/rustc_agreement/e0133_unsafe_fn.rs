// Calling an `unsafe fn` outside `unsafe`.
unsafe fn raw_read(addr: u32) -> u32 {
    addr
}

fn trax_main() {
    println!("{}", raw_read(4)); //~ E0133
}
