// Variadic C functions (printf) have no TRaX implementation and no fixed ABI here.
extern "C" {
    fn printf(fmt: *const u8, ...) -> i32;
}

fn trax_main() {
    unsafe {
        printf("hi\n".as_ptr());
    }
}
