// One C function declared twice.
extern "C" {
    fn shade(x: f32) -> f32;
}

mod inner {
    extern "C" {
        fn shade(x: f32) -> f32;
    }
    pub fn go() -> f32 {
        unsafe { shade(2.0) }
    }
}

fn trax_main() {
    let _ = unsafe { shade(1.0) } + inner::go();
}
