// Float methods of the math library need the prelude crate.
fn trax_main() {
    let a = 1.0f32;
    let s = a.sin();
}
