//! IEEE 754 arithmetic for MSA lanes (half, single, double) in software.
//!
//! Every operation is computed exactly on unpacked integers and rounded once, under the
//! rounding mode from MSACSR, with flush-to-zero and IEEE exception flags. (For round to
//! nearest without flush-to-zero, add/sub/mul/div/sqrt/fma/compare/min/max first try the
//! host's arithmetic (module `float_fast`), used only when its result is provably
//! identical.)
//!
//! - NaN encoding is NaN-2008 (quiet bit = most significant fraction bit set). An invalid
//!   operation with no NaN input gives the default NaN (`0x7FC00000`, `0x7FF8000000000000`,
//!   `0x7E00`). A NaN input propagates, quieted: the first signaling NaN among the
//!   operands in operand order (`ws`, `wt`; for fused multiply-add the accumulator `wd`
//!   first, then `ws`, `wt`) wins, otherwise the first quiet NaN in the same order. Any
//!   signaling NaN input raises Invalid; so does `inf * 0` in a fused multiply-add even
//!   when the accumulator is a quiet NaN.
//! - Tininess is detected after rounding; Underflow is raised when a tiny result is also
//!   inexact, or (IEEE trapped underflow) when Underflow is enabled in MSACSR, except for
//!   binary16 results and min/max.
//! - With MSACSR.FS set, subnormal inputs are read as zero of the same sign, raising
//!   Inexact (compares excepted), and subnormal results are replaced by zero of the same
//!   sign, raising Underflow and Inexact.
//! - `frcp` is correctly rounded `1/x`; `frsqrt` is `1/sqrt(x)` as two correctly rounded
//!   steps (square root, then reciprocal). The architecture allows approximations here,
//!   so unless the operation is invalid or divides by zero, or the reciprocal's operand
//!   is infinite or its result a NaN, they raise exactly Inexact.
//! - `ftq` saturation raises Overflow and Inexact; a NaN gives 0 and raises Invalid.
//!
//! These choices follow QEMU's MSA model, which the test suite uses as an oracle.

use std::cmp::Ordering;

use super::float_fast::{try_fast, Op};

/// Inexact flag bit (as in MSACSR's Flags/Cause/Enables fields).
pub const FLAG_I: u32 = 1;
/// Underflow flag bit.
pub const FLAG_U: u32 = 2;
/// Overflow flag bit.
pub const FLAG_O: u32 = 4;
/// Divide-by-zero flag bit.
pub const FLAG_Z: u32 = 8;
/// Invalid-operation flag bit.
pub const FLAG_V: u32 = 16;

/// IEEE rounding mode (MSACSR.RM encoding order).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Round {
    /// Round to nearest, ties to even (RM = 0).
    Nearest,
    /// Round toward zero (RM = 1).
    Zero,
    /// Round toward +infinity (RM = 2).
    Up,
    /// Round toward -infinity (RM = 3).
    Down,
}

impl Round {
    /// The mode selected by a 2-bit RM field.
    pub fn from_rm(rm: u32) -> Round {
        match rm & 3 {
            0 => Round::Nearest,
            1 => Round::Zero,
            2 => Round::Up,
            _ => Round::Down,
        }
    }
}

/// Floating-point format of a lane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fmt {
    /// binary16.
    H,
    /// binary32.
    S,
    /// binary64.
    D,
}

impl Fmt {
    /// Precision in bits, including the hidden bit.
    fn p(self) -> i32 {
        match self {
            Fmt::H => 11,
            Fmt::S => 24,
            Fmt::D => 53,
        }
    }

    /// Exponent bias (also the maximum unbiased exponent).
    fn bias(self) -> i32 {
        match self {
            Fmt::H => 15,
            Fmt::S => 127,
            Fmt::D => 1023,
        }
    }

    /// Total width in bits.
    pub fn width(self) -> u32 {
        match self {
            Fmt::H => 16,
            Fmt::S => 32,
            Fmt::D => 64,
        }
    }

    fn frac_bits(self) -> u32 {
        self.p() as u32 - 1
    }

    fn exp_mask(self) -> u64 {
        (1u64 << (self.width() - 1 - self.frac_bits())) - 1
    }

    pub(crate) fn sign_bit(self) -> u64 {
        1u64 << (self.width() - 1)
    }

    fn quiet_bit(self) -> u64 {
        1u64 << (self.frac_bits() - 1)
    }

    /// The default quiet NaN.
    pub fn default_nan(self) -> u64 {
        (self.exp_mask() << self.frac_bits()) | self.quiet_bit()
    }

