#[derive(Clone, Copy)]
struct S {
    v: u32,
}

fn total<T: Copy>(xs: &[T]) -> T {
    let mut s = xs[0];
    for &x in xs {
        s = s + x;
    }
    s
}

fn trax_main() {
    let a = [S { v: 1 }, S { v: 2 }];
    let t = total(&a);
}
