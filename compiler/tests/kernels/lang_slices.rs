//! TRaX-Rust language suite, part 3: slices `&[T]`/`&mut [T]` (bounds-checked), `len`,
//! sub-slicing, `iter`/`iter_mut` with `enumerate`, `zip`, `rev`, `step_by`, `skip`,
//! `take`, `copied`; slice patterns; `core::mem::swap`/`replace`/`take`; slice
//! methods (`first`, `last`, `swap`, `fill`, `contains`, `is_empty`).

fn sum(xs: &[f32]) -> f32 {
    let mut s = 0.0;
    for x in xs {
        s += x;
    }
    s
}

fn dot(a: &[f32], b: &[f32]) -> f32 {
    let mut s = 0.0;
    for (x, y) in a.iter().zip(b.iter()) {
        s += x * y;
    }
    s
}

fn scale(xs: &mut [f32], k: f32) {
    for x in xs.iter_mut() {
        *x *= k;
    }
}

fn argmax(xs: &[i32]) -> Option<usize> {
    if xs.is_empty() {
        return None;
    }
    let mut best = 0;
    for (i, &x) in xs.iter().enumerate() {
        if x > xs[best] {
            best = i;
        }
    }
    Some(best)
}

fn describe(xs: &[u8]) -> u32 {
    match xs {
        [] => 0,
        [a] => *a as u32,
        [a, b] => (*a as u32) * 10 + *b as u32,
        [first, .., last] => 1000 + (*first as u32) * 10 + *last as u32,
    }
}

fn middle(xs: &[u32]) -> &[u32] {
    if xs.len() < 3 {
        return xs;
    }
    &xs[1..xs.len() - 1]
}

fn insertion_sort(xs: &mut [i32]) {
    for i in 1..xs.len() {
        let mut j = i;
        while j > 0 && xs[j - 1] > xs[j] {
            xs.swap(j - 1, j);
            j -= 1;
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
struct Entry {
    node: u32,
    t: f32,
}

/// A fixed-capacity stack of `(node, t)` pairs, as a BVH traversal keeps.
struct Stack {
    items: [(u32, f32); 8],
    len: usize,
}

impl Stack {
    fn new() -> Stack {
        Stack {
            items: [(0, 0.0); 8],
            len: 0,
        }
    }
    fn push(&mut self, node: u32, t: f32) {
        self.items[self.len] = (node, t);
        self.len += 1;
    }
    fn pop(&mut self) -> Option<(u32, f32)> {
        if self.len == 0 {
            None
        } else {
            self.len -= 1;
            Some(self.items[self.len])
        }
    }
    fn live(&self) -> &[(u32, f32)] {
        &self.items[..self.len]
    }
}

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let a = [1.0f32, 2.0, 3.0, 4.0];
    let b = [0.5f32, 0.25, 2.0, 1.0];
    println!("sum {} {} dot {}", sum(&a), sum(&a[1..3]), dot(&a, &b));
    let mut c = a;
    scale(&mut c, 2.0);
    scale(&mut c[..2], 10.0);
    println!("scaled {:?} len {} {}", c, c.len(), (&c[2..]).len());
    println!("argmax {:?} {:?}", argmax(&[3, 9, -1, 9]), argmax(&[]));
    println!("describe {} {} {} {}", describe(&[]), describe(&[7]), describe(&[1, 2]), describe(&[4, 5, 6, 9]));
    let m = [10u32, 20, 30, 40, 50];
    println!("middle {:?} {:?} {:?}", middle(&m), middle(&m[..2]), &m[1..=2]);
    let mut v = [5, -3, 8, 0, 2, 2, -7];
    insertion_sort(&mut v);
    println!("sorted {:?}", v);
    // Iterator adapters in for loops.
    for (i, x) in a.iter().enumerate().rev() {
        print!("{}:{} ", i, x);
    }
    println!();
    for x in m.iter().step_by(2) {
        print!("{} ", x);
    }
    println!();
    for x in m.iter().rev().step_by(2) {
        print!("{} ", x);
    }
    println!();
    for (i, x) in m.iter().skip(1).take(3).enumerate() {
        print!("{}={} ", i, x);
    }
    println!();
    for (k, (x, y)) in (0..10).zip(a.iter().zip(b.iter())) {
        print!("{}:{}*{} ", k, x, y);
    }
    println!();
    let mut total = 0;
    for x in m.iter().copied() {
        total += x;
    }
    for x in (0..20).rev().step_by(7) {
        print!("{} ", x);
    }
    println!("total {}", total);
    for x in &mut c {
        *x -= 1.0;
    }
    println!("c {:?}", c);
    // Slice methods.
    let s: &[u32] = &m;
    println!("first {:?} last {:?} empty {} contains {} {}", s.first(), s.last(), s.is_empty(), s.contains(&30), s.contains(&31));
    let mut f = [0u16; 5];
    f.fill(3);
    f[..2].fill(9);
    println!("fill {:?}", f);
    // mem::swap / replace / take.
    let mut x = 1;
    let mut y = 2;
    core::mem::swap(&mut x, &mut y);
    let old = std::mem::replace(&mut x, 10);
    let mut e = Entry { node: 4, t: 1.5 };
    let taken = core::mem::take(&mut e);
    println!("swap {} {} {} {:?} {:?}", x, y, old, taken, e);
    // A traversal stack of tuples.
    let mut st = Stack::new();
    st.push(0, 0.5);
    st.push(3, 1.5);
    st.push(7, 0.25);
    println!("live {:?}", st.live());
    while let Some((node, t)) = st.pop() {
        if t < 1.0 {
            print!("visit {} ", node);
        } else {
            print!("skip {} ", node);
        }
    }
    println!();
}
