//! Host-arithmetic fast paths for MSA floating point (round to nearest, no flush-to-zero).
//!
//! Results are used only when the host result is provably the correctly rounded one and a
//! normal number above the smallest normal (no overflow, underflow or special operands);
//! otherwise the exact software path in [`super::float`] runs. Both paths give identical
//! results and flags (checked by the test suite against the reference model and QEMU).

use super::float::{Env, Fmt, Round, FLAG_I};

/// A lane operation with a host fast path.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Op {
    Add,
    Mul,
    Div,
    Sqrt,
    /// `c + a*b` (negate `a` for `c - a*b`).
    Fma,
}

/// 2^-900: keeps error terms of double-precision operations representable.
const TINY: f64 = f64::from_bits((1023 - 900) << 52);

/// Error-free sum: `s + e == a + b` exactly (barring overflow).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// One lane: `Some((bits, inexact))` when the host result is usable, else `None`.
#[inline(always)]
pub(crate) fn run(f: Fmt, op: Op, a: u64, b: u64, c: u64) -> Option<(u64, bool)> {
    match f {
        Fmt::S => {
            let x = f32::from_bits(a as u32) as f64;
            let y = f32::from_bits(b as u32) as f64;
            let z = f32::from_bits(c as u32) as f64;
            if !x.is_finite() || !y.is_finite() || !z.is_finite() {
                return None;
            }
            let (r, inexact) = match op {
                Op::Add => {
                    let (s, e) = two_sum(x, y);
                    if e != 0.0 {
                        return None;
                    }
                    let r = s as f32;
                    (r, r as f64 != s)
                }
                Op::Mul => {
                    let p = x * y; // exact: 24 x 24 bits
                    let r = p as f32;
                    (r, r as f64 != p)
                }
                Op::Div => {
                    if y == 0.0 {
                        return None;
                    }
                    // Rounding to f64 then f32 is innocuous for division (53 >= 2*24+2).
                    let r = (x / y) as f32;
                    (r, r as f64 * y != x)
                }
                Op::Sqrt => {
                    if x <= 0.0 {
                        return None;
                    }
                    let r = x.sqrt() as f32;
                    (r, r as f64 * r as f64 != x)
                }
                Op::Fma => {
                    let (s, e) = two_sum(x * y, z);
                    if e != 0.0 {
                        return None;
                    }
                    let r = s as f32;
                    (r, r as f64 != s)
                }
            };
            (r.is_finite() && r.abs() > f32::MIN_POSITIVE).then_some((r.to_bits() as u64, inexact))
        }
        Fmt::D => {
            let x = f64::from_bits(a);
            let y = f64::from_bits(b);
            if !x.is_finite() || !y.is_finite() {
                return None;
            }
            let (r, inexact) = match op {
                Op::Add => {
                    let (s, e) = two_sum(x, y);
                    (s, e != 0.0)
                }
                Op::Mul => {
                    let p = x * y;
                    if p.abs() < TINY {
                        return None;
                    }
                    (p, x.mul_add(y, -p) != 0.0)
                }
                Op::Div => {
                    if x.abs() < TINY || y == 0.0 {
                        return None;
                    }
                    let q = x / y;
                    (q, (-q).mul_add(y, x) != 0.0)
                }
                Op::Sqrt => {
                    if x < TINY {
                        return None;
                    }
                    let r = x.sqrt();
                    (r, (-r).mul_add(r, x) != 0.0)
                }
                Op::Fma => return None,
            };
            (r.is_finite() && r.abs() > f64::MIN_POSITIVE).then_some((r.to_bits(), inexact))
        }
        Fmt::H => None,
    }
}

/// Operations with a whole-vector fast path ([`vector_fast`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FastOp {
    /// `ws + wt`.
    Add,
    /// `ws - wt`.
    Sub,
    /// `ws * wt`.
    Mul,
    /// `ws / wt`.
    Div,
    /// `wd + ws * wt`.
    Fmadd,
    /// `wd - ws * wt`.
    Fmsub,
}

/// Whole-vector host fast path (round to nearest, no flush-to-zero): the result and the
/// raised flags when every lane qualifies for the host fast path, else `None` (the caller then
/// runs the general per-lane path, which gives identical results).
pub fn vector_fast(
    env: &Env,
    f: Fmt,
    op: FastOp,
    s: u128,
    t: u128,
    d: u128,
) -> Option<(u128, u32)> {
    if env.mode != Round::Nearest || env.ftz {
        return None;
    }
    let (width, lanes) = match f {
        Fmt::S => (32, 4),
        Fmt::D => (64, 2),
        Fmt::H => return None,
    };
    let mask = u64::MAX >> (64 - width);
    let sign = f.sign_bit();
    let mut r = 0u128;
    let mut inexact = false;
    for i in 0..lanes {
        let sh = i * width;
        let a = (s >> sh) as u64 & mask;
        let b = (t >> sh) as u64 & mask;
        let c = (d >> sh) as u64 & mask;
        let (x, ix) = match op {
            FastOp::Add => run(f, Op::Add, a, b, 0)?,
            FastOp::Sub => run(f, Op::Add, a, b ^ sign, 0)?,
            FastOp::Mul => run(f, Op::Mul, a, b, 0)?,
            FastOp::Div => run(f, Op::Div, a, b, 0)?,
            FastOp::Fmadd => run(f, Op::Fma, a, b, c)?,
            FastOp::Fmsub => run(f, Op::Fma, a ^ sign, b, c)?,
        };
        r |= (x as u128) << sh;
        inexact |= ix;
    }
    Some((r, if inexact { FLAG_I } else { 0 }))
}

/// Tries the host fast path; on success records Inexact and returns the result.
#[inline(always)]
pub(crate) fn try_fast(env: &mut Env, f: Fmt, op: Op, a: u64, b: u64, c: u64) -> Option<u64> {
    if env.mode != Round::Nearest || env.ftz {
        return None;
    }
    let (r, inexact) = run(f, op, a, b, c)?;
    if inexact {
        env.flags |= FLAG_I;
    }
    Some(r)
}
