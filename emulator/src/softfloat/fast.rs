//! Host-arithmetic fast paths of the soft-float core.
//!
//! Each returns `None` unless the host's result is provably the correctly rounded one
//! with exactly the flags the exact path ([`super::exact`]) would raise; the caller then
//! runs the exact path. Arithmetic (`lane`) qualifies in round to nearest without flush
//! to zero when the result is finite and larger in magnitude than the smallest normal
//! (so nothing overflowed, underflowed, was a NaN or divided by zero, and only Inexact
//! can arise), or an exact zero or infinity no rounding produced; compares, min/max, rounding to an integer and integer conversions are
//! exact on the host in every rounding mode. `tests::fast_paths_match_the_exact_path`
//! checks that both paths agree.

use super::{Env, Fmt, MinMax, Round, FLAG_I, FLAG_V, REL_EQ, REL_LT, REL_UN};

/// An arithmetic operation with a host fast path.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Op {
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
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Finite and above the smallest normal in magnitude (so neither tiny nor overflowed).
#[inline(always)]
fn usable_f32(r: f32) -> bool {
    let m = r.to_bits() & 0x7FFF_FFFF;
    m.wrapping_sub(0x0080_0001) < 0x7F80_0000 - 0x0080_0001
}

#[inline(always)]
fn usable_f64(r: f64) -> bool {
    let m = r.to_bits() & 0x7FFF_FFFF_FFFF_FFFF;
    m.wrapping_sub(0x0010_0000_0000_0001) < 0x7FF0_0000_0000_0000 - 0x0010_0000_0000_0001
}

/// One operation in round to nearest: `Some((bits, inexact))` when the host result is
/// usable, else `None`.
///
/// Usable: a finite result above the smallest normal (then only Inexact can arise), or
/// an exact zero or infinity that involved no rounding, overflow or division by zero
/// (a zero or infinite operand, or an exact zero sum), whose host value is the IEEE one.
#[inline(always)]
pub(super) fn lane(f: Fmt, op: Op, a: u64, b: u64, c: u64) -> Option<(u64, bool)> {
    match f {
        Fmt::S => {
            let x = f32::from_bits(a as u32);
            let y = f32::from_bits(b as u32);
            let (r, inexact) = match op {
                Op::Add => {
                    // TwoSum in f32: the exact error of the rounded sum. An intermediate
                    // overflow (possible only for an inexact sum) yields a non-zero error.
                    let r = x + y;
                    if !usable_f32(r) {
                        // A sum of binary32 numbers is a multiple of the smallest
                        // subnormal: it rounds to zero only when it is zero.
                        let exact =
                            r == 0.0 || (r.is_infinite() && (x.is_infinite() | y.is_infinite()));
                        return exact.then_some((r.to_bits() as u64, false));
                    }
                    let bb = r - x;
                    (r, (x - (r - bb)) + (y - bb) != 0.0)
                }
                // Products of two f32 significands are exact in f64.
                Op::Mul => {
                    let r = x * y;
                    if !usable_f32(r) {
                        return special(
                            r,
                            (x == 0.0) | (y == 0.0),
                            x.is_infinite() | y.is_infinite(),
                        );
                    }
                    (r, x as f64 * y as f64 != r as f64)
                }
                Op::Div => {
                    let r = x / y;
                    if !usable_f32(r) {
                        return special(r, (x == 0.0) | y.is_infinite(), x.is_infinite());
                    }
                    (r, r as f64 * y as f64 != x as f64)
                }
                Op::Sqrt => {
                    let r = x.sqrt();
                    if !usable_f32(r) {
                        return special(r, true, true);
                    }
                    (r, r as f64 * r as f64 != x as f64)
                }
                Op::Fma => {
                    let z = f32::from_bits(c as u32);
                    if !x.is_finite() || !y.is_finite() || !z.is_finite() {
                        return None;
                    }
                    // x*y is exact in f64; the sum is exact if its error term is zero,
                    // and then one rounding to f32 gives the fused result.
                    let (s, e) = two_sum(x as f64 * y as f64, z as f64);
                    if e != 0.0 {
                        return None;
                    }
                    let r = s as f32;
                    if !usable_f32(r) {
                        return (s == 0.0).then_some((r.to_bits() as u64, false));
                    }
                    (r, r as f64 != s)
                }
            };
            Some((r.to_bits() as u64, inexact))
        }
        Fmt::D => {
            let x = f64::from_bits(a);
            let y = f64::from_bits(b);
            let (r, inexact) = match op {
                Op::Add => {
                    let (s, e) = two_sum(x, y);
                    if !usable_f64(s) {
                        let exact =
                            s == 0.0 || (s.is_infinite() && (x.is_infinite() | y.is_infinite()));
                        return exact.then_some((s.to_bits(), false));
                    }
                    (s, e != 0.0)
                }
                Op::Mul => {
                    let p = x * y;
                    if !usable_f64(p) {
                        return special(
                            p,
                            (x == 0.0) | (y == 0.0),
                            x.is_infinite() | y.is_infinite(),
                        );
                    }
                    if p.abs() < TINY {
                        return None;
                    }
                    (p, x.mul_add(y, -p) != 0.0)
                }
                Op::Div => {
                    let q = x / y;
                    if !usable_f64(q) {
                        return special(q, (x == 0.0) | y.is_infinite(), x.is_infinite());
                    }
                    if x.abs() < TINY {
                        return None;
                    }
                    (q, (-q).mul_add(y, x) != 0.0)
                }
                Op::Sqrt => {
                    let r = x.sqrt();
                    if !usable_f64(r) {
                        return special(r, true, true);
                    }
                    if x < TINY {
                        return None;
                    }
                    (r, (-r).mul_add(r, x) != 0.0)
                }
                Op::Fma => return None,
            };
            Some((r.to_bits(), inexact))
        }
        Fmt::H => None,
    }
}

