//! The exact path of the soft-float core: operands are unpacked to integers, the
//! operation is computed exactly (128-bit intermediates) and rounded once. Used whenever
//! the host fast paths ([`super::fast`]) cannot vouch for their result.

use std::cmp::Ordering;

use super::{
    Env, Fmt, MinMax, Round, FLAG_I, FLAG_O, FLAG_U, FLAG_V, FLAG_Z, REL_EQ, REL_LT, REL_UN,
};

/// An unpacked operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Val {
    Nan { signaling: bool },
    Inf(bool),
    Zero(bool),
    Fin(Fin),
}

/// A finite nonzero value `(-1)^sign * mant * 2^exp` with bit 62 of `mant` set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Fin {
    sign: bool,
    exp: i32,
    mant: u64,
}

impl Fin {
    /// (sign, exponent, mantissa) with a 128-bit mantissa, for [`add_fin`].
    fn wide(self) -> (bool, i32, u128) {
        (self.sign, self.exp, self.mant as u128)
    }

    /// The exact product, as [`Fin::wide`].
    fn times(self, o: Fin) -> (bool, i32, u128) {
        (
            self.sign ^ o.sign,
            self.exp + o.exp,
            self.mant as u128 * o.mant as u128,
        )
    }
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
    Val::Fin(Fin {
        sign,
        exp: exp - s,
        mant: mant << s,
    })
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
        Val::Fin(x) => round_pack(env, f, x.sign, x.exp, x.mant as u128),
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

#[inline]
pub(super) fn add_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a, b]) {
        return n;
    }
    match (unpack(env, f, a), unpack(env, f, b)) {
        (Val::Inf(x), Val::Inf(y)) if x != y => invalid(env, f),
        (Val::Inf(x), _) | (_, Val::Inf(x)) => f.inf(x),
        (Val::Zero(x), Val::Zero(y)) => f.zero(if x == y { x } else { env.mode == Round::Down }),
        (Val::Zero(_), v) | (v, Val::Zero(_)) => pack_val(env, f, v),
        (Val::Fin(x), Val::Fin(y)) => add_fin(env, f, x.wide(), y.wide()),
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

#[inline]
pub(super) fn sub_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a, b]) {
        return n;
    }
    add_exact(env, f, a, neg_unless_nan(f, b))
}

#[inline]
pub(super) fn mul_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a, b]) {
        return n;
    }
    match (unpack(env, f, a), unpack(env, f, b)) {
        (Val::Inf(_), Val::Zero(_)) | (Val::Zero(_), Val::Inf(_)) => invalid(env, f),
        (Val::Inf(x), v) | (v, Val::Inf(x)) => f.inf(x ^ sign_of(v)),
        (Val::Zero(x), v) | (v, Val::Zero(x)) => f.zero(x ^ sign_of(v)),
        (Val::Fin(x), Val::Fin(y)) => {
            let (sign, exp, mant) = x.times(y);
            round_pack(env, f, sign, exp, mant)
        }
        _ => f.default_nan(),
    }
}

fn sign_of(v: Val) -> bool {
    match v {
        Val::Nan { .. } => false,
        Val::Inf(s) | Val::Zero(s) => s,
        Val::Fin(x) => x.sign,
    }
}

#[inline]
pub(super) fn div_exact(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
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
        (Val::Fin(x), Val::Fin(y)) => {
            let n = (x.mant as u128) << 64;
            let q = n / y.mant as u128;
            let r = n % y.mant as u128;
            round_pack(
                env,
                f,
                x.sign ^ y.sign,
                x.exp - 64 - y.exp,
                q | (r != 0) as u128,
            )
        }
        _ => f.default_nan(),
    }
}

#[inline]
pub(super) fn sqrt_exact(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a]) {
        return n;
    }
    match unpack(env, f, a) {
        Val::Zero(s) => f.zero(s),
        Val::Inf(false) => f.inf(false),
        Val::Fin(Fin {
            sign: false,
            exp,
            mant,
        }) => {
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

#[inline]
pub(super) fn fma_exact(env: &mut Env, f: Fmt, a: u64, b: u64, c: u64, negate: bool) -> u64 {
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
        (false, vc) => match (va, vb, vc) {
            (Val::Fin(x), Val::Fin(y), Val::Zero(_)) => {
                let (_, exp, mant) = x.times(y);
                round_pack(env, f, psign, exp, mant)
            }
            (Val::Fin(x), Val::Fin(y), Val::Fin(z)) => {
                let (_, exp, mant) = x.times(y);
                add_fin(env, f, (psign, exp, mant), z.wide())
            }
            _ => f.default_nan(),
        },
    }
}

/// [`super::compare`] on unpacked operands.
#[inline]
pub(super) fn compare_exact(env: &mut Env, f: Fmt, a: u64, b: u64, signaling: bool) -> u8 {
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
        return REL_UN;
    }
    match total_key(va).cmp(&total_key(vb)) {
        Ordering::Less => REL_LT,
        Ordering::Equal => REL_EQ,
        Ordering::Greater => 0,
    }
}

