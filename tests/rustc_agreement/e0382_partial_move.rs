// Moving a field out of a struct leaves the struct partially moved.
struct Inner {
    v: u32,
}

struct Outer {
    inner: Inner,
    w: u32,
}

fn take(i: Inner) -> u32 {
    i.v
}

fn whole(o: Outer) -> u32 {
    o.w
}

fn trax_main() {
    let o = Outer { inner: Inner { v: 1 }, w: 2 };
    let a = take(o.inner);
    let b = whole(o); //~ E0382
    println!("{} {}", a, b);
}
