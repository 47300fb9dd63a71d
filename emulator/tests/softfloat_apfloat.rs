//! The soft-float core against an independent implementation: `rustc_apfloat`, the Rust
//! port of LLVM's APFloat (the arithmetic rustc uses for constant evaluation).
//!
//! Add, sub, mul, div and fused multiply-add in binary16/32/64, in all four rounding
//! modes, on operands biased to the underflow and overflow boundaries, plus round to
//! integral and conversion to i32: results and IEEE flags must agree, except where
//! APFloat is knowingly not what MIPS (and QEMU, the other oracle) does:
//! - NaN operands: APFloat returns the first NaN operand; MIPS NaN-2008 returns the first
//!   *signalling* NaN, quieted. Only "a NaN, and Invalid or not" is compared.
//! - Overflow in a directed rounding mode whose result is the largest finite number:
//!   APFloat raises Inexact alone, IEEE 754 (7.4) and QEMU Overflow and Inexact.
//! - A result that rounds up to the smallest normal number from below it: APFloat judges
//!   tininess on the result rounded to the format (not tiny), IEEE 754 "after rounding"
//!   on the value rounded with an unbounded exponent, which may stay below the smallest
//!   normal (tiny: Underflow and Inexact), as QEMU does (`tests/fpu_qemu.rs` pins such
//!   a `mul.s` and a `maddf.s`).
//!
//! Why APFloat is an oracle here and not the core's exact path: see `softfloat/mod.rs`.

use rustc_apfloat::ieee::{Double, Half, Single};
use rustc_apfloat::{Float, Round as ARound, Status};
use trax_emulator::softfloat::testgen::Rng;
use trax_emulator::softfloat::{self as sf, Env, Fmt, Round};

/// (fraction bits, width).
fn layout(f: Fmt) -> (u32, u32) {
    match f {
        Fmt::H => (10, 16),
        Fmt::S => (23, 32),
        Fmt::D => (52, 64),
    }
}

fn is_nan(f: Fmt, x: u64) -> bool {
    let (fb, w) = layout(f);
    let emax = (1u64 << (w - 1 - fb)) - 1;
    (x >> fb) & emax == emax && x & ((1 << fb) - 1) != 0
}

/// Smallest normal magnitude (either sign).
fn is_min_normal(f: Fmt, x: u64) -> bool {
    let (fb, w) = layout(f);
    x & !(1 << (w - 1)) == 1 << fb
}

/// Largest finite magnitude (either sign).
fn is_max(f: Fmt, x: u64) -> bool {
    let (fb, w) = layout(f);
    let emax = (1u64 << (w - 1 - fb)) - 1;
    x & !(1 << (w - 1)) == (emax << fb) - 1
}

fn ar(m: Round) -> ARound {
    match m {
        Round::Nearest => ARound::NearestTiesToEven,
        Round::Zero => ARound::TowardZero,
        Round::Up => ARound::TowardPositive,
        Round::Down => ARound::TowardNegative,
    }
}

fn flags(s: Status) -> u32 {
    [
        (Status::INEXACT, sf::FLAG_I),
        (Status::UNDERFLOW, sf::FLAG_U),
        (Status::OVERFLOW, sf::FLAG_O),
        (Status::DIV_BY_ZERO, sf::FLAG_Z),
        (Status::INVALID_OP, sf::FLAG_V),
    ]
    .iter()
    .filter(|(a, _)| s.contains(*a))
    .fold(0, |acc, (_, b)| acc | b)
}

#[derive(Clone, Copy, Debug)]
enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Fma,
}

macro_rules! apfloat {
    ($T:ty, $op:expr, $a:expr, $b:expr, $c:expr, $m:expr) => {{
        let x = <$T>::from_bits($a as u128);
        let y = <$T>::from_bits($b as u128);
        let z = <$T>::from_bits($c as u128);
        let r = match $op {
            Op::Add => x.add_r(y, ar($m)),
            Op::Sub => x.sub_r(y, ar($m)),
            Op::Mul => x.mul_r(y, ar($m)),
            Op::Div => x.div_r(y, ar($m)),
            Op::Fma => x.mul_add_r(y, z, ar($m)),
        };
        (r.value.to_bits() as u64, flags(r.status))
    }};
}

fn theirs(f: Fmt, op: Op, a: u64, b: u64, c: u64, m: Round) -> (u64, u32) {
    match f {
        Fmt::H => apfloat!(Half, op, a, b, c, m),
        Fmt::S => apfloat!(Single, op, a, b, c, m),
        Fmt::D => apfloat!(Double, op, a, b, c, m),
    }
}

