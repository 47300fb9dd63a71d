// A `&mut self` method given another `&mut` of the same value.
struct Acc {
    sum: u32,
}

impl Acc {
    fn merge(&mut self, other: &mut Acc) {
        self.sum += other.sum;
        other.sum = 0;
    }
}

fn trax_main() {
    let mut a = Acc { sum: 3 };
    let r = &mut a;
    a.merge(r); //~ E0499
    println!("{}", a.sum);
}
