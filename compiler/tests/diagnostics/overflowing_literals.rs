fn a() -> u8 {
    let x: u8 = 300;
    x
}

fn b() -> i8 {
    -129
}

fn c() -> u8 {
    300 as u8
}

fn d() -> f32 {
    1e40
}

fn e() -> i32 {
    0x8000_0000
}

fn f() -> i8 {
    -(-128i8)
}

fn g(x: u8) -> u32 {
    // A pattern literal is checked against the scrutinee's type.
    match x {
        300 => 1,
        _ => 0,
    }
}

fn h(x: i8) -> u32 {
    match x {
        -128 => 1,
        0..=200 => 2,
        _ => 0,
    }
}

fn trax_main() {
    // In range: a negated literal may reach MIN; an odd number of minus signs negates it.
    let ok: i8 = -128;
    let ok2 = -(128i8);
    let ok3 = -0x80i8;
    let ok4: f32 = 3.4e38;
    let ok5: i32 = -(2147483648);
    println!("{} {} {} {} {} {}", ok, ok2, ok3, ok4, ok5, a());
    println!("{} {} {} {} {} {} {}", b(), c(), d(), e(), f(), g(44), h(3));
}
