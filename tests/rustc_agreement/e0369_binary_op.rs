// `+` on a struct without `Add`.
#[derive(Clone, Copy)]
struct Rgb {
    r: f32,
}

fn trax_main() {
    let a = Rgb { r: 0.5 };
    let b = a + a; //~ E0369
    println!("{}", b.r);
}