/// A result outside the usable range: `Some` for a zero that `exact_zero` vouches for
/// (an operand made it zero, not underflow) and an infinity that `exact_inf` vouches
/// for (an infinite operand, not overflow or division by zero); `None` otherwise (NaNs,
/// tiny and overflowed results). The host's signs are IEEE's.
#[inline(always)]
fn special<T: HostFloat>(r: T, exact_zero: bool, exact_inf: bool) -> Option<(u64, bool)> {
    let ok = (r.is_zero() & exact_zero) | (r.is_inf() & exact_inf);
    ok.then(|| (r.bits(), false))
}

/// The two host float types, for [`special`].
trait HostFloat: Copy {
    fn is_zero(self) -> bool;
    fn is_inf(self) -> bool;
    fn bits(self) -> u64;
}
impl HostFloat for f32 {
    fn is_zero(self) -> bool {
        self == 0.0
    }
    fn is_inf(self) -> bool {
        self.is_infinite()
    }
    fn bits(self) -> u64 {
        self.to_bits() as u64
    }
}
impl HostFloat for f64 {
    fn is_zero(self) -> bool {
        self == 0.0
    }
    fn is_inf(self) -> bool {
        self.is_infinite()
    }
    fn bits(self) -> u64 {
        self.to_bits()
    }
}

/// [`lane`] under `env`: on success records Inexact and returns the result.
#[inline(always)]
pub(super) fn try_lane(env: &mut Env, f: Fmt, op: Op, a: u64, b: u64, c: u64) -> Option<u64> {
    if env.mode != Round::Nearest || env.ftz {
        return None;
    }
    let (r, inexact) = lane(f, op, a, b, c)?;
    env.flags |= inexact as u32 * FLAG_I;
    Some(r)
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
#[inline]
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
            FastOp::Add => lane(f, Op::Add, a, b, 0)?,
            FastOp::Sub => lane(f, Op::Add, a, b ^ sign, 0)?,
            FastOp::Mul => lane(f, Op::Mul, a, b, 0)?,
            FastOp::Div => lane(f, Op::Div, a, b, 0)?,
            FastOp::Fmadd => lane(f, Op::Fma, a, b, c)?,
            FastOp::Fmsub => lane(f, Op::Fma, a ^ sign, b, c)?,
        };
        r |= (x as u128) << sh;
        inexact |= ix;
    }
    Some((r, if inexact { FLAG_I } else { 0 }))
}

/// Operands of a binary32 or binary64 format as f64 (exact), `None` for binary16.
#[inline(always)]
fn host(f: Fmt, a: u64) -> Option<f64> {
    match f {
        Fmt::S => Some(f32::from_bits(a as u32) as f64),
        Fmt::D => Some(f64::from_bits(a)),
        Fmt::H => None,
    }
}

/// Signalling NaN test on raw bits.
#[inline(always)]
fn snan(f: Fmt, a: u64) -> bool {
    let abs = a & !f.sign_bit();
    abs > f.inf(false) && abs & f.quiet_bit() == 0
}

/// Runs `$body` with `$x`, `$y` bound to the operands in the host type of `$f` (f32 or
/// f64; no widening), or evaluates to `None` for binary16.
macro_rules! native {
    ($f:expr, $a:expr, $b:expr, |$x:ident, $y:ident| $body:expr) => {
        match $f {
            Fmt::S => {
                let ($x, $y) = (f32::from_bits($a as u32), f32::from_bits($b as u32));
                $body
            }
            Fmt::D => {
                let ($x, $y) = (f64::from_bits($a), f64::from_bits($b));
                $body
            }
            Fmt::H => None,
        }
    };
}

/// IEEE comparison without flush to zero (see [`super::compare`]).
#[inline(always)]
pub(super) fn compare(env: &mut Env, f: Fmt, a: u64, b: u64, signaling: bool) -> Option<u8> {
    native!(f, a, b, |x, y| {
        // Non-short-circuit operators: the outcome is data, better as flags than branches.
        let un = x.is_nan() | y.is_nan();
        env.flags |= (un & (signaling | snan(f, a) | snan(f, b))) as u32 * FLAG_V;
        Some(((un as u8) * REL_UN) | ((x == y) as u8 * REL_EQ) | ((x < y) as u8 * REL_LT))
    })
}