    fn inf(self, sign: bool) -> u64 {
        (self.exp_mask() << self.frac_bits()) | if sign { self.sign_bit() } else { 0 }
    }

    fn zero(self, sign: bool) -> u64 {
        if sign {
            self.sign_bit()
        } else {
            0
        }
    }

    fn max_finite(self, sign: bool) -> u64 {
        self.inf(sign) - 1
    }
}

/// Rounding environment of one instruction; `flags` accumulates raised exceptions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Env {
    /// Rounding mode.
    pub mode: Round,
    /// Flush subnormal inputs and outputs to zero (MSACSR.FS).
    pub ftz: bool,
    /// Underflow is enabled (trapping): exact tiny results then also raise Underflow, as
    /// IEEE 754 specifies for trapped underflow.
    pub trap_underflow: bool,
    /// Raised exception flags (`FLAG_*` bits).
    pub flags: u32,
}

impl Env {
    /// Environment from an MSACSR value (RM bits 1..0, Underflow enable bit 8, FS bit 24),
    /// no flags raised.
    pub fn from_msacsr(csr: u32) -> Env {
        Env {
            mode: Round::from_rm(csr),
            ftz: csr & (1 << 24) != 0,
            trap_underflow: csr & (1 << 8) != 0,
            flags: 0,
        }
    }
}

/// An unpacked operand. Finite values are `mant * 2^exp` with bit 62 of `mant` set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Val {
    Nan { signaling: bool },
    Inf(bool),
    Zero(bool),
    Fin { sign: bool, exp: i32, mant: u64 },
}

/// Unpacks an operand; with flush-to-zero a subnormal reads as zero and raises Inexact.
fn unpack(env: &mut Env, f: Fmt, bits: u64) -> Val {
    let sign = bits & f.sign_bit() != 0;
    let fb = f.frac_bits();
    let e = ((bits >> fb) & f.exp_mask()) as i32;
    let frac = bits & ((1u64 << fb) - 1);
    if e as u64 == f.exp_mask() {
        if frac == 0 {
            Val::Inf(sign)
        } else {
            Val::Nan {
                signaling: frac & f.quiet_bit() == 0,
            }
        }
    } else if e == 0 {
        if frac == 0 {
            Val::Zero(sign)
        } else if env.ftz {
            env.flags |= FLAG_I;
            Val::Zero(sign)
        } else {
            normalized(sign, 1 - f.bias() - fb as i32, frac)
        }
    } else {
        normalized(sign, e - f.bias() - fb as i32, frac | (1u64 << fb))
    }
}

fn normalized(sign: bool, exp: i32, mant: u64) -> Val {
    let s = mant.leading_zeros() as i32 - 1;
    Val::Fin {
        sign,
        exp: exp - s,
        mant: mant << s,
    }
}

/// Handles NaN operands: `Some(result)` if any operand is a NaN (see module docs).
fn propagate_nan(env: &mut Env, f: Fmt, ops: &[u64]) -> Option<u64> {
    let frac_mask = (1u64 << f.frac_bits()) - 1;
    let exp_of = |b: u64| (b >> f.frac_bits()) & f.exp_mask();
    let is_nan = |b: u64| exp_of(b) == f.exp_mask() && b & frac_mask != 0;
    let is_snan = |b: u64| b & f.quiet_bit() == 0 && is_nan(b);
    let nan = if let Some(&s) = ops.iter().find(|&&b| is_snan(b)) {
        env.flags |= FLAG_V;
        s | f.quiet_bit()
    } else {
        *ops.iter().find(|&&b| is_nan(b))?
    };
    // Operands are unpacked (and subnormals flushed, raising Inexact) before NaNs are seen.
    if env.ftz && ops.iter().any(|&b| exp_of(b) == 0 && b & frac_mask != 0) {
        env.flags |= FLAG_I;
    }
    Some(nan)
}

fn invalid(env: &mut Env, f: Fmt) -> u64 {
    env.flags |= FLAG_V;
    f.default_nan()
}

/// Shifts `mant` right by `shift` (>= 1) rounding per `mode`; returns (kept, inexact).
fn round_shift(mant: u128, shift: i32, sign: bool, mode: Round) -> (u128, bool) {
    if shift <= 0 {
        return (mant << (-shift).min(127), false);
    }
    let s = shift as u32;
    let kept = if s >= 128 { 0 } else { mant >> s };
    let round_bit = if s > 128 { 0 } else { (mant >> (s - 1)) & 1 };
    let below = if s > 128 {
        mant
    } else {
        mant & ((1u128 << (s - 1)) - 1)
    };
    let inexact = round_bit != 0 || below != 0;
    let up = match mode {
        Round::Nearest => round_bit != 0 && (below != 0 || kept & 1 != 0),
        Round::Zero => false,
        Round::Up => !sign && inexact,
        Round::Down => sign && inexact,
    };
    (kept + up as u128, inexact)
}