/// A key ordering non-NaN values numerically (both zeros equal).
fn total_key(v: Val) -> (i32, i64, i64) {
    match v {
        Val::Zero(_) | Val::Nan { .. } => (0, 0, 0),
        Val::Inf(s) => (if s { -2 } else { 2 }, 0, 0),
        Val::Fin(Fin { sign, exp, mant }) => {
            let k = (exp as i64, mant as i64);
            if sign {
                (-1, -k.0, -k.1)
            } else {
                (1, k.0, k.1)
            }
        }
    }
}

/// [`super::min_max`] on unpacked operands (NaN operands, flush to zero, binary16).
#[inline]
pub(super) fn min_max_exact(env: &mut Env, f: Fmt, a: u64, b: u64, kind: MinMax) -> u64 {
    // Picking an operand never underflows, even when it is subnormal.
    let u = env.flags & FLAG_U;
    let r = min_max_unpacked(env, f, a, b, kind);
    env.flags = (env.flags & !FLAG_U) | u;
    r
}

fn min_max_unpacked(env: &mut Env, f: Fmt, a: u64, b: u64, kind: MinMax) -> u64 {
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
        Val::Fin(x) => total_key(Val::Fin(Fin { sign: false, ..x })),
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

/// [`super::to_int`] on the unpacked operand.
#[inline]
pub(super) fn to_int_exact(
    env: &mut Env,
    f: Fmt,
    a: u64,
    mode: Round,
    signed: bool,
    bits: u32,
) -> u64 {
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
        Val::Fin(Fin { sign, exp, mant }) => {
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

/// [`super::from_int`] by rounding the integer's bits.
#[inline]
pub(super) fn from_int_exact(env: &mut Env, f: Fmt, v: i128) -> u64 {
    round_pack(env, f, v < 0, 0, v.unsigned_abs())
}

/// [`super::rint`] on the unpacked operand.
#[inline]
pub(super) fn rint_exact(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if let Some(n) = propagate_nan(env, f, &[a]) {
        return n;
    }
    match unpack(env, f, a) {
        Val::Fin(Fin { sign, exp, mant }) if exp < 0 => {
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
        Val::Fin(Fin {
            sign: false, exp, ..
        }) => super::from_int(env, f, (exp + 62) as i128),
        _ => invalid(env, f),
    }
}

/// `fexp2`: `a * 2^n`.
pub fn exp2(env: &mut Env, f: Fmt, a: u64, n: i64) -> u64 {
    if let Some(r) = propagate_nan(env, f, &[a]) {
        return r;
    }
    match unpack(env, f, a) {
        Val::Fin(Fin { sign, exp, mant }) => {
            let e = (exp as i64).saturating_add(n).clamp(-100_000, 100_000) as i32;
            round_pack(env, f, sign, e, mant as u128)
        }
        v => pack_val(env, f, v),
    }
}

/// [`super::convert`] on the unpacked operand.
#[inline]
pub(super) fn convert_exact(env: &mut Env, from: Fmt, to: Fmt, a: u64) -> u64 {
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
    let s = super::sqrt(&mut e, f, a);
    let r = reciprocal(&mut e, f, s);
    env.flags |= e.flags;
    r
}

/// `1 / a` with the approximate-reciprocal flag rule; `env.flags` must start empty.
fn reciprocal(env: &mut Env, f: Fmt, a: u64) -> u64 {
    let one = (f.bias() as u64) << f.frac_bits();
    let r = super::div(env, f, one, a);
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
        Val::Fin(x) => Val::Fin(Fin {
            exp: x.exp + frac,
            ..x
        }),
        v => v,
    };
    let mode = env.mode;
    val_to_int(env, v, mode, true, bits, FLAG_O | FLAG_I)
}
