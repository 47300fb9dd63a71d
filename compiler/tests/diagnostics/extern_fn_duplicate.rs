// Two exports under one C name.
mod a {
    #[no_mangle]
    pub extern "C" fn scale(x: f32) -> f32 {
        x * 2.0
    }
}

mod b {
    #[no_mangle]
    pub extern "C" fn scale(x: f32) -> f32 {
        x * 3.0
    }
}
