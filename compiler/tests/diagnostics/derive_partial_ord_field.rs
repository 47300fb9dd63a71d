#[derive(Clone, Copy, PartialEq, PartialOrd)]
struct Sample {
    rgb: [f32; 3],
    weight: f32,
}

fn trax_main() {}