fn overflow(env: &mut Env, f: Fmt, sign: bool) -> u64 {
    env.flags |= FLAG_O | FLAG_I;
    let to_inf = match env.mode {
        Round::Nearest => true,
        Round::Zero => false,
        Round::Up => !sign,
        Round::Down => sign,
    };
    if to_inf {
        f.inf(sign)
    } else {
        f.max_finite(sign)
    }
}

/// Rounds the exact value `(-1)^sign * mant * 2^exp` to format `f`. `mant` may carry a
/// sticky bit in bit 0 provided it has at least two bits below the rounding position.
fn round_pack(env: &mut Env, f: Fmt, sign: bool, exp: i32, mant: u128) -> u64 {
    if mant == 0 {
        return f.zero(sign);
    }
    let p = f.p();
    let emin = 1 - f.bias();
    let top = 127 - mant.leading_zeros() as i32;
    let e = top + exp;
    if e > f.bias() + 1 {
        return overflow(env, f, sign);
    }
    let q = (e - (p - 1)).max(emin - (p - 1));
    let (mut kept, inexact) = round_shift(mant, q - exp, sign, env.mode);
    let mut q = q;
    if kept == 1u128 << p {
        kept >>= 1;
        q += 1;
    }
    let tiny = e < emin && {
        let (k2, _) = round_shift(mant, e - (p - 1) - exp, sign, env.mode);
        !(e == emin - 1 && k2 == 1u128 << p)
    };
    if inexact {
        env.flags |= FLAG_I;
    }
    // Binary16 results (fexdo.h) signal exact tiny results never, like QEMU.
    if tiny && (inexact || (env.trap_underflow && f != Fmt::H)) {
        env.flags |= FLAG_U;
    }
    if kept == 0 {
        return f.zero(sign);
    }
    let fb = f.frac_bits();
    let rtop = 127 - kept.leading_zeros() as i32;
    if rtop + q > f.bias() {
        return overflow(env, f, sign);
    }
    let bits = if kept >> fb != 0 {
        (((rtop + q + f.bias()) as u64) << fb) | (kept as u64 & ((1u64 << fb) - 1))
    } else if env.ftz {
        env.flags |= FLAG_U | FLAG_I;
        0
    } else {
        kept as u64
    };
    bits | f.zero(sign)
}

/// Re-packs an exactly representable unpacked value.
fn pack_val(env: &mut Env, f: Fmt, v: Val) -> u64 {
    match v {
        Val::Nan { .. } => f.default_nan(),
        Val::Inf(s) => f.inf(s),
        Val::Zero(s) => f.zero(s),
        Val::Fin { sign, exp, mant } => round_pack(env, f, sign, exp, mant as u128),
    }
}

/// Exact sum of two finite nonzero values (mantissas up to 126 bits), rounded.
fn add_fin(env: &mut Env, f: Fmt, a: (bool, i32, u128), b: (bool, i32, u128)) -> u64 {
    let norm = |(s, e, m): (bool, i32, u128)| {
        let sh = m.leading_zeros() as i32 - 2;
        (s, e - sh, m << sh)
    };
    let (a, b) = (norm(a), norm(b));
    let (big, small) = if a.1 >= b.1 { (a, b) } else { (b, a) };
    let d = (big.1 - small.1) as u32;
    let sm = if d == 0 {
        small.2
    } else if d >= 127 {
        1
    } else {
        (small.2 >> d) | ((small.2 & ((1u128 << d) - 1) != 0) as u128)
    };
    if big.0 == small.0 {
        round_pack(env, f, big.0, big.1, big.2 + sm)
    } else if big.2 > sm {
        round_pack(env, f, big.0, big.1, big.2 - sm)
    } else if big.2 < sm {
        round_pack(env, f, small.0, big.1, sm - big.2)
    } else {
        f.zero(env.mode == Round::Down)
    }
}

/// `a + b`.
#[inline]
pub fn add(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = try_fast(env, f, Op::Add, a, b, 0) {
        return r;
    }
    add_exact(env, f, a, b)
}

