// Only the C ABI is understood.
extern "system" {
    fn helper(x: f32) -> f32;
}

fn trax_main() {
    let _ = unsafe { helper(1.0) };
}
