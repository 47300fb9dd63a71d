// A `&mut self` method through a shared reference.
struct Film {
    n: u32,
}

impl Film {
    fn add(&mut self) {
        self.n += 1;
    }
}

fn record(f: &Film) {
    f.add(); //~ E0596
}

fn trax_main() {
    let mut f = Film { n: 0 };
    record(&f);
    f.add();
    println!("{}", f.n);
}