#[inline(never)]
fn add_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a, b]) {
        return n;
    }
    match (unpack(env, f, a), unpack(env, f, b)) {
        (Val::Inf(x), Val::Inf(y)) if x != y => invalid(env, f),
        (Val::Inf(x), _) | (_, Val::Inf(x)) => f.inf(x),
        (Val::Zero(x), Val::Zero(y)) => f.zero(if x == y { x } else { env.mode == Round::Down }),
        (Val::Zero(_), v) | (v, Val::Zero(_)) => pack_val(env, f, v),
        (
            Val::Fin {
                sign: s1,
                exp: e1,
                mant: m1,
            },
            Val::Fin {
                sign: s2,
                exp: e2,
                mant: m2,
            },
        ) => add_fin(env, f, (s1, e1, m1 as u128), (s2, e2, m2 as u128)),
        _ => f.default_nan(),
    }
}

fn neg_unless_nan(f: Fmt, x: u64) -> u64 {
    let exp_all = (x >> f.frac_bits()) & f.exp_mask() == f.exp_mask();
    let frac = x & ((1u64 << f.frac_bits()) - 1);
    if exp_all && frac != 0 {
        x
    } else {
        x ^ f.sign_bit()
    }
}

/// `a - b`.
#[inline]
pub fn sub(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = try_fast(env, f, Op::Add, a, b ^ f.sign_bit(), 0) {
        return r;
    }
    sub_exact(env, f, a, b)
}

#[inline(never)]
fn sub_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a, b]) {
        return n;
    }
    add(env, f, a, neg_unless_nan(f, b))
}

/// `a * b`.
#[inline]
pub fn mul(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = try_fast(env, f, Op::Mul, a, b, 0) {
        return r;
    }
    mul_exact(env, f, a, b)
}

#[inline(never)]
fn mul_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a, b]) {
        return n;
    }
    match (unpack(env, f, a), unpack(env, f, b)) {
        (Val::Inf(_), Val::Zero(_)) | (Val::Zero(_), Val::Inf(_)) => invalid(env, f),
        (Val::Inf(x), v) | (v, Val::Inf(x)) => f.inf(x ^ sign_of(v)),
        (Val::Zero(x), v) | (v, Val::Zero(x)) => f.zero(x ^ sign_of(v)),
        (
            Val::Fin {
                sign: s1,
                exp: e1,
                mant: m1,
            },
            Val::Fin {
                sign: s2,
                exp: e2,
                mant: m2,
            },
        ) => round_pack(env, f, s1 ^ s2, e1 + e2, m1 as u128 * m2 as u128),
        _ => f.default_nan(),
    }
}

fn sign_of(v: Val) -> bool {
    match v {
        Val::Nan { .. } => false,
        Val::Inf(s) | Val::Zero(s) => s,
        Val::Fin { sign, .. } => sign,
    }
}

/// `a / b`.
#[inline]
pub fn div(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = try_fast(env, f, Op::Div, a, b, 0) {
        return r;
    }
    div_exact(env, f, a, b)
}

#[inline(never)]
fn div_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a, b]) {
        return n;
    }
    match (unpack(env, f, a), unpack(env, f, b)) {
        (Val::Inf(_), Val::Inf(_)) | (Val::Zero(_), Val::Zero(_)) => invalid(env, f),
        (Val::Inf(x), v) => f.inf(x ^ sign_of(v)),
        (v, Val::Inf(x)) => f.zero(x ^ sign_of(v)),
        (Val::Zero(x), v) => f.zero(x ^ sign_of(v)),
        (v, Val::Zero(x)) => {
            env.flags |= FLAG_Z;
            f.inf(x ^ sign_of(v))
        }
        (
            Val::Fin {
                sign: s1,
                exp: e1,
                mant: m1,
            },
            Val::Fin {
                sign: s2,
                exp: e2,
                mant: m2,
            },
        ) => {
            let n = (m1 as u128) << 64;
            let q = n / m2 as u128;
            let r = n % m2 as u128;
            round_pack(env, f, s1 ^ s2, e1 - 64 - e2, q | (r != 0) as u128)
        }
        _ => f.default_nan(),
    }
}

/// Square root.
#[inline]
pub fn sqrt(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if let Some(r) = try_fast(env, f, Op::Sqrt, a, 0, 0) {
        return r;
    }
    sqrt_exact(env, f, a)
}

