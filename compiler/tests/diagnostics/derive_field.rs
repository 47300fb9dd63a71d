struct NoDbg {
    v: f32,
}
#[derive(Debug)]
struct Outer {
    inner: NoDbg,
}
fn trax_main() {}
