// `extern "C"` is for functions C code calls: they need `#[no_mangle]`.
extern "C" fn helper(x: f32) -> f32 {
    x * 2.0
}

fn trax_main() {
    let _ = helper(1.0);
}
