//! Every scalar base type as a parameter and a local, for the DWARF tests
//! (`compiler/tests/features.rs` with llvm-dwarfdump, `emulator/tests/gdb.rs` with gdb).
//! The values are chosen so a wrong encoding or size shows: an unsigned type described
//! as a character prints as one, and a `u64` above 2^32 loses its high word.

#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn take(
    a: u8,
    b: u16,
    c: u32,
    d: u64,
    e: usize,
    f: i8,
    g: i16,
    h: i32,
    i: i64,
    j: isize,
    k: f32,
    l: f64,
    m: bool,
    n: char,
) -> u64 {
    let sum = d + c as u64 + b as u64 + a as u64 + e as u64; // BODY
    let neg = i + h as i64 + g as i64 + f as i64 + j as i64;
    if m && n == 'Z' && k < 2.0 && l > 2.0 {
        sum + neg as u64
    } else {
        sum
    }
}

fn trax_main() {
    let v8: u8 = 200;
    let v16: u16 = 60000;
    let v32: u32 = 123456;
    let v64: u64 = (1 << 40) + 5;
    let vus: usize = 77;
    let i8v: i8 = -100;
    let i16v: i16 = -30000;
    let i32v: i32 = -123456;
    let i64v: i64 = -(1 << 41);
    let isz: isize = -77;
    let f: f32 = 1.5;
    let d: f64 = 2.25;
    let t: bool = true;
    let ch: char = 'Z';
    let r = take(v8, v16, v32, v64, vus, i8v, i16v, i32v, i64v, isz, f, d, t, ch); // CALL
    println!("{}", r);
}