/// Rounding per `mode`, no flush to zero, underflow only when inexact.
fn env(mode: Round) -> Env {
    Env::from_fcsr(mode as u32)
}

fn ours(f: Fmt, op: Op, a: u64, b: u64, c: u64, m: Round) -> (u64, u32) {
    let e = &mut env(m);
    let r = match op {
        Op::Add => sf::add(e, f, a, b),
        Op::Sub => sf::sub(e, f, a, b),
        Op::Mul => sf::mul(e, f, a, b),
        Op::Div => sf::div(e, f, a, b),
        Op::Fma => sf::fma(e, f, a, b, c, false),
    };
    (r, e.flags)
}

#[test]
fn arithmetic_agrees_with_apfloat() {
    const MODES: [Round; 4] = [Round::Nearest, Round::Zero, Round::Up, Round::Down];
    let mut r = Rng(0xABCD_EF12_3456_789B);
    let mut bad = Vec::new();
    let (mut compared, mut overflow_to_max, mut tiny_to_min) = (0u64, 0u64, 0u64);
    for f in [Fmt::H, Fmt::S, Fmt::D] {
        for _ in 0..60_000 {
            let (a, b, c) = (r.operand(f), r.operand(f), r.operand(f));
            for m in MODES {
                for op in [Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Fma] {
                    let (o, t) = (ours(f, op, a, b, c, m), theirs(f, op, a, b, c, m));
                    compared += 1;
                    let same = if is_nan(f, o.0) || is_nan(f, t.0) {
                        is_nan(f, o.0) && is_nan(f, t.0) && o.1 == t.1
                    } else if m != Round::Nearest && is_max(f, o.0) && o.1 == t.1 | sf::FLAG_O {
                        overflow_to_max += 1;
                        o.0 == t.0
                    } else if is_min_normal(f, o.0) && o.1 == t.1 | sf::FLAG_U {
                        tiny_to_min += 1;
                        o.0 == t.0
                    } else {
                        o == t
                    };
                    if !same && bad.len() < 10 {
                        bad.push(format!(
                            "{f:?} {op:?} {a:#x} {b:#x} {c:#x} {m:?}: ours {:#x} flags {:#x}, apfloat {:#x} flags {:#x}",
                            o.0, o.1, t.0, t.1
                        ));
                    }
                }
            }
        }
    }
    assert!(
        bad.is_empty(),
        "differences from APFloat:\n{}",
        bad.join("\n")
    );
    // The comparison reached both boundaries (the known differences) often.
    assert!(overflow_to_max > 1000, "{overflow_to_max} of {compared}");
    assert!(tiny_to_min > 100, "{tiny_to_min} of {compared}");
    println!("{compared} compared; {overflow_to_max} overflowed to the largest finite, {tiny_to_min} tiny results rounded to the smallest normal");
}

#[test]
fn round_to_integral_and_conversion_agree_with_apfloat() {
    let mut r = Rng(0x1357_9BDF_2468_ACE1);
    for _ in 0..100_000 {
        for f in [Fmt::S, Fmt::D] {
            let a = r.operand(f);
            for m in [Round::Nearest, Round::Zero, Round::Up, Round::Down] {
                let e = &mut env(m);
                let ours = (sf::rint(e, f, a), e.flags);
                let e = &mut env(m);
                let ours_int = (sf::to_int(e, f, a, m, true, 32), e.flags);
                let (theirs, theirs_int) = match f {
                    Fmt::S => {
                        let x = Single::from_bits(a as u128);
                        let i = x.to_i128_r(32, ar(m), &mut false);
                        let v = x.round_to_integral(ar(m));
                        (
                            (v.value.to_bits() as u64, flags(v.status)),
                            (i.value, i.status),
                        )
                    }
                    _ => {
                        let x = Double::from_bits(a as u128);
                        let i = x.to_i128_r(32, ar(m), &mut false);
                        let v = x.round_to_integral(ar(m));
                        (
                            (v.value.to_bits() as u64, flags(v.status)),
                            (i.value, i.status),
                        )
                    }
                };
                if !is_nan(f, a) {
                    assert_eq!(ours, theirs, "rint {f:?} {a:#x} {m:?}");
                }
                // APFloat gives 0 for NaN, like r6; saturated values match too.
                let theirs_int = ((theirs_int.0 as i32 as u32) as u64, flags(theirs_int.1));
                assert_eq!(ours_int, theirs_int, "to_int {f:?} {a:#x} {m:?}");
            }
        }
    }
}
