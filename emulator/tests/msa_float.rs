//! MSA floating-point semantics checked against a reference model written here with the
//! host's IEEE arithmetic: single-precision lanes are computed in f64 with error-free
//! transformations (TwoSum, fused multiply-add residuals) to round correctly in all four
//! MSACSR rounding modes; double-precision lanes use host f64 (round to nearest).
//! Random inputs are biased towards NaNs (quiet and signaling), ±0, ±inf, subnormals,
//! and integer-conversion boundaries. Results and MSACSR Cause/Flags are compared.

mod msa_common;

use msa_common::*;
use trax_emulator::msa::{MsaFault, MsaOutcome};
use trax_emulator::RegFile;

const I: u32 = 1;
const U: u32 = 2;
const O: u32 = 4;
const Z: u32 = 8;
const V: u32 = 16;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Near,
    Zero,
    Up,
    Down,
}

const MODES: [Mode; 4] = [Mode::Near, Mode::Zero, Mode::Up, Mode::Down];

/// Per-lane reference context: rounding mode, flush-to-zero, raised flags.
struct Ctx {
    mode: Mode,
    ftz: bool,
    flags: u32,
}

fn is_nan32(x: u32) -> bool {
    x & 0x7F80_0000 == 0x7F80_0000 && x & 0x7F_FFFF != 0
}
fn is_snan32(x: u32) -> bool {
    is_nan32(x) && x & 0x40_0000 == 0
}
fn is_nan64(x: u64) -> bool {
    x & 0x7FF0_0000_0000_0000 == 0x7FF0_0000_0000_0000 && x & 0xF_FFFF_FFFF_FFFF != 0
}
fn is_snan64(x: u64) -> bool {
    is_nan64(x) && x & 0x8_0000_0000_0000 == 0
}

/// NaN operand rule: first signaling NaN (quieted, raises Invalid), else first quiet NaN.
/// Subnormal operands are still flushed (raising Inexact) when FS is set.
fn nan32(c: &mut Ctx, ops: &[u32]) -> Option<u32> {
    let r = if let Some(&x) = ops.iter().find(|&&x| is_snan32(x)) {
        c.flags |= V;
        x | 0x40_0000
    } else {
        *ops.iter().find(|&&x| is_nan32(x))?
    };
    for &x in ops {
        flush32(c, x);
    }
    Some(r)
}
fn nan64(c: &mut Ctx, ops: &[u64]) -> Option<u64> {
    let r = if let Some(&x) = ops.iter().find(|&&x| is_snan64(x)) {
        c.flags |= V;
        x | 0x8_0000_0000_0000
    } else {
        *ops.iter().find(|&&x| is_nan64(x))?
    };
    for &x in ops {
        flush64(c, x);
    }
    Some(r)
}

const DNAN32: u32 = 0x7FC0_0000;
const DNAN64: u64 = 0x7FF8_0000_0000_0000;

/// Flush-to-zero of an input: a subnormal reads as a signed zero and raises Inexact.
fn flush32(c: &mut Ctx, x: u32) -> f32 {
    if c.ftz && x & 0x7F80_0000 == 0 {
        if x & 0x7F_FFFF != 0 {
            c.flags |= I;
        }
        f32::from_bits(x & 0x8000_0000)
    } else {
        f32::from_bits(x)
    }
}
fn flush64(c: &mut Ctx, x: u64) -> f64 {
    if c.ftz && x & 0x7FF0_0000_0000_0000 == 0 {
        if x & 0xF_FFFF_FFFF_FFFF != 0 {
            c.flags |= I;
        }
        f64::from_bits(x & 0x8000_0000_0000_0000)
    } else {
        f64::from_bits(x)
    }
}

fn sgn(x: f64) -> i32 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// The two f32 neighbours (lo <= X <= hi) of the exact value X = h + (tiny of sign r).
fn bracket(h: f64, r: i32) -> (f32, f32, bool) {
    let f0 = h as f32;
    let f0d = f0 as f64;
    if f0d == h {
        match r {
            0 => (f0, f0, true),
            1 => (f0, f0.next_up(), false),
            _ => (f0.next_down(), f0, false),
        }
    } else if f0d < h {
        (f0, f0.next_up(), false)
    } else {
        (f0.next_down(), f0, false)
    }
}

/// Rounds X = h + r·tiny to f32 in mode `m`, ignoring the exponent range limits above
/// (X must be well inside f64's range).
fn round32_raw(h: f64, r: i32, m: Mode) -> (f32, bool) {
    let (lo, hi, exact) = bracket(h, r);
    if exact {
        return (lo, false);
    }
    let pick_hi = match m {
        Mode::Up => true,
        Mode::Down => false,
        Mode::Zero => h < 0.0,
        Mode::Near => {
            let mid = (lo as f64 + hi as f64) / 2.0;
            if h != mid {
                (h - lo as f64).abs() > (hi as f64 - h).abs()
            } else if r != 0 {
                r > 0
            } else {
                hi.to_bits() & 1 == 0
            }
        }
    };
    (if pick_hi { hi } else { lo }, true)
}

