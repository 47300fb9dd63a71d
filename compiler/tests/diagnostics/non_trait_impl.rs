#[derive(Clone, Copy)]
struct P {
    x: f32,
}

impl PartialEq for P {
    fn eq(&self, o: &P) -> bool {
        true
    }
}

fn trax_main() {}