#[inline(never)]
fn sqrt_exact(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a]) {
        return n;
    }
    match unpack(env, f, a) {
        Val::Zero(s) => f.zero(s),
        Val::Inf(false) => f.inf(false),
        Val::Fin {
            sign: false,
            exp,
            mant,
        } => {
            let (exp, mant) = if exp & 1 != 0 {
                (exp - 1, (mant as u128) << 1)
            } else {
                (exp, mant as u128)
            };
            let n = mant << 64;
            let r = n.isqrt();
            let sticky = (r * r != n) as u128;
            round_pack(env, f, false, (exp - 64) / 2, r | sticky)
        }
        _ => invalid(env, f),
    }
}

/// Fused `c + a*b` (or `c - a*b` when `negate` is set), rounded once.
#[inline]
pub fn fma(env: &mut Env, f: Fmt, a: u64, b: u64, c: u64, negate: bool) -> u64 {
    let na = if negate { a ^ f.sign_bit() } else { a };
    if let Some(r) = try_fast(env, f, Op::Fma, na, b, c) {
        return r;
    }
    fma_exact(env, f, a, b, c, negate)
}

#[inline(never)]
fn fma_exact(env: &mut Env, f: Fmt, a: u64, b: u64, c: u64, negate: bool) -> u64 {
    let (va, vb, vc) = (unpack(env, f, a), unpack(env, f, b), unpack(env, f, c));
    let is_inf = |v: Val| matches!(v, Val::Inf(_));
    let is_zero = |v: Val| matches!(v, Val::Zero(_));
    // inf * 0 is invalid even when the accumulator is a quiet NaN.
    if (is_inf(va) && is_zero(vb)) || (is_zero(va) && is_inf(vb)) {
        env.flags |= FLAG_V;
    }
    if let Some(n) = propagate_nan(env, f, &[c, a, b]) {
        return n;
    }
    let psign = sign_of(va) ^ sign_of(vb) ^ negate;
    let prod_inf = matches!(va, Val::Inf(_)) || matches!(vb, Val::Inf(_));
    let prod_zero = matches!(va, Val::Zero(_)) || matches!(vb, Val::Zero(_));
    if prod_inf && prod_zero {
        return invalid(env, f);
    }
    if prod_inf {
        return match vc {
            Val::Inf(s) if s != psign => invalid(env, f),
            _ => f.inf(psign),
        };
    }
    match (prod_zero, vc) {
        (_, Val::Inf(s)) => f.inf(s),
        (true, Val::Zero(s)) => f.zero(if s == psign {
            s
        } else {
            env.mode == Round::Down
        }),
        (true, v) => pack_val(env, f, v),
        (false, Val::Zero(_)) => match (va, vb) {
            (
                Val::Fin {
                    exp: e1, mant: m1, ..
                },
                Val::Fin {
                    exp: e2, mant: m2, ..
                },
            ) => round_pack(env, f, psign, e1 + e2, m1 as u128 * m2 as u128),
            _ => f.default_nan(),
        },
        (false, Val::Fin { sign, exp, mant }) => match (va, vb) {
            (
                Val::Fin {
                    exp: e1, mant: m1, ..
                },
                Val::Fin {
                    exp: e2, mant: m2, ..
                },
            ) => add_fin(
                env,
                f,
                (psign, e1 + e2, m1 as u128 * m2 as u128),
                (sign, exp, mant as u128),
            ),
            _ => f.default_nan(),
        },
        _ => f.default_nan(),
    }
}

/// IEEE comparison; `None` when unordered. Signaling compares raise Invalid on any NaN,
/// quiet compares only on signaling NaNs.
///
/// Compares never raise Inexact (not even when flushing subnormal inputs).
pub fn compare(env: &mut Env, f: Fmt, a: u64, b: u64, signaling: bool) -> Option<Ordering> {
    if !env.ftz && f != Fmt::H {
        let (x, y) = if f == Fmt::S {
            (
                f32::from_bits(a as u32) as f64,
                f32::from_bits(b as u32) as f64,
            )
        } else {
            (f64::from_bits(a), f64::from_bits(b))
        };
        if !x.is_nan() && !y.is_nan() {
            return x.partial_cmp(&y);
        }
    }
    let saved = env.flags;
    let va = unpack(env, f, a);
    let vb = unpack(env, f, b);
    env.flags = (env.flags & !FLAG_I) | (saved & FLAG_I);
    let nan_a = matches!(va, Val::Nan { .. });
    let nan_b = matches!(vb, Val::Nan { .. });
    if nan_a || nan_b {
        let snan = matches!(va, Val::Nan { signaling: true })
            || matches!(vb, Val::Nan { signaling: true });
        if signaling || snan {
            env.flags |= FLAG_V;
        }
        return None;
    }
    Some(total_key(va).cmp(&total_key(vb)))
}

