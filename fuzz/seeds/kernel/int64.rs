//! 64-bit division and 64-bit integer/float conversions need runtime helpers on MIPS32;
//! the compiler supplies them (no compiler-rt on TRaX).

fn trax_main() {
    let g = trax::global_id();
    let a = g as u64 * 1_234_567_891;
    let b = (g as i64 + 3) * -77;
    println!("{} {}", a / (g as u64 + 1), a % 1000);
    println!("{} {}", b / (g as i64 + 2), b % (g as i64 + 2));
    println!("{} {}", a as f32, b as f64);
    let f = trax::rand();
    println!("{} {}", (f * 1e10) as u64, (f as f64 * -1e12) as i64);
}
