#[derive(Clone, Copy, Debug)]
struct P {
    x: f32,
}

fn trax_main() {
    let p = P { x: 1.0 };
    println!("{}", p);
}