/// A key ordering non-NaN values numerically (both zeros equal).
fn total_key(v: Val) -> (i32, i64, i64) {
    match v {
        Val::Zero(_) | Val::Nan { .. } => (0, 0, 0),
        Val::Inf(s) => (if s { -2 } else { 2 }, 0, 0),
        Val::Fin { sign, exp, mant } => {
            let k = (exp as i64, mant as i64);
            if sign {
                (-1, -k.0, -k.1)
            } else {
                (1, k.0, k.1)
            }
        }
    }
}

/// Which operand a min/max picks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MinMax {
    /// `fmax`.
    Max,
    /// `fmin`.
    Min,
    /// `fmax_a` (larger magnitude).
    MaxA,
    /// `fmin_a` (smaller magnitude).
    MinA,
}

/// `fmax`/`fmin`/`fmax_a`/`fmin_a`: a quiet NaN loses against a number; signaling NaNs
/// raise Invalid and propagate; `max(-0, +0) = +0`, `min(-0, +0) = -0`; for the magnitude
/// forms equal magnitudes fall back to the plain form.
pub fn min_max(env: &mut Env, f: Fmt, a: u64, b: u64, kind: MinMax) -> u64 {
    // Picking an operand never underflows, even when it is subnormal.
    let u = env.flags & FLAG_U;
    let r = min_max_inner(env, f, a, b, kind);
    env.flags = (env.flags & !FLAG_U) | u;
    r
}

fn min_max_inner(env: &mut Env, f: Fmt, a: u64, b: u64, kind: MinMax) -> u64 {
    if !env.ftz && f != Fmt::H && matches!(kind, MinMax::Max | MinMax::Min) {
        let (x, y) = if f == Fmt::S {
            (
                f32::from_bits(a as u32) as f64,
                f32::from_bits(b as u32) as f64,
            )
        } else {
            (f64::from_bits(a), f64::from_bits(b))
        };
        if !x.is_nan() && !y.is_nan() {
            let pick_a = if kind == MinMax::Max {
                x > y || (x == y && !x.is_sign_negative())
            } else {
                x < y || (x == y && x.is_sign_negative())
            };
            return if pick_a { a } else { b };
        }
    }
    let va = unpack(env, f, a);
    let vb = unpack(env, f, b);
    let snan = |v: Val| matches!(v, Val::Nan { signaling: true });
    if snan(va) || snan(vb) {
        return propagate_nan(env, f, &[a, b]).unwrap_or(f.default_nan());
    }
    match (matches!(va, Val::Nan { .. }), matches!(vb, Val::Nan { .. })) {
        (true, _) if matches!(vb, Val::Nan { .. }) => return a,
        (true, false) => return pack_val(env, f, vb),
        (false, true) => return pack_val(env, f, va),
        _ => {}
    }
    let ka = total_key(va);
    let kb = total_key(vb);
    let abs = |v: Val| match v {
        Val::Inf(_) => total_key(Val::Inf(false)),
        Val::Zero(_) => (0, 0, 0),
        Val::Fin { exp, mant, .. } => total_key(Val::Fin {
            sign: false,
            exp,
            mant,
        }),
        Val::Nan { .. } => (0, 0, 0),
    };
    // For equal values, order -0 below +0.
    let ord = ka.cmp(&kb).then(sign_of(vb).cmp(&sign_of(va)));
    let mag = abs(va).cmp(&abs(vb));
    let pick_a = match kind {
        MinMax::Max => ord != Ordering::Less,
        MinMax::Min => ord != Ordering::Greater,
        MinMax::MaxA => {
            mag == Ordering::Greater || (mag == Ordering::Equal && ord != Ordering::Less)
        }
        MinMax::MinA => {
            mag == Ordering::Less || (mag == Ordering::Equal && ord != Ordering::Greater)
        }
    };
    pack_val(env, f, if pick_a { va } else { vb })
}

