//! TRaX-Rust language suite, part 6: closures. Closures without captures, capturing by
//! reference (shared and mutable) and by value (`move`), passed to generic functions with
//! `Fn`/`FnMut`/`FnOnce` bounds (by value and by reference), stored in generic structs,
//! called directly, nested, with typed and pattern parameters, inside generic functions;
//! the `Option`/`Result` combinators that take closures.
//! Every call is static: each closure expression is its own type.

fn apply<F: Fn(i32) -> i32>(f: F, x: i32) -> i32 {
    f(x)
}

fn apply_mut<F: FnMut(i32)>(mut f: F, n: i32) {
    for i in 0..n {
        f(i);
    }
}

fn twice<F>(f: &F, x: f32) -> f32
where
    F: Fn(f32) -> f32,
{
    f(f(x))
}

fn consume<F: FnOnce() -> u32>(f: F) -> u32 {
    f()
}

fn compose<A: Fn(i32) -> i32, B: Fn(i32) -> i32>(a: A, b: B, x: i32) -> i32 {
    b(a(x))
}

fn call0<F: Fn() -> i32>(f: F) -> i32 {
    f()
}

fn gen<T: Copy + std::ops::Add<Output = T>>(a: T, b: T) -> T {
    let f = |x: T| x + b;
    f(a)
}

/// Integrates `f` over [a, b] with the midpoint rule.
fn integrate<F: Fn(f64) -> f64>(f: F, a: f64, b: f64, n: u32) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = 0.0;
    for i in 0..n {
        s += f(a + (i as f64 + 0.5) * h);
    }
    s * h
}

struct Mapper<F: Fn(i32) -> i32> {
    f: F,
    calls: u32,
}

impl<F: Fn(i32) -> i32> Mapper<F> {
    fn run(&mut self, x: i32) -> i32 {
        self.calls += 1;
        (self.f)(x)
    }
}

#[derive(Debug, Clone, Copy)]
struct P {
    x: f32,
    y: f32,
}

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let k = 3;
    println!("no capture {}", apply(|x| x * 2 + 1, 5));
    println!("capture {}", apply(|x| x * k, 5));
    let mut sum = 0;
    apply_mut(|i| sum += i * i, 5);
    println!("sum {}", sum);
    let s = 1.5f32;
    let g = |x: f32| x * s;
    println!("twice {} direct {}", twice(&g, 2.0), g(4.0));
    let p = P { x: 1.0, y: 2.0 };
    let m = move || (p.x + p.y) as u32 + 7;
    println!("move {} {:?}", consume(m), p);
    println!("compose {}", compose(|x| x + 1, |y| y * 10, 4));
    let add = |a: i32, b: i32| -> i32 { a + b };
    println!("typed {}", add(2, 3));
    let mut count = 0u32;
    let mut inc = || count += 1;
    inc();
    inc();
    println!("count {}", count);
    let pts = [P { x: 1.0, y: 0.0 }, P { x: -2.0, y: 1.0 }];
    let mut total = 0.0f32;
    for q in pts.iter() {
        let d = |o: &P| o.x * o.x + o.y * o.y;
        total += d(q);
    }
    println!("total {:?}", total);
    let pick = |(a, b): (i32, i32)| if a > b { a } else { b };
    println!("pattern {}", pick((3, 9)));
    let a = 4;
    let outer = |y: i32| {
        let inner = || a + y;
        call0(inner) * 2
    };
    println!("nested {}", outer(1));
    println!("generic {} {}", gen(1, 2), gen(1.5f32, 2.0));
    let mut acc = [0i32; 3];
    let mut put = |i: usize, val: i32| acc[i] = val;
    put(0, 5);
    put(2, 7);
    println!("array {:?}", acc);
    let c = 2.0;
    println!("integral {:?}", integrate(|x| c * x * x, 0.0, 3.0, 100));
    let mut mp = Mapper { f: |x| x - k, calls: 0 };
    let r = mp.run(10) + mp.run(20);
    println!("mapper {} {}", r, mp.calls);
    let early = |x: i32| -> i32 {
        if x < 0 {
            return 0;
        }
        x * 2
    };
    println!("return {} {}", early(-5), early(5));
    let first_even = |xs: &[i32]| -> Option<usize> {
        for (i, x) in xs.iter().enumerate() {
            if x % 2 == 0 {
                return Some(i);
            }
        }
        None
    };
    println!("slice {:?} {:?}", first_even(&[1, 3, 4]), first_even(&[1]));
    let base = 10;
    let some = first_even(&[5, 8]);
    let none = first_even(&[5]);
    println!(
        "option map {:?} {:?} map_or {} {} map_or_else {}",
        some.map(|i| i as i32 + base),
        none.map(|i| i + 1),
        some.map_or(-1, |i| i as i32 * 3),
        none.map_or(-1, |i| i as i32 * 3),
        none.map_or_else(|| base * 2, |i| i as i32),
    );
    println!(
        "and_then {:?} {:?} or_else {:?} unwrap_or_else {} filter {:?} {:?}",
        some.and_then(|i| if i > 0 { Some(i * 100) } else { None }),
        Some(0usize).and_then(|i| if i > 0 { Some(i * 100) } else { None }),
        none.or_else(|| Some(77)),
        none.unwrap_or_else(|| 42),
        Some(4).filter(|x| *x % 2 == 0),
        Some(5).filter(|x| *x % 2 == 0),
    );
    let mut calls = 0;
    let lazy = Some(3).unwrap_or_else(|| {
        calls += 1;
        0
    });
    println!(
        "lazy {} {} is_some_and {} {} ok_or_else {:?} {:?}",
        lazy,
        calls,
        some.is_some_and(|i| i == 1),
        none.is_some_and(|i| i == 1),
        some.ok_or_else(|| "none"),
        none.ok_or_else(|| base),
    );
    let ok: Result<i32, u8> = Ok(6);
    let err: Result<i32, u8> = Err(2);
    println!(
        "result map {:?} {:?} map_err {:?} {:?} and_then {:?} unwrap_or_else {} {} is_ok_and {} {}",
        ok.map(|v| v * k),
        err.map(|v| v * k),
        ok.map_err(|e| e as i32 + 1),
        err.map_err(|e| e as i32 + 1),
        ok.and_then(|v| if v > 5 { Err(9) } else { Ok(v) }),
        ok.unwrap_or_else(|e| e as i32),
        err.unwrap_or_else(|e| e as i32 * 100),
        ok.is_ok_and(|v| v == 6),
        err.is_ok_and(|v| v == 6),
    );
}
