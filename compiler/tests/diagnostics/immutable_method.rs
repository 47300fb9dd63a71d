#[derive(Clone, Copy)]
struct C {
    n: u32,
}

impl C {
    fn bump(&mut self) {
        self.n += 1;
    }
}

fn trax_main() {
    let c = C { n: 0 };
    c.bump();
}
