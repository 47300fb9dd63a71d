struct S {
    x: f32,
}

fn draw(s: &dyn Fn()) {}

fn trax_main() {}