/// Full f32 rounding with overflow, tininess-after-rounding underflow and flush-to-zero.
fn round32(c: &mut Ctx, h: f64, r: i32) -> u32 {
    if h == 0.0 && r == 0 {
        return (h as f32).to_bits();
    }
    let neg = h < 0.0 || (h == 0.0 && r < 0);
    // Overflow: rounding X/2 (no overflow possible) reaches 2^127.
    let (half, _) = round32_raw(h / 2.0, r, c.mode);
    if half.abs() >= 2f32.powi(127) {
        c.flags |= O | I;
        let to_inf = match c.mode {
            Mode::Near => true,
            Mode::Zero => false,
            Mode::Up => !neg,
            Mode::Down => neg,
        };
        let v = if to_inf { f32::INFINITY } else { f32::MAX };
        return if neg { (-v).to_bits() } else { v.to_bits() };
    }
    let (v, inexact) = round32_raw(h, r, c.mode);
    // Tiny: the result rounded to 24 bits with unbounded exponent is below 2^-126.
    let (scaled, _) = round32_raw(h * 2f64.powi(100), r, c.mode);
    let tiny = (scaled.abs() as f64) < 2f64.powi(-126 + 100);
    if inexact {
        c.flags |= I;
        if tiny {
            c.flags |= U;
        }
    }
    if c.ftz && v != 0.0 && v.abs() < f32::MIN_POSITIVE {
        c.flags |= U | I;
        return v.to_bits() & 0x8000_0000;
    }
    v.to_bits()
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn zero_sum_sign(c: &Ctx, a: f64, b: f64) -> f32 {
    if a == 0.0 && b == 0.0 && a.is_sign_negative() == b.is_sign_negative() {
        a as f32
    } else if c.mode == Mode::Down {
        -0.0
    } else {
        0.0
    }
}

/// f32 binary arithmetic: op 0 add, 1 sub, 2 mul, 3 div.
fn ref_arith32(c: &mut Ctx, op: u32, xa: u32, xb: u32) -> u32 {
    if let Some(n) = nan32(c, &[xa, xb]) {
        return n;
    }
    let a = flush32(c, xa) as f64;
    let mut b = flush32(c, xb) as f64;
    if op == 1 {
        b = -b;
    }
    match op {
        0 | 1 => {
            if a.is_infinite() && b.is_infinite() && a != b {
                c.flags |= V;
                return DNAN32;
            }
            if a.is_infinite() || b.is_infinite() {
                return ((a + b) as f32).to_bits();
            }
            let (s, e) = two_sum(a, b);
            if s == 0.0 && e == 0.0 {
                return zero_sum_sign(c, a, b).to_bits();
            }
            round32(c, s, sgn(e))
        }
        2 => {
            if (a.is_infinite() && b == 0.0) || (a == 0.0 && b.is_infinite()) {
                c.flags |= V;
                return DNAN32;
            }
            let p = a * b;
            if p.is_infinite() || p == 0.0 {
                return (p as f32).to_bits();
            }
            round32(c, p, 0)
        }
        _ => {
            if (a == 0.0 && b == 0.0) || (a.is_infinite() && b.is_infinite()) {
                c.flags |= V;
                return DNAN32;
            }
            if b == 0.0 && a.is_finite() {
                // Divide-by-zero only for a finite dividend (inf / 0 is an exact inf).
                c.flags |= Z;
                return ((a / b) as f32).to_bits();
            }
            if a.is_infinite() || b.is_infinite() || a == 0.0 {
                return ((a / b) as f32).to_bits();
            }
            let q = a / b;
            let rem = (-q).mul_add(b, a);
            round32(c, q, sgn(rem) * sgn(b))
        }
    }
}

fn ref_sqrt32(c: &mut Ctx, xa: u32) -> u32 {
    if let Some(n) = nan32(c, &[xa]) {
        return n;
    }
    let a = flush32(c, xa) as f64;
    if a == 0.0 || a == f64::INFINITY {
        return (a as f32).to_bits();
    }
    if a < 0.0 {
        c.flags |= V;
        return DNAN32;
    }
    let r = a.sqrt();
    round32(c, r, sgn((-r).mul_add(r, a)))
}

/// wd + ws*wt (or wd - ws*wt), fused.
fn ref_fma32(c: &mut Ctx, xa: u32, xb: u32, xc: u32, negate: bool) -> u32 {
    let a = flush32(c, xa) as f64;
    let b = flush32(c, xb) as f64;
    let acc = flush32(c, xc) as f64;
    if (a.is_infinite() && b == 0.0) || (a == 0.0 && b.is_infinite()) {
        c.flags |= V; // even with a quiet NaN accumulator
    }
    // The accumulator's NaN takes precedence for fused multiply-add.
    if let Some(n) = nan32(c, &[xc, xa, xb]) {
        return n;
    }
    if (a.is_infinite() && b == 0.0) || (a == 0.0 && b.is_infinite()) {
        c.flags |= V;
        return DNAN32;
    }
    let p = if negate { -(a * b) } else { a * b };
    if p.is_infinite() && acc.is_infinite() && p != acc {
        c.flags |= V;
        return DNAN32;
    }
    if p.is_infinite() || acc.is_infinite() {
        return ((p + acc) as f32).to_bits();
    }
    let (s, e) = two_sum(p, acc);
    if s == 0.0 && e == 0.0 {
        return zero_sum_sign(c, p, acc).to_bits();
    }
    round32(c, s, sgn(e))
}

fn ref_minmax32(c: &mut Ctx, kind: u32, xa: u32, xb: u32) -> u32 {
    // kind: 12 fmin, 13 fmin_a, 14 fmax, 15 fmax_a
    if is_snan32(xa) || is_snan32(xb) {
        return nan32(c, &[xa, xb]).unwrap();
    }
    if is_nan32(xa) && is_nan32(xb) {
        return xa;
    }
    let a = flush32(c, xa);
    let b = flush32(c, xb);
    if is_nan32(xa) {
        return b.to_bits();
    }
    if is_nan32(xb) {
        return a.to_bits();
    }
    let max = |a: f32, b: f32| {
        if a > b || (a == b && !a.is_sign_negative()) {
            a
        } else {
            b
        }
    };
    let min = |a: f32, b: f32| {
        if a < b || (a == b && a.is_sign_negative()) {
            a
        } else {
            b
        }
    };
    let r = match kind {
        12 => min(a, b),
        14 => max(a, b),
        13 => {
            if a.abs() < b.abs() {
                a
            } else if b.abs() < a.abs() {
                b
            } else {
                min(a, b)
            }
        }
        _ => {
            if a.abs() > b.abs() {
                a
            } else if b.abs() > a.abs() {
                b
            } else {
                max(a, b)
            }
        }
    };
    r.to_bits()
}

/// Compare predicate by the 3RF op4 field of minors 0x1A (c | s<<3) and 0x1C.
fn ref_cmp32(c: &mut Ctx, minor: u32, op4: u32, xa: u32, xb: u32) -> bool {
    let signaling = op4 & 8 != 0;
    let un = is_nan32(xa) || is_nan32(xb);
    if (un && signaling) || is_snan32(xa) || is_snan32(xb) {
        c.flags |= V;
    }
    // Compares never raise Inexact, even when flushing inputs.
    let saved = c.flags;
    let a = flush32(c, xa);
    let b = flush32(c, xb);
    c.flags = (c.flags & !I) | (saved & I);
    let (lt, eq) = (!un && a < b, !un && a == b);
    match (minor, op4 & 7) {
        (0x1A, 0) => false,
        (0x1A, 1) => un,
        (0x1A, 2) => eq,
        (0x1A, 3) => un || eq,
        (0x1A, 4) => lt,
        (0x1A, 5) => un || lt,
        (0x1A, 6) => lt || eq,
        (0x1A, 7) => un || lt || eq,
        (_, 1) => !un,
        (_, 2) => !eq,
        _ => !un && !eq,
    }
}

fn round_int(x: f64, m: Mode) -> f64 {
    match m {
        Mode::Near => x.round_ties_even(),
        Mode::Zero => x.trunc(),
        Mode::Up => x.ceil(),
        Mode::Down => x.floor(),
    }
}

/// Float-to-integer: NaN -> 0, saturation, both Invalid.
fn ref_to_int(c: &mut Ctx, x: f64, is_nan: bool, m: Mode, signed: bool, bits: u32) -> u64 {
    ref_to_int_sat(c, x, is_nan, m, signed, bits, V)
}

/// Float-to-integer with the given flags on saturation (Invalid for ftint, Overflow and
/// Inexact for ftq); NaN always gives 0 and Invalid.
fn ref_to_int_sat(
    c: &mut Ctx,
    x: f64,
    is_nan: bool,
    m: Mode,
    signed: bool,
    bits: u32,
    sat: u32,
) -> u64 {
    let mask = if bits == 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    };
    if is_nan {
        c.flags |= V;
        return 0;
    }
    let (lo, hi) = if signed {
        (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
    } else {
        (0, (1i128 << bits) - 1)
    };
    let r = round_int(x, m);
    let ri = r as i128; // saturating cast
    if r.is_infinite() || ri < lo || ri > hi {
        c.flags |= sat;
        return (if r < 0.0 { lo } else { hi }) as u64 & mask;
    }
    if r != x {
        c.flags |= I;
    }
    ri as u64 & mask
}

/// Exact value of a binary16 bit pattern as f64 (NaNs excluded).
fn f16_value(h: u16) -> f64 {
    let s = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let e = (h >> 10) & 31;
    let f = (h & 0x3FF) as f64;
    match e {
        0 => s * f * 2f64.powi(-24),
        31 => s * f64::INFINITY,
        _ => s * (1024.0 + f) * 2f64.powi(e as i32 - 25),
    }
}

/// Rounds a finite f64 (exact value) to binary16 bits in mode `m` with flags.
fn round16(c: &mut Ctx, x: f64) -> u16 {
    let sign: u16 = if x.is_sign_negative() { 0x8000 } else { 0 };
    if x == 0.0 {
        return sign;
    }
    let ax = x.abs();
    let e = ax.log2().floor() as i32;
    let e = if 2f64.powi(e) > ax {
        e - 1
    } else if 2f64.powi(e + 1) <= ax {
        e + 1
    } else {
        e
    };
    let ulp_unb = 2f64.powi(e - 10);
    let ulp = 2f64.powi(e.max(-14) - 10);
    let mdir = |m: Mode| match (m, sign != 0) {
        (Mode::Up, true) => Mode::Down,
        (Mode::Down, true) => Mode::Up,
        (m, _) => m,
    };
    let q = ax / ulp;
    let r = round_int(q, mdir(c.mode)) * ulp;
    let r_unb = round_int(ax / ulp_unb, mdir(c.mode)) * ulp_unb;
    let inexact = r != ax;
    if r_unb >= 65536.0 {
        c.flags |= O | I;
        let to_inf = match c.mode {
            Mode::Near => true,
            Mode::Zero => false,
            Mode::Up => sign == 0,
            Mode::Down => sign != 0,
        };
        return sign | if to_inf { 0x7C00 } else { 0x7BFF };
    }
    if inexact {
        c.flags |= I;
        if r_unb < 2f64.powi(-14) {
            c.flags |= U;
        }
    }
    // Encode r.
    let bits = if r < 2f64.powi(-14) {
        (r / 2f64.powi(-24)) as u16
    } else {
        let e = r.log2().floor() as i32;
        let e = if 2f64.powi(e) > r { e - 1 } else { e };
        (((e + 15) as u16) << 10) | ((r / 2f64.powi(e - 10)) as u16 - 1024)
    };
    if c.ftz && bits != 0 && bits < 0x400 {
        c.flags |= U | I;
        return sign;
    }
    sign | bits
}

fn f64_bits_ulp_safe(x: f64) -> bool {
    x == 0.0 || x.abs() >= 2f64.powi(-1022 + 60) || x.is_nan() || x.is_infinite()
}

struct Case {
    word: u32,
    ws: u128,
    wt: u128,
    wd: u128,
    csr: u32,
}

/// Runs one case; returns (w3, MSACSR).
fn exec(case: &Case) -> (u128, u32) {
    let mut regs = RegFile::default();
    regs.fpr[1] = case.ws;
    regs.fpr[2] = case.wt;
    regs.fpr[3] = case.wd;
    regs.msacsr = case.csr;
    let out = run(case.word, &mut regs, &mut FlatMem(vec![]));
    assert_eq!(out, MsaOutcome::Done, "{}", mnemonic(case.word));
    (regs.fpr[3], regs.msacsr)
}

fn mode_csr(m: Mode, ftz: bool) -> u32 {
    (match m {
        Mode::Near => 0,
        Mode::Zero => 1,
        Mode::Up => 2,
        Mode::Down => 3,
    }) | if ftz { 1 << 24 } else { 0 }
}

/// Checks a whole instruction: `lane_ref(ctx, i, ws, wt, wd)` gives the expected result
/// vector lane `i` (of `out_bits` bits) and accumulates flags.
fn check(case: &Case, out_bits: u32, lane_ref: &dyn Fn(&mut Ctx, u32) -> u64, flag_mask: u32) {
    let mode = MODES[(case.csr & 3) as usize];
    let mut c = Ctx {
        mode,
        ftz: case.csr & (1 << 24) != 0,
        flags: 0,
    };
    let want: Vec<u64> = (0..128 / out_bits).map(|i| lane_ref(&mut c, i)).collect();
    let (got, csr) = exec(case);
    let got_l: Vec<u64> = (0..128 / out_bits).map(|i| get(got, out_bits, i)).collect();
    let ctx = || {
        format!(
            "{} mode {:?} ftz {}: ws={:#034x} wt={:#034x} wd={:#034x}",
            mnemonic(case.word),
            mode,
            c.ftz,
            case.ws,
            case.wt,
            case.wd
        )
    };
    assert_eq!(
        got_l.iter().map(|x| format!("{x:#x}")).collect::<Vec<_>>(),
        want.iter().map(|x| format!("{x:#x}")).collect::<Vec<_>>(),
        "{}",
        ctx()
    );
    let cause = (csr >> 12) & 0x3F;
    assert_eq!(
        cause & flag_mask,
        c.flags & flag_mask,
        "cause flags of {}",
        ctx()
    );
    assert_eq!(
        (csr >> 2) & 0x1F & flag_mask,
        c.flags & flag_mask,
        "sticky flags of {}",
        ctx()
    );
}

fn vec32(rng: &mut Rng) -> u128 {
    from_lanes(32, &[0, 1, 2, 3].map(|_| rng.f32_bits() as u64))
}
fn vec64(rng: &mut Rng) -> u128 {
    from_lanes(64, &[rng.f64_bits(), rng.f64_bits()])
}

const N: usize = 1500;

fn random_csr(rng: &mut Rng) -> u32 {
    mode_csr(MODES[rng.below(4) as usize], rng.below(4) == 0)
}

#[test]
fn single_arith_all_modes() {
    let mut rng = Rng(21);
    for op4 in [0u32, 1, 2, 3, 4, 5, 12, 13, 14, 15] {
        let word = enc_3rf(0x1B, op4, 0, 2, 1, 3);
        for _ in 0..N {
            let case = Case {
                word,
                ws: vec32(&mut rng),
                wt: vec32(&mut rng),
                wd: vec32(&mut rng),
                csr: random_csr(&mut rng),
            };
            let l = |v: u128, i| get(v, 32, i) as u32;
            check(
                &case,
                32,
                &|c, i| {
                    let (a, b, d) = (l(case.ws, i), l(case.wt, i), l(case.wd, i));
                    (match op4 {
                        0..=3 => ref_arith32(c, op4, a, b),
                        4 => ref_fma32(c, a, b, d, false),
                        5 => ref_fma32(c, a, b, d, true),
                        _ => ref_minmax32(c, op4, a, b),
                    }) as u64
                },
                0x1F,
            );
        }
    }
}

#[test]
fn single_unary_all_modes() {
    let mut rng = Rng(22);
    // 2RF op9 values: 0x190 + k.
    for k in [0u32, 1, 2, 3, 4, 5, 6, 7, 12, 13, 14, 15] {
        let word = enc_2rf(0x190 + k, 0, 1, 3);
        for _ in 0..N {
            let mut ws = vec32(&mut rng);
            if k >= 14 {
                ws = rng.int_vec(32);
            }
            let case = Case {
                word,
                ws,
                wt: 0,
                wd: 0,
                csr: random_csr(&mut rng),
            };
            check(
                &case,
                32,
                &|c, i| {
                    let x = get(case.ws, 32, i) as u32;
                    // fclass and the integer sources of ffint never flush.
                    let xf = if k == 0 || k >= 14 {
                        0.0
                    } else {
                        flush32(c, x) as f64
                    };
                    let m = c.mode;
                    match k {
                        0 => {
                            let f = f32::from_bits(x);
                            let neg = x >> 31 == 1;
                            let bit = match f.classify() {
                                _ if is_snan32(x) => return 1,
                                std::num::FpCategory::Nan => return 2,
                                std::num::FpCategory::Infinite => 0,
                                std::num::FpCategory::Normal => 1,
                                std::num::FpCategory::Subnormal => 2,
                                std::num::FpCategory::Zero => 3,
                            };
                            1u64 << (bit + if neg { 2 } else { 6 })
                        }
                        1 => ref_to_int(c, xf, is_nan32(x), Mode::Zero, true, 32),
                        2 => ref_to_int(c, xf, is_nan32(x), Mode::Zero, false, 32),
                        3 => ref_sqrt32(c, x) as u64,
                        4 | 5 => {
                            // Approximate reciprocals: exactly Inexact unless invalid, divide
                            // by zero, an infinite operand or a NaN result.
                            let before = c.flags;
                            c.flags = 0;
                            let arg = if k == 4 { ref_sqrt32(c, x) } else { x };
                            let r = ref_arith32(c, 3, 0x3F80_0000, arg);
                            let arg_inf = arg & 0x7FFF_FFFF == 0x7F80_0000;
                            let r_qnan = is_nan32(r) && !is_snan32(r);
                            if !arg_inf && !r_qnan && c.flags & (V | Z) == 0 {
                                c.flags = I;
                            }
                            c.flags |= before;
                            r as u64
                        }
                        6 => {
                            if let Some(n) = nan32(c, &[x]) {
                                return n as u64;
                            }
                            let r = round_int(xf, m);
                            if r != xf {
                                c.flags |= I;
                            }
                            (r as f32).to_bits() as u64
                        }
                        7 => {
                            if let Some(n) = nan32(c, &[x]) {
                                return n as u64;
                            }
                            if xf == 0.0 {
                                c.flags |= Z;
                                return f32::NEG_INFINITY.to_bits() as u64;
                            }
                            if xf < 0.0 {
                                c.flags |= V;
                                return DNAN32 as u64;
                            }
                            if xf.is_infinite() {
                                return x as u64;
                            }
                            let e = if x & 0x7F80_0000 == 0 {
                                -149 + (31 - (x & 0x7F_FFFF).leading_zeros() as i32)
                            } else {
                                ((x >> 23) & 0xFF) as i32 - 127
                            };
                            (e as f32).to_bits() as u64
                        }
                        12 => ref_to_int(c, xf, is_nan32(x), m, true, 32),
                        13 => ref_to_int(c, xf, is_nan32(x), m, false, 32),
                        14 => round32(c, x as i32 as f64, 0) as u64,
                        _ => round32(c, x as f64, 0) as u64,
                    }
                },
                0x1F,
            );
        }
    }
}

#[test]
fn single_compares() {
    let mut rng = Rng(23);
    let ops: Vec<(u32, u32)> = (0..16)
        .map(|k| (0x1A, k))
        .chain([1, 2, 3, 9, 10, 11].iter().map(|&k| (0x1C, k)))
        .collect();
    for (minor, op4) in ops {
        let word = enc_3rf(minor, op4, 0, 2, 1, 3);
        for _ in 0..400 {
            let mut ws = vec32(&mut rng);
            let wt = vec32(&mut rng);
            if rng.below(3) == 0 {
                ws = wt; // equal operands
            }
            let case = Case {
                word,
                ws,
                wt,
                wd: 0,
                csr: random_csr(&mut rng),
            };
            check(
                &case,
                32,
                &|c, i| {
                    let t = ref_cmp32(
                        c,
                        minor,
                        op4,
                        get(case.ws, 32, i) as u32,
                        get(case.wt, 32, i) as u32,
                    );
                    if t {
                        0xFFFF_FFFF
                    } else {
                        0
                    }
                },
                0x1F,
            );
        }
    }
}

#[test]
fn format_conversions() {
    let mut rng = Rng(24);
    for _ in 0..N {
        let csr = random_csr(&mut rng);
        // fexdo.h: f32 -> f16, ws to the upper half.
        let (ws, wt) = (vec32(&mut rng), vec32(&mut rng));
        let case = Case {
            word: enc_3rf(0x1B, 8, 0, 2, 1, 3),
            ws,
            wt,
            wd: 0,
            csr,
        };
        check(
            &case,
            16,
            &|c, i| {
                let x = if i < 4 {
                    get(wt, 32, i)
                } else {
                    get(ws, 32, i - 4)
                } as u32;
                if is_nan32(x) {
                    if is_snan32(x) {
                        c.flags |= V;
                    }
                    return ((x >> 16) & 0x8000 | 0x7E00 | ((x >> 13) & 0x3FF)) as u64;
                }
                let f = flush32(c, x);
                if f.is_infinite() {
                    return if f < 0.0 { 0xFC00 } else { 0x7C00 };
                }
                round16(c, f as f64) as u64
            },
            0x1F,
        );
        // fexdo.w: f64 -> f32.
        let (ws, wt) = (vec64(&mut rng), vec64(&mut rng));
        let case = Case {
            word: enc_3rf(0x1B, 8, 1, 2, 1, 3),
            ws,
            wt,
            wd: 0,
            csr,
        };
        check(
            &case,
            32,
            &|c, i| {
                let x = if i < 2 {
                    get(wt, 64, i)
                } else {
                    get(ws, 64, i - 2)
                };
                if is_nan64(x) {
                    if is_snan64(x) {
                        c.flags |= V;
                    }
                    return (((x >> 32) as u32 & 0x8000_0000)
                        | 0x7FC0_0000
                        | ((x >> 29) as u32 & 0x7F_FFFF)) as u64;
                }
                let f = flush64(c, x);
                if f.is_infinite() || f == 0.0 {
                    return (f as f32).to_bits() as u64;
                }
                // Values beyond f32 range by far: scale keeps round32 valid.
                round32(c, f.clamp(-1e300, 1e300), 0) as u64
            },
            0x1F,
        );
        // fexupl.w / fexupr.w: f16 -> f32 (exact).
        let ws = rng.int_vec(16);
        for (op, base) in [(0x198u32, 4u32), (0x199, 0)] {
            let case = Case {
                word: enc_2rf(op, 0, 1, 3),
                ws,
                wt: 0,
                wd: 0,
                csr,
            };
            check(
                &case,
                32,
                &|c, i| {
                    let h = get(ws, 16, base + i) as u16;
                    let sign = ((h as u32) & 0x8000) << 16;
                    if h & 0x7C00 == 0x7C00 && h & 0x3FF != 0 {
                        if h & 0x200 == 0 {
                            c.flags |= V;
                        }
                        return (sign | 0x7FC0_0000 | ((h as u32 & 0x3FF) << 13)) as u64;
                    }
                    if c.ftz && h & 0x7C00 == 0 {
                        if h & 0x3FF != 0 {
                            c.flags |= I;
                        }
                        return sign as u64;
                    }
                    (f16_value(h) as f32).to_bits() as u64
                },
                0x1F,
            );
        }
        // fexupl.d / fexupr.d: f32 -> f64 (exact).
        let ws = vec32(&mut rng);
        for (op, base) in [(0x198u32, 2u32), (0x199, 0)] {
            let case = Case {
                word: enc_2rf(op, 1, 1, 3),
                ws,
                wt: 0,
                wd: 0,
                csr,
            };
            check(
                &case,
                64,
                &|c, i| {
                    let x = get(ws, 32, base + i) as u32;
                    if is_nan32(x) {
                        if is_snan32(x) {
                            c.flags |= V;
                        }
                        return ((x as u64 & 0x8000_0000) << 32)
                            | DNAN64
                            | ((x as u64 & 0x7F_FFFF) << 29);
                    }
                    (flush32(c, x) as f64).to_bits()
                },
                0x1F,
            );
        }
        // ffql/ffqr .w (Q15) and .d (Q31).
        let ws = rng.int_vec(16);
        for (op, base) in [(0x19Au32, 4u32), (0x19B, 0)] {
            let case = Case {
                word: enc_2rf(op, 0, 1, 3),
                ws,
                wt: 0,
                wd: 0,
                csr,
            };
            check(
                &case,
                32,
                &|_, i| ((get(ws, 16, base + i) as i16 as f32) / 32768.0).to_bits() as u64,
                0x1F,
            );
        }
        let ws = rng.int_vec(32);
        for (op, base) in [(0x19Au32, 2u32), (0x19B, 0)] {
            let case = Case {
                word: enc_2rf(op, 1, 1, 3),
                ws,
                wt: 0,
                wd: 0,
                csr,
            };
            check(
                &case,
                64,
                &|_, i| ((get(ws, 32, base + i) as i32 as f64) / 2147483648.0).to_bits(),
                0x1F,
            );
        }
        // ftq.h: f32 -> Q15.
        let (ws, wt) = (vec32(&mut rng), vec32(&mut rng));
        let case = Case {
            word: enc_3rf(0x1B, 10, 0, 2, 1, 3),
            ws,
            wt,
            wd: 0,
            csr,
        };
        check(
            &case,
            16,
            &|c, i| {
                let x = if i < 4 {
                    get(wt, 32, i)
                } else {
                    get(ws, 32, i - 4)
                } as u32;
                let m = c.mode;
                let v = flush32(c, x) as f64 * 32768.0;
                ref_to_int_sat(c, v, is_nan32(x), m, true, 16, O | I)
            },
            0x1F,
        );
        // fexp2.w: ws * 2^wt.
        let ws = vec32(&mut rng);
        let wt = from_lanes(
            32,
            &[0, 1, 2, 3].map(|_| match rng.below(3) {
                0 => rng.u64() & 0xFFFF_FFFF,
                _ => (rng.below(300) as i64 - 150) as u64,
            }),
        );
        let case = Case {
            word: enc_3rf(0x1B, 7, 0, 2, 1, 3),
            ws,
            wt,
            wd: 0,
            csr,
        };
        check(
            &case,
            32,
            &|c, i| {
                let x = get(ws, 32, i) as u32;
                if let Some(n) = nan32(c, &[x]) {
                    return n as u64;
                }
                let n = (get(wt, 32, i) as i32).clamp(-400, 400);
                let v = flush32(c, x) as f64 * 2f64.powi(n);
                if v == 0.0 || v.is_infinite() {
                    return (v as f32).to_bits() as u64;
                }
                round32(c, v, 0) as u64
            },
            0x1F,
        );
    }
}

/// Double-precision lanes, round to nearest, against host f64 arithmetic. Flags are
/// compared except Inexact/Underflow on subnormal results (where the residual trick
/// used here is not exact) and Inexact/Underflow on fmadd/fmsub (no exact residual
/// available; single-precision fmadd/fmsub flags are fully checked above).
#[test]
fn double_ops_nearest() {
    let mut rng = Rng(25);
    for _ in 0..N {
        let ftz = rng.below(4) == 0;
        let csr = mode_csr(Mode::Near, ftz);
        let (ws, wt, wd) = (vec64(&mut rng), vec64(&mut rng), vec64(&mut rng));
        for op4 in [0u32, 1, 2, 3, 4, 5, 12, 13, 14, 15] {
            let word = enc_3rf(0x1B, op4, 1, 2, 1, 3);
            let case = Case {
                word,
                ws,
                wt,
                wd,
                csr,
            };
            // Decide the flag mask from the lane results first.
            let mut c = Ctx {
                mode: Mode::Near,
                ftz,
                flags: 0,
            };
            let lane = |c: &mut Ctx, i: u32| -> (u64, bool) {
                let (xa, xb, xd) = (get(ws, 64, i), get(wt, 64, i), get(wd, 64, i));
                let ops: &[u64] = if op4 == 4 || op4 == 5 {
                    &[xd, xa, xb]
                } else {
                    &[xa, xb]
                };
                if op4 < 12 {
                    if op4 == 4 || op4 == 5 {
                        let (fa, fb) = (flush64(c, xa), flush64(c, xb));
                        if (fa.is_infinite() && fb == 0.0) || (fa == 0.0 && fb.is_infinite()) {
                            c.flags |= V; // even with a quiet NaN accumulator
                        }
                    }
                    if let Some(n) = nan64(c, ops) {
                        return (n, true);
                    }
                }
                let (a, b) = (flush64(c, xa), flush64(c, xb));
                let d = if op4 == 4 || op4 == 5 {
                    flush64(c, xd)
                } else {
                    0.0
                };
                let (r, resid) = match op4 {
                    0 | 1 => {
                        let b = if op4 == 1 { -b } else { b };
                        let (s, e) = two_sum(a, b);
                        let s = if s == 0.0 && !(a == 0.0 && b == 0.0) {
                            0.0
                        } else {
                            s
                        };
                        (s, if s.is_finite() { e } else { 0.0 })
                    }
                    2 => {
                        let p = a * b;
                        (p, if p.is_finite() { a.mul_add(b, -p) } else { 0.0 })
                    }
                    3 => {
                        let q = a / b;
                        // Residual of the quotient on operands scaled into [1, 2^64) so the
                        // fused residual cannot underflow (scaled quotient is exact).
                        let norm = |mut x: f64| {
                            while x != 0.0 && x.abs() < 1.0 {
                                x *= 2f64.powi(64);
                            }
                            while x.is_finite() && x.abs() >= 2f64.powi(64) {
                                x *= 2f64.powi(-64);
                            }
                            x
                        };
                        let (an, bn) = (norm(a), norm(b));
                        let qn = an / bn;
                        (
                            q,
                            if q.is_finite() && q != 0.0 {
                                (-qn).mul_add(bn, an)
                            } else {
                                0.0
                            },
                        )
                    }
                    4 => (a.mul_add(b, d), 0.0),
                    5 => ((-a).mul_add(b, d), 0.0),
                    12 => (
                        if a < b || (a == b && a.is_sign_negative()) || b.is_nan() {
                            a
                        } else {
                            b
                        },
                        0.0,
                    ),
                    14 => (
                        if a > b || (a == b && !a.is_sign_negative()) || b.is_nan() {
                            a
                        } else {
                            b
                        },
                        0.0,
                    ),
                    13 => {
                        let pick_a = if a.abs() == b.abs() {
                            a < b || (a == b && a.is_sign_negative())
                        } else {
                            a.abs() < b.abs() || b.is_nan()
                        };
                        (if pick_a { a } else { b }, 0.0)
                    }
                    _ => {
                        let pick_a = if a.abs() == b.abs() {
                            a > b || (a == b && !a.is_sign_negative())
                        } else {
                            a.abs() > b.abs() || b.is_nan()
                        };
                        (if pick_a { a } else { b }, 0.0)
                    }
                };
                if op4 >= 12 {
                    if is_snan64(xa) || is_snan64(xb) {
                        return (nan64(c, &[xa, xb]).unwrap(), true);
                    }
                    if is_nan64(xa) && is_nan64(xb) {
                        return (xa, true);
                    }
                    return (r.to_bits(), true);
                }
                if r.is_nan() {
                    c.flags |= V;
                    return (DNAN64, true);
                }
                let div_by_zero = op4 == 3 && b == 0.0 && a.is_finite();
                if div_by_zero {
                    c.flags |= Z;
                }
                let finite_in = a.is_finite() && b.is_finite() && (op4 < 4 || d.is_finite());
                if r.is_infinite() && finite_in && !div_by_zero {
                    c.flags |= O | I;
                }
                // A nonzero exact product/quotient that rounds to zero is inexact and tiny.
                if r == 0.0
                    && (op4 == 2 || op4 == 3)
                    && a != 0.0
                    && a.is_finite()
                    && b.is_finite()
                    && b != 0.0
                {
                    c.flags |= U | I;
                }
                if resid != 0.0 {
                    c.flags |= I;
                }
                if ftz && r != 0.0 && r.abs() < f64::MIN_POSITIVE {
                    c.flags |= U | I;
                    return (r.to_bits() & (1 << 63), false);
                }
                (r.to_bits(), f64_bits_ulp_safe(r))
            };
            let mut safe = true;
            let want: Vec<u64> = (0..2)
                .map(|i| {
                    let (v, s) = lane(&mut c, i);
                    safe &= s;
                    v
                })
                .collect();
            let mask = if !safe || op4 == 4 || op4 == 5 {
                V | Z | O
            } else {
                0x1F
            };
            let _ = &want;
            check(&case, 64, &|c2, i| lane(c2, i).0, mask);
        }
    }
}

#[test]
fn double_conversions_nearest() {
    let mut rng = Rng(26);
    for _ in 0..N {
        let ws = vec64(&mut rng);
        let csr = mode_csr(Mode::Near, false);
        // ftint_s.d / ftint_u.d / ftrunc_s.d / ftrunc_u.d
        for (k, m, signed) in [
            (12u32, Mode::Near, true),
            (13, Mode::Near, false),
            (1, Mode::Zero, true),
            (2, Mode::Zero, false),
        ] {
            let case = Case {
                word: enc_2rf(0x190 + k, 1, 1, 3),
                ws,
                wt: 0,
                wd: 0,
                csr,
            };
            check(
                &case,
                64,
                &|c, i| {
                    let x = get(ws, 64, i);
                    ref_to_int(c, f64::from_bits(x), is_nan64(x), m, signed, 64)
                },
                0x1F,
            );
        }
        // ffint_s.d / ffint_u.d: i64/u64 -> f64; Inexact via exact i128 comparison.
        let wi = rng.int_vec(64);
        for (k, signed) in [(14u32, true), (15, false)] {
            let case = Case {
                word: enc_2rf(0x190 + k, 1, 1, 3),
                ws: wi,
                wt: 0,
                wd: 0,
                csr,
            };
            check(
                &case,
                64,
                &|c, i| {
                    let x = get(wi, 64, i);
                    let (v, exact) = if signed {
                        let f = x as i64 as f64;
                        (f, f as i128 == x as i64 as i128)
                    } else {
                        let f = x as f64;
                        (f, f as i128 == x as i128)
                    };
                    if !exact {
                        c.flags |= I;
                    }
                    v.to_bits()
                },
                0x1F,
            );
        }
        // fsqrt.d, frint.d, fclass.d
        let case = Case {
            word: enc_2rf(0x193, 1, 1, 3),
            ws,
            wt: 0,
            wd: 0,
            csr,
        };
        check(
            &case,
            64,
            &|c, i| {
                let x = get(ws, 64, i);
                if let Some(n) = nan64(c, &[x]) {
                    return n;
                }
                let f = f64::from_bits(x);
                if f < 0.0 {
                    c.flags |= V;
                    return DNAN64;
                }
                let r = f.sqrt();
                // Residual on a copy scaled by 2^200 (exact), so it cannot underflow.
                let (fs, rs) = (f * 2f64.powi(200), r * 2f64.powi(100));
                if r.is_finite() && r != 0.0 && (-rs).mul_add(rs, fs) != 0.0 {
                    c.flags |= I;
                }
                r.to_bits()
            },
            0x1F,
        );
        let case = Case {
            word: enc_2rf(0x196, 1, 1, 3),
            ws,
            wt: 0,
            wd: 0,
            csr,
        };
        check(
            &case,
            64,
            &|c, i| {
                let x = get(ws, 64, i);
                if let Some(n) = nan64(c, &[x]) {
                    return n;
                }
                let f = f64::from_bits(x);
                let r = f.round_ties_even();
                if r != f {
                    c.flags |= I;
                }
                r.to_bits()
            },
            0x1F,
        );
        let case = Case {
            word: enc_2rf(0x190, 1, 1, 3),
            ws,
            wt: 0,
            wd: 0,
            csr,
        };
        check(
            &case,
            64,
            &|_, i| {
                let x = get(ws, 64, i);
                let f = f64::from_bits(x);
                let neg = x >> 63 == 1;
                let bit = match f.classify() {
                    _ if is_snan64(x) => return 1,
                    std::num::FpCategory::Nan => return 2,
                    std::num::FpCategory::Infinite => 0,
                    std::num::FpCategory::Normal => 1,
                    std::num::FpCategory::Subnormal => 2,
                    std::num::FpCategory::Zero => 3,
                };
                1u64 << (bit + if neg { 2 } else { 6 })
            },
            0x1F,
        );
    }
}

#[test]
fn enabled_exceptions_trap_unless_nx() {
    // fdiv.w with 1/0 in lane 0; Z enabled (Enables bit 3 -> MSACSR bit 10).
    let word = enc_3rf(0x1B, 3, 0, 2, 1, 3);
    let ws = from_lanes(32, &[0x3F80_0000, 0x3F80_0000, 0x3F80_0000, 0x3F80_0000]);
    let wt = from_lanes(32, &[0, 0x3F80_0000, 0x3F80_0000, 0x3F80_0000]);
    let mut regs = RegFile::default();
    regs.fpr[1] = ws;
    regs.fpr[2] = wt;
    regs.fpr[3] = 0x55;
    regs.msacsr = 1 << 10;
    let out = run(word, &mut regs, &mut FlatMem(vec![]));
    assert_eq!(out, MsaOutcome::Fault(MsaFault::FpException { cause: Z }));
    assert_eq!(regs.fpr[3], 0x55, "destination not written on a trap");
    assert_eq!((regs.msacsr >> 12) & 0x3F, Z, "cause recorded");
    assert_eq!((regs.msacsr >> 2) & 0x1F, 0, "flags not updated on a trap");
    // With NX set the faulting lane becomes a signaling NaN carrying its cause, its
    // exception is not recorded, and the other lanes complete normally.
    regs.msacsr = (1 << 10) | (1 << 18);
    assert_eq!(run(word, &mut regs, &mut FlatMem(vec![])), MsaOutcome::Done);
    assert_eq!(get(regs.fpr[3], 32, 0), 0x7F80_0000 | Z as u64);
    assert_eq!(get(regs.fpr[3], 32, 1), 0x3F80_0000);
    assert_eq!((regs.msacsr >> 2) & 0x1F, 0);
    assert_eq!((regs.msacsr >> 12) & 0x3F, 0);
}

#[test]
fn hand_computed_float_vectors() {
    let f = |x: f32| x.to_bits() as u64;
    let ws = from_lanes(32, &[f(1.5), f(-2.0), f(1e30), f(0.1)]);
    let wt = from_lanes(32, &[f(2.25), f(0.5), f(1e30), f(0.2)]);
    let (sum, csr) = exec(&Case {
        word: enc_3rf(0x1B, 0, 0, 2, 1, 3),
        ws,
        wt,
        wd: 0,
        csr: 0,
    });
    assert_eq!(
        sum,
        from_lanes(32, &[f(3.75), f(-1.5), f(2e30), f(0.1 + 0.2)])
    );
    assert_eq!((csr >> 2) & 0x1F, I, "0.1 + 0.2 is inexact");
    let (prod, csr) = exec(&Case {
        word: enc_3rf(0x1B, 2, 0, 2, 1, 3),
        ws,
        wt,
        wd: 0,
        csr: 0,
    });
    assert_eq!(get(prod, 32, 2), 0x7F80_0000, "1e60 overflows to +inf");
    assert_eq!((csr >> 2) & 0x1F, O | I);
    // Round toward zero: overflow gives MAX instead.
    let (prod, _) = exec(&Case {
        word: enc_3rf(0x1B, 2, 0, 2, 1, 3),
        ws,
        wt,
        wd: 0,
        csr: 1,
    });
    assert_eq!(get(prod, 32, 2), f(f32::MAX));
    // ftint_s.w: 2.5 -> 2 (nearest even), -2.5 -> -2, NaN -> 0, 3e9 saturates.
    let ws = from_lanes(32, &[f(2.5), f(-2.5), 0x7FC0_0000, f(3e9)]);
    let (r, csr) = exec(&Case {
        word: enc_2rf(0x19C, 0, 1, 3),
        ws,
        wt: 0,
        wd: 0,
        csr: 0,
    });
    assert_eq!(
        r,
        from_lanes(32, &[2, (-2i32) as u32 as u64, 0, 0x7FFF_FFFF])
    );
    assert_eq!((csr >> 2) & 0x1F, I | V);
    // fmax.w with a quiet NaN returns the number; fmin.w(-0, +0) = -0.
    let ws = from_lanes(32, &[0x7FC0_0000, f(-0.0), 0, 0]);
    let wt = from_lanes(32, &[f(3.0), f(0.0), 0, 0]);
    let (r, _) = exec(&Case {
        word: enc_3rf(0x1B, 14, 0, 2, 1, 3),
        ws,
        wt,
        wd: 0,
        csr: 0,
    });
    assert_eq!(get(r, 32, 0), f(3.0));
    let (r, _) = exec(&Case {
        word: enc_3rf(0x1B, 12, 0, 2, 1, 3),
        ws,
        wt,
        wd: 0,
        csr: 0,
    });
    assert_eq!(get(r, 32, 1), f(-0.0));
    // fclass.w of +1.0 is "positive normal" (bit 7).
    let (r, _) = exec(&Case {
        word: enc_2rf(0x190, 0, 1, 3),
        ws: f(1.0) as u128,
        wt: 0,
        wd: 0,
        csr: 0,
    });
    assert_eq!(get(r, 32, 0), 1 << 7);
    // Flush-to-zero: smallest subnormal + 0 = +0 with FS set.
    let (r, _) = exec(&Case {
        word: enc_3rf(0x1B, 0, 0, 2, 1, 3),
        ws: 1,
        wt: 0,
        wd: 0,
        csr: 1 << 24,
    });
    assert_eq!(get(r, 32, 0), 0);
    // fexdo.h of 1.0 is 0x3C00; 65520 rounds to +inf in binary16.
    let ws = from_lanes(32, &[f(1.0), f(65520.0), 0, 0]);
    let (r, _) = exec(&Case {
        word: enc_3rf(0x1B, 8, 0, 2, 1, 3),
        ws,
        wt: 0,
        wd: 0,
        csr: 0,
    });
    assert_eq!((get(r, 16, 4), get(r, 16, 5)), (0x3C00, 0x7C00));
}
