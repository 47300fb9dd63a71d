//! TRaX-Rust language suite, part 1: tuples, tuple structs, enums (with and without
//! data, discriminants, `as`), `Option`/`Result`, `match` (enums, tuples, structs,
//! ranges, bindings, guards, `|`, `@`), `if let`, `while let`, `let ... else`, `let`
//! destructuring, `matches!` and `?`. Prints what it computes; `trax native` must print
//! the same bytes.

#[derive(Clone, Copy, Debug, PartialEq)]
enum Material {
    Diffuse(f32),
    Mirror,
    Glass { ior: f32, tint: (f32, f32, f32) },
    Emitter(f32, u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum Axis {
    X = 1,
    Y = 2,
    Z = 4,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Sign {
    Neg = -1,
    Zero,
    Pos,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Hit {
    t: f32,
    id: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Default)]
struct Pair(i32, i32);

#[derive(Clone, Copy, Debug)]
struct Unit;

fn intersect(t: f32, id: u32) -> Option<Hit> {
    if t > 0.0 {
        Some(Hit { t, id })
    } else {
        None
    }
}

fn classify(x: i32) -> &'static str {
    match x {
        i32::MIN..=-1 => "negative",
        0 => "zero",
        1 | 2 | 3 => "small",
        n if n % 2 == 0 => "even",
        _ => "odd",
    }
}

fn albedo(m: &Material) -> f32 {
    match m {
        Material::Diffuse(a) => *a,
        Material::Mirror => 1.0,
        Material::Glass { ior, .. } if *ior > 1.4 => 0.9,
        Material::Glass { tint: (r, g, b), .. } => (r + g + b) / 3.0,
        Material::Emitter(p, _) => p * 0.5,
    }
}

fn div(a: i32, b: i32) -> Result<i32, u32> {
    if b == 0 {
        Err(7)
    } else {
        Ok(a / b)
    }
}

fn twice(a: i32, b: i32) -> Result<i32, u32> {
    let q = div(a, b)?;
    Ok(q * 2)
}

fn first_hit(ts: &[f32]) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (i, &t) in ts.iter().enumerate() {
        if let Some(h) = intersect(t, i as u32) {
            match best {
                Some(b) if b.t <= h.t => {}
                _ => best = Some(h),
            }
        }
    }
    best
}

fn add_hits(a: Option<Hit>, b: Option<Hit>) -> Option<f32> {
    let x = a?;
    let y = b?;
    Some(x.t + y.t)
}

fn sign_of(v: f32) -> Sign {
    if v < 0.0 {
        Sign::Neg
    } else if v == 0.0 {
        Sign::Zero
    } else {
        Sign::Pos
    }
}

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    // Tuples.
    let p = (1u32, 2.5f32, true);
    let (a, b, c) = p;
    println!("tuple {} {} {} {:?}", a, b, c, p);
    let nested = ((1, 2), [3, 4]);
    let ((x, y), [z, w]) = nested;
    println!("nested {} {} {} {} {}", x, y, z, w, nested.0 .1);
    let mut q = (0i32, 0i32);
    q.0 = 5;
    q.1 += 3;
    println!("q {:?}", q);
    // Tuple structs and unit structs.
    let pr = Pair(3, -4);
    let Pair(m, n) = pr;
    println!("pair {} {} {} {:?} {:?} {:?}", m, n, pr.0 + pr.1, pr, Pair::default(), Unit);
    // Enums with data, matching with bindings, guards and nested patterns.
    let mats = [
        Material::Diffuse(0.25),
        Material::Mirror,
        Material::Glass {
            ior: 1.5,
            tint: (1.0, 1.0, 1.0),
        },
        Material::Glass {
            ior: 1.2,
            tint: (0.3, 0.6, 0.9),
        },
        Material::Emitter(4.0, 2),
    ];
    for (i, m) in mats.iter().enumerate() {
        println!("mat {} {:?} albedo {}", i, m, albedo(m));
    }
    let mut mirrors = 0;
    for m in mats {
        if let Material::Mirror = m {
            mirrors += 1;
        }
        if matches!(m, Material::Glass { ior, .. } if ior < 1.3) {
            println!("low-ior glass");
        }
    }
    println!("mirrors {} eq {} ne {}", mirrors, mats[0] == Material::Diffuse(0.25), mats[1] != mats[4]);
    // C-like enums: discriminants and casts.
    println!("axis {} {} {} {:?}", Axis::X as u8, Axis::Y as i32, Axis::Z as u32, Axis::Z);
    println!("sign {} {} {} {:?}", Sign::Neg as i32, Sign::Zero as i32, Sign::Pos as i8, sign_of(-2.0));
    for v in [-1.5f32, 0.0, 3.0] {
        let s = match sign_of(v) {
            Sign::Neg => "-",
            Sign::Zero => "0",
            Sign::Pos => "+",
        };
        println!("sign_of({}) = {}", v, s);
    }
    // Option and Result.
    let h = intersect(2.0, 7);
    let miss = intersect(-1.0, 8);
    println!("hit {:?} miss {:?} some {} none {}", h, miss, h.is_some(), miss.is_none());
    println!("unwrap_or {:?}", miss.unwrap_or(Hit { t: 9.0, id: 0 }));
    println!("first {:?}", first_hit(&[3.0, -1.0, 0.5, 2.0]));
    println!("first none {:?}", first_hit(&[-3.0]));
    println!("add {:?} {:?}", add_hits(h, h), add_hits(h, miss));
    println!("div {:?} {:?} twice {:?} {:?}", div(7, 2), div(1, 0), twice(9, 3), twice(1, 0));
    if let Ok(v) = div(10, 3) {
        println!("ok {}", v);
    }
    let r: Result<u8, u8> = Err(3);
    println!("result {} {} {:?} {:?}", r.is_ok(), r.is_err(), r.ok(), r.err());
    let mut opt = Some(3);
    let taken = opt.take();
    println!("take {:?} {:?}", taken, opt);
    // while let.
    let mut stack = [0u32; 8];
    let mut len = 0;
    for v in [5u32, 6, 7] {
        stack[len] = v;
        len += 1;
    }
    let mut n_pop = len;
    while let Some(top) = if n_pop > 0 {
        n_pop -= 1;
        Some(stack[n_pop])
    } else {
        None
    } {
        println!("pop {}", top);
    }
    // let-else.
    let Some(hh) = h else {
        panic!("no hit");
    };
    println!("let-else {}", hh.id);
    // Classifying with ranges, | and guards.
    for v in [-5, 0, 2, 8, 9] {
        println!("{} is {}", v, classify(v));
    }
    // @ bindings and char ranges.
    for ch in ['a', 'Q', '7', '#'] {
        let kind = match ch {
            c @ 'a'..='z' => (c, "lower"),
            c @ 'A'..='Z' => (c, "upper"),
            c @ '0'..='9' => (c, "digit"),
            c => (c, "other"),
        };
        println!("{:?}", kind);
    }
    // Struct patterns and arrays.
    let hit = Hit { t: 1.5, id: 3 };
    let Hit { t, id: which } = hit;
    match hit {
        Hit { id: 0, .. } => println!("id zero"),
        Hit { t: tt, id } if tt > 1.0 => println!("far {} {}", tt, id),
        _ => println!("near"),
    }
    let arr = [1, 2, 3, 4, 5];
    let [first, second, rest @ ..] = arr;
    println!("arr {} {} {:?} {} {}", first, second, rest, t, which);
    match arr {
        [1, .., last] => println!("ends with {}", last),
        _ => println!("other"),
    }
}
