fn area(s: impl Copy) -> f32 {
    0.0
}

fn trax_main() {}