/// The relation of two operands that are not NaN (see [`super::compare_ordered`]).
#[inline(always)]
pub(super) fn compare_ordered(f: Fmt, a: u64, b: u64) -> Option<u8> {
    native!(f, a, b, |x, y| {
        (!(x.is_nan() | y.is_nan())).then_some(((x == y) as u8 * REL_EQ) | ((x < y) as u8 * REL_LT))
    })
}

/// Min/max of two non-NaN operands without flush to zero (see [`super::min_max`]).
#[inline(always)]
pub(super) fn min_max(f: Fmt, a: u64, b: u64, kind: MinMax) -> Option<u64> {
    native!(f, a, b, |x, y| {
        if x.is_nan() | y.is_nan() {
            return None;
        }
        let is_max = matches!(kind, MinMax::Max | MinMax::MaxA);
        if matches!(kind, MinMax::MaxA | MinMax::MinA) {
            let (ax, ay) = (x.abs(), y.abs());
            if ax != ay {
                return Some(if (ax > ay) == is_max { a } else { b });
            }
        }
        // Equal (incl. +0 == -0): min prefers the negative, max the positive.
        // Non-short-circuit operators: the comparisons are data, better as flags.
        let eq = x == y;
        let by_sign = is_max != x.is_sign_negative();
        let by_order = if is_max { x > y } else { x < y };
        let pick_a = (eq & by_sign) | (!eq & by_order);
        Some(if pick_a { a } else { b })
    })
}

/// `x` rounded to an integral value per `mode` (exact on the host).
#[inline(always)]
fn round_int(x: f64, mode: Round) -> f64 {
    match mode {
        Round::Nearest => x.round_ties_even(),
        Round::Zero => x.trunc(),
        Round::Up => x.ceil(),
        Round::Down => x.floor(),
    }
}

/// Float to integer without flush to zero (see [`super::to_int`]).
#[inline(always)]
pub(super) fn to_int(
    env: &mut Env,
    f: Fmt,
    a: u64,
    mode: Round,
    signed: bool,
    bits: u32,
) -> Option<u64> {
    let x = host(f, a)?;
    if x.is_nan() {
        env.flags |= FLAG_V;
        return Some(0);
    }
    let mask = u64::MAX >> (64 - bits);
    let r = round_int(x, mode);
    // Bounds as powers of two (exact in f64): [lo, hi).
    let (lo, hi) = if signed {
        (-((1u64 << (bits - 1)) as f64), (1u64 << (bits - 1)) as f64)
    } else {
        (0.0, (1u128 << bits) as f64)
    };
    if r >= hi {
        env.flags |= FLAG_V;
        return Some(if signed { mask >> 1 } else { mask });
    }
    if r < lo {
        env.flags |= FLAG_V;
        return Some(if signed { !(mask >> 1) & mask } else { 0 });
    }
    if r != x {
        env.flags |= FLAG_I;
    }
    Some(if signed {
        r as i64 as u64 & mask
    } else {
        r as u64
    })
}

/// Integer to float: exactly representable values in any mode, others in round to
/// nearest (see [`super::from_int`]).
#[inline(always)]
pub(super) fn from_int(env: &mut Env, f: Fmt, v: i128) -> Option<u64> {
    let v = i64::try_from(v).ok()?;
    let m = v.unsigned_abs();
    // Significant bits: from the highest set bit down to the lowest.
    let width = (64 - m.leading_zeros()).saturating_sub(m.trailing_zeros());
    let exact = width <= f.p() as u32;
    if !exact && env.mode != Round::Nearest {
        return None;
    }
    let r = match f {
        Fmt::S => (v as f32).to_bits() as u64,
        Fmt::D => (v as f64).to_bits(),
        Fmt::H => return None,
    };
    if !exact {
        env.flags |= FLAG_I;
    }
    Some(r)
}

/// Round to an integral value without flush to zero (see [`super::rint`]).
#[inline(always)]
pub(super) fn rint(env: &mut Env, f: Fmt, a: u64) -> Option<u64> {
    let x = host(f, a)?;
    if x.is_nan() {
        return None;
    }
    // The host functions keep the sign of a zero result (rint(-0.3) = -0).
    let r = round_int(x, env.mode);
    if r != x {
        env.flags |= FLAG_I;
    }
    Some(match f {
        Fmt::S => (r as f32).to_bits() as u64,
        _ => r.to_bits(),
    })
}

/// Format conversion: exact widening without flush to zero, narrowing in round to
/// nearest to a usable result (see [`super::convert`]).
#[inline(always)]
pub(super) fn convert(env: &mut Env, from: Fmt, to: Fmt, a: u64) -> Option<u64> {
    if env.ftz {
        return None;
    }
    match (from, to) {
        (Fmt::S, Fmt::D) => {
            let x = f32::from_bits(a as u32);
            (!x.is_nan()).then(|| (x as f64).to_bits())
        }
        (Fmt::D, Fmt::S) if env.mode == Round::Nearest => {
            let x = f64::from_bits(a);
            let r = x as f32;
            if !usable_f32(r) {
                return None;
            }
            if r as f64 != x {
                env.flags |= FLAG_I;
            }
            Some(r.to_bits() as u64)
        }
        _ => None,
    }
}