/// `fclass` bit mask: 0 sNaN, 1 qNaN, 2..5 negative inf/normal/subnormal/zero, 6..9 positive.
pub fn class(f: Fmt, a: u64) -> u64 {
    let mut env = Env {
        mode: Round::Nearest,
        ftz: false,
        trap_underflow: false,
        flags: 0,
    };
    let neg = a & f.sign_bit() != 0;
    let base = |k: u32| {
        if neg {
            1u64 << (2 + k)
        } else {
            1u64 << (6 + k)
        }
    };
    match unpack(&mut env, f, a) {
        Val::Nan { signaling: true } => 1,
        Val::Nan { signaling: false } => 2,
        Val::Inf(_) => base(0),
        Val::Zero(_) => base(3),
        Val::Fin { .. } => {
            if (a >> f.frac_bits()) & f.exp_mask() == 0 {
                base(2)
            } else {
                base(1)
            }
        }
    }
}

/// Converts to a `bits`-wide integer (signed or unsigned) rounding per `mode`.
///
/// NaN gives 0; out-of-range values saturate; both raise Invalid (and not Inexact).
pub fn to_int(env: &mut Env, f: Fmt, a: u64, mode: Round, signed: bool, bits: u32) -> u64 {
    let v = unpack(env, f, a);
    val_to_int(env, v, mode, signed, bits, FLAG_V)
}

/// Rounds `v` to an integer; out-of-range values saturate raising `sat_flags`.
fn val_to_int(env: &mut Env, v: Val, mode: Round, signed: bool, bits: u32, sat_flags: u32) -> u64 {
    let (lo, hi): (i128, i128) = if signed {
        (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
    } else {
        (0, (1i128 << bits) - 1)
    };
    let mask = if bits == 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    };
    let sat = |env: &mut Env, v: i128| {
        env.flags |= sat_flags;
        v as u64 & mask
    };
    match v {
        Val::Nan { .. } => {
            env.flags |= FLAG_V;
            0
        }
        Val::Inf(s) => sat(env, if s { lo } else { hi }),
        Val::Zero(_) => 0,
        Val::Fin { sign, exp, mant } => {
            if exp > 64 {
                return sat(env, if sign { lo } else { hi });
            }
            let (mag, inexact) = round_shift(mant as u128, -exp, sign, mode);
            let v = if sign { -(mag as i128) } else { mag as i128 };
            if v < lo || v > hi {
                return sat(env, if sign { lo } else { hi });
            }
            if inexact {
                env.flags |= FLAG_I;
            }
            v as u64 & mask
        }
    }
}

/// Converts an integer to format `f`, rounding per the environment.
pub fn from_int(env: &mut Env, f: Fmt, v: i128) -> u64 {
    round_pack(env, f, v < 0, 0, v.unsigned_abs())
}

/// Rounds to an integral value in the same format (`frint`), raising Inexact.
pub fn rint(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a]) {
        return n;
    }
    match unpack(env, f, a) {
        Val::Fin { sign, exp, mant } if exp < 0 => {
            let (k, inexact) = round_shift(mant as u128, -exp, sign, env.mode);
            if inexact {
                env.flags |= FLAG_I;
            }
            if k == 0 {
                f.zero(sign)
            } else {
                round_pack(env, f, sign, 0, k)
            }
        }
        v => pack_val(env, f, v),
    }
}

/// `flog2`: `floor(log2(a))` as a float. Zero gives -inf (Divide-by-zero); negative
/// values give the default NaN (Invalid).
pub fn log2(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a]) {
        return n;
    }
    match unpack(env, f, a) {
        Val::Zero(_) => {
            env.flags |= FLAG_Z;
            f.inf(true)
        }
        Val::Inf(false) => f.inf(false),
        Val::Fin {
            sign: false, exp, ..
        } => from_int(env, f, (exp + 62) as i128),
        _ => invalid(env, f),
    }
}

/// `fexp2`: `a * 2^n`.
pub fn exp2(env: &mut Env, f: Fmt, a: u64, n: i64) -> u64 {
    if let Some(r) = propagate_nan(env, f, &[a]) {
        return r;
    }
    match unpack(env, f, a) {
        Val::Fin { sign, exp, mant } => {
            let e = (exp as i64).saturating_add(n).clamp(-100_000, 100_000) as i32;
            round_pack(env, f, sign, e, mant as u128)
        }
        v => pack_val(env, f, v),
    }
}

/// Converts between formats (`fexupl/r` widen exactly, `fexdo` narrows with rounding).
/// NaNs keep their sign and the top of their payload and are quieted.
pub fn convert(env: &mut Env, from: Fmt, to: Fmt, a: u64) -> u64 {
    match unpack(env, from, a) {
        Val::Nan { signaling } => {
            if signaling {
                env.flags |= FLAG_V;
            }
            let frac = a & ((1u64 << from.frac_bits()) - 1);
            let payload = if to.frac_bits() >= from.frac_bits() {
                frac << (to.frac_bits() - from.frac_bits())
            } else {
                frac >> (from.frac_bits() - to.frac_bits())
            };
            to.inf(a & from.sign_bit() != 0) | payload | to.quiet_bit()
        }
        v => pack_val(env, to, v),
    }
}

