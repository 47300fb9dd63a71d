//! Uses every language feature of TRaX-Rust (brief §3). Valid Rust: it also builds with
//! rustc against the host prelude, and prints the same text on both.

mod geometry;

mod util {
    pub const SCALE: i32 = 3;

    pub fn triple(x: i32) -> i32 {
        x * SCALE
    }

    pub mod deep {
        pub fn quad(x: i32) -> i32 {
            super::triple(x) + x
        }
    }
}

use geometry::Vec3;
use util::deep::quad;

const N: usize = 8;
const LIMIT: u32 = 1 << 4;
static TABLE: [i32; 4] = [1, 2, 3, 5];
static mut COUNTER: u32 = 0;

#[derive(Clone, Copy, Debug)]
struct Counter {
    hits: u32,
    misses: u32,
}

impl Counter {
    fn new() -> Counter {
        Counter { hits: 0, misses: 0 }
    }

    fn record(&mut self, hit: bool) {
        if hit {
            self.hits += 1;
        } else {
            self.misses += 1;
        }
    }

    fn total(&self) -> u32 {
        self.hits + self.misses
    }

    fn into_ratio(self) -> f32 {
        if self.total() == 0 {
            0.0
        } else {
            self.hits as f32 / self.total() as f32
        }
    }
}

fn fib(n: u32) -> u32 {
    if n < 2 {
        n
    } else {
        fib(n - 1) + fib(n - 2)
    }
}

#[inline(never)]
fn classify(x: i32) -> u8 {
    match x {
        i32::MIN..=-1 => 0,
        0 => 1,
        1 | 2 | 3 => 2,
        4..=9 => 3,
        _ => 4,
    }
}

#[inline]
fn sum_array(a: &[f32; N]) -> f32 {
    let mut s = 0.0;
    for x in a.iter() {
        s += *x;
    }
    s
}

fn fill(a: &mut [f32; N], v: f32) {
    let mut i = 0;
    while i < N {
        a[i] = v * i as f32;
        i += 1;
    }
}

fn bump() -> u32 {
    unsafe {
        COUNTER += 1;
        COUNTER
    }
}

fn first_square_over(limit: u32) -> u32 {
    let mut i = 0u32;
    let found = loop {
        i += 1;
        if i * i > limit {
            break i;
        }
    };
    found
}

fn trax_main() {
    // Integers, wrapping arithmetic, casts, shifts, bit operations.
    let a: i32 = 7;
    let b = -3;
    let c = a / b + a % b;
    let big: u32 = 0xFFFF_FFF0;
    let wrapped = big.wrapping_add(32);
    let shifted = (1u32 << 31) >> 4;
    let bits = 0b1010u8 ^ 0b0110 | 1 & 3;
    let wide: i64 = (a as i64) << 40;
    let uwide: u64 = wide as u64 + 1;
    let us: usize = 5;
    println!("ints {} {} {} {} {} {} {} {}", c, wrapped, shifted, bits, wide, uwide, us, !a);
    let neg_shift = -16i32 >> 2;
    println!("shift {} {}", neg_shift, (a as u32).count_ones());

    // Floats, methods and printing.
    let x = 2.0f32;
    let y: f64 = 0.1 + 0.2;
    let r = x.sqrt().min(1.5).max(0.5) + (-x).abs() + x.floor() + (2.5f32).ceil();
    let cl = (5.5f32).clamp(0.0, 1.0);
    let m = x.mul_add(3.0, 1.0) + x.powi(3) + (2.5f32).round() + (-2.7f32).trunc();
    println!("floats {} {} {} {} {}", x, y, r, cl, m);
    println!("bits {} {} {}", x.to_bits(), f32::from_bits(0x3f80_0000), (0.0f32 / 0.0).is_nan());
    let third = 1.0f32 / 3.0;
    println!("display {} {} {} {}", third, 1.0e-7f32, 1e20f64, f32::MAX);

    // Booleans, chars, short-circuit.
    let t = a > 3 && b < 0 || false;
    let f = !t;
    let ch = 'Z';
    let byte = b'a';
    println!("bool {} {} char {} {} {}", t, f, ch, byte as char, ch as u32);
    println!("literal {}", "text");

    // Shadowing and blocks as expressions.
    let v = 1;
    let v = v + 1;
    let v = {
        let w = v * 10;
        w + 1
    };
    println!("shadow {}", v);

    // if/else as expressions.
    let kind = if v > 20 {
        "big"
    } else if v > 10 {
        "medium"
    } else {
        "small"
    };
    println!("kind {}", kind);

    // match on integers.
    let mut classes = [0u8; 6];
    let samples = [-5, 0, 2, 7, 100, 3];
    for i in 0..6 {
        classes[i] = classify(samples[i]);
    }
    println!("classes {} {} {} {} {} {}", classes[0], classes[1], classes[2], classes[3], classes[4], classes[5]);

    // Loops: while, loop with break value, for ranges (exclusive, inclusive, reversed),
    // labeled break/continue.
    let mut total = 0;
    for i in 0..10 {
        if i % 2 == 0 {
            continue;
        }
        total += i;
    }
    for i in 1..=3 {
        total += i * 100;
    }
    for i in (0..3).rev() {
        total = total * 2 + i;
    }
    let mut pairs = 0;
    'outer: for i in 0..5 {
        for j in 0..5 {
            if j > i {
                continue 'outer;
            }
            if i == 4 {
                break 'outer;
            }
            pairs += 1;
        }
    }
    println!("loops {} {} {}", total, pairs, first_square_over(LIMIT));

    // Recursion, modules, use, consts, statics.
    println!("fib {} quad {} table {} scale {}", fib(10), quad(2), TABLE[3], util::SCALE);
    bump();
    println!("counter {}", bump());

    // Structs, methods with self/&self/&mut self, derive(Clone, Copy).
    let mut cnt = Counter::new();
    for i in 0..10 {
        cnt.record(i % 3 == 0);
    }
    let copy = cnt;
    println!("counter {} {} {} {}", cnt.hits, copy.misses, cnt.total(), copy.into_ratio());

    // Operator overloading.
    let p = Vec3::new(1.0, 2.0, 3.0);
    let q = Vec3::splat(0.5);
    let mut s = p + q * 2.0 - -p;
    s += Vec3::new(1.0, 1.0, 1.0);
    s -= q;
    s *= 2.0;
    s /= 4.0;
    let d = (p * q) / Vec3::splat(2.0);
    println!("vec {} {} {} dot {} len {}", s.x, s.y, s.z, p.dot(q), d.length());

    // Arrays, references, raw pointers.
    let mut arr = [0.0f32; N];
    fill(&mut arr, 0.5);
    let sum = sum_array(&arr);
    let rp: *const f32 = &arr[2];
    let second = unsafe { *rp.add(1) };
    let mut cell = 5u32;
    let mp = &mut cell as *mut u32;
    unsafe {
        *mp += 1;
    }
    let rr = &cell;
    println!("arrays {} {} {} {}", sum, second, *rr, arr.len());

    // Nested struct with array field; field assignment through references.
    let mut tri = geometry::Triangle { v: [p, q, s], id: 9 };
    {
        let first = &mut tri.v[0];
        first.x = 10.0;
    }
    println!("tri {} {} {}", tri.v[0].x, tri.id, tri.centroid().y);

    // assert!, assert_eq! (pass); panic!/unreachable! are exercised by the runtime tests.
    assert!(cnt.total() == 10, "counted");
    assert_eq!(classify(4), 3);
    assert_ne!(fib(5), 0);
    print!("done");
    println!();
}
