// A method taking `self` by value moves the receiver.
struct Stack {
    top: u32,
}

impl Stack {
    fn finish(self) -> u32 {
        self.top
    }
}

fn trax_main() {
    let s = Stack { top: 4 };
    let a = s.finish();
    let b = s.finish(); //~ E0382
    println!("{} {}", a, b);
}
