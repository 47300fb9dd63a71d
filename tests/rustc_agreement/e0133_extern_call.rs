// A call to a function of an `extern "C"` block outside `unsafe`.
extern "C" {
    fn shade(x: f32) -> f32;
}

fn trax_main() {
    let v = shade(0.5); //~ E0133
    println!("{}", v);
}
