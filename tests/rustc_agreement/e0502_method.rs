// A `&self` borrow kept while a `&mut self` method runs.
struct Counter {
    n: u32,
}

impl Counter {
    fn get(&self) -> &u32 {
        &self.n
    }
    fn inc(&mut self) {
        self.n += 1;
    }
}

fn trax_main() {
    let mut c = Counter { n: 0 };
    let n = c.get();
    c.inc(); //~ E0502
    println!("{}", n);
}