/// `frcp`: correctly rounded `1 / a` (flags as described in the module docs).
pub fn rcp(env: &mut Env, f: Fmt, a: u64) -> u64 {
    let mut e = Env { flags: 0, ..*env };
    let r = reciprocal(&mut e, f, a);
    env.flags |= e.flags;
    r
}

/// `frsqrt`: `1 / sqrt(a)` as two correctly rounded steps.
pub fn rsqrt(env: &mut Env, f: Fmt, a: u64) -> u64 {
    let mut e = Env { flags: 0, ..*env };
    let s = sqrt(&mut e, f, a);
    let r = reciprocal(&mut e, f, s);
    env.flags |= e.flags;
    r
}

/// `1 / a` with the approximate-reciprocal flag rule; `env.flags` must start empty.
fn reciprocal(env: &mut Env, f: Fmt, a: u64) -> u64 {
    let one = (f.bias() as u64) << f.frac_bits();
    let r = div(env, f, one, a);
    let a_inf = a & !f.sign_bit() == f.inf(false);
    let r_qnan = (r >> f.frac_bits()) & f.exp_mask() == f.exp_mask() && r & f.quiet_bit() != 0;
    if !a_inf && !r_qnan && env.flags & (FLAG_V | FLAG_Z) == 0 {
        env.flags = FLAG_I;
    }
    r
}

/// `ffql/ffqr`: fixed-point `q` with `frac` fraction bits (Q15 or Q31) to float, exact.
pub fn from_fixed(env: &mut Env, f: Fmt, q: i64, frac: i32) -> u64 {
    round_pack(env, f, q < 0, -frac, q.unsigned_abs() as u128)
}

/// `ftq`: float to fixed point with `frac` fraction bits in `bits`-wide lanes, rounding
/// per the environment; NaN gives 0 (Invalid), out-of-range saturates (Overflow, Inexact).
pub fn to_fixed(env: &mut Env, f: Fmt, a: u64, frac: i32, bits: u32) -> u64 {
    let v = match unpack(env, f, a) {
        Val::Fin { sign, exp, mant } => Val::Fin {
            sign,
            exp: exp + frac,
            mant,
        },
        v => v,
    };
    let mode = env.mode;
    val_to_int(env, v, mode, true, bits, FLAG_O | FLAG_I)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env() -> Env {
        Env {
            mode: Round::Nearest,
            ftz: false,
            trap_underflow: false,
            flags: 0,
        }
    }

    #[test]
    fn add_matches_host() {
        let mut e = env();
        let r = add(
            &mut e,
            Fmt::S,
            1.5f32.to_bits() as u64,
            2.25f32.to_bits() as u64,
        );
        assert_eq!(f32::from_bits(r as u32), 3.75);
        assert_eq!(e.flags, 0);
        let r = add(&mut e, Fmt::D, 0.1f64.to_bits(), 0.2f64.to_bits());
        assert_eq!(f64::from_bits(r), 0.1 + 0.2);
        assert_eq!(e.flags, FLAG_I);
    }

    #[test]
    fn directed_rounding() {
        let mut e = Env {
            mode: Round::Down,
            ..env()
        };
        let r = div(&mut e, Fmt::S, 1f32.to_bits() as u64, 3f32.to_bits() as u64);
        // 1/3 rounds up to nearest (0x3EAAAAAB), so rounding down is one ulp lower.
        assert_eq!(r as u32, (1f32 / 3.0).to_bits() - 1);
        e.mode = Round::Up;
        let r = div(&mut e, Fmt::S, 1f32.to_bits() as u64, 3f32.to_bits() as u64);
        assert_eq!(r as u32, (1f32 / 3.0).to_bits());
    }

    #[test]
    fn half_conversion() {
        let mut e = env();
        assert_eq!(
            convert(&mut e, Fmt::S, Fmt::H, 1.0f32.to_bits() as u64),
            0x3C00
        );
        assert_eq!(
            convert(&mut e, Fmt::H, Fmt::S, 0x3C00) as u32,
            1.0f32.to_bits()
        );
        assert_eq!(
            convert(&mut e, Fmt::S, Fmt::H, 65520f32.to_bits() as u64),
            0x7C00
        );
    }
}
