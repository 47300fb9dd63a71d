// C passes slices and structs differently from TRaX-Rust.
#[no_mangle]
pub extern "C" fn total(xs: &[f32]) -> f32 {
    xs[0]
}
