// Reading a `static mut` outside `unsafe`.
static mut FRAMES: u32 = 0;

fn trax_main() {
    let f = FRAMES; //~ E0133
    println!("{}", f);
}
