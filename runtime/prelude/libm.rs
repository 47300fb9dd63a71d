//! Elementary functions for `f32` and `f64` with C libm names (`trax::libm`).
//!
//! Written once, in TRaX-Rust, from IEEE basic operations only (`+ - * /`, `sqrt`,
//! `mul_add` = fused multiply-add, comparisons, bit casts, integer operations): the trax
//! compiler builds it for the machine and rustc for `trax native`, and both give the same
//! bits for every input. Nothing here calls the host's libm.
//!
//! Accuracy (see `runtime/tests/libm_host.rs` and `runtime/benches/libm_ulp.rs`): the f32
//! functions evaluate in f64 and round once, so they are within 0.51 ULP (correctly
//! rounded for the overwhelming majority of inputs); the f64 functions are within 1 ULP.
//! Special values follow C99 Annex F (NaN, ±0, ±inf, overflow, underflow, the special
//! cases of `pow` and `atan2`). A NaN input comes back quieted; an invalid operation
//! (`sin(inf)`, `log(-1)`, `pow(-8, 1/3)`, ...) returns the default NaN `0x7FC00000` /
//! `0x7FF8000000000000`; NaNs are never produced by arithmetic, so their bits are the
//! same on every host.
//!
//! Methods:
//! - sin, cos, tan: argument reduction by `pi/2` (Cody-Waite with fused multiply-adds
//!   and `pi/2` in 53-bit parts, two for f32 below 2^28, three and a double-length result
//!   for f64 below 2^30; above that an exact Payne-Hanek reduction with 1280 bits of
//!   `2/pi`, correct for every finite input of both types, huge f64 arguments included),
//!   then minimax polynomials on `[-pi/4, pi/4]`; tan = sin/cos (f64: with a
//!   double-length quotient).
//! - atan2, atan, asin, acos: f32 through an f64 `atan` on `[0, tan(pi/8)]`; f64 through
//!   `atan(k/16)` tables and a double-length reduced argument; f64 asin/acos through a
//!   polynomial on `[0, 1/2]` and `asin(x) = pi/2 - 2 asin(sqrt((1-x)/2))`.
//! - exp, exp2: `2^(j/64)` table (double-length) and a short polynomial; subnormal
//!   results are rounded once.
//! - log, log2, log10: `x = 2^e m`, `m` in `[sqrt(1/2), sqrt(2))`,
//!   `ln m = 2 atanh(f / (2 + f))`; pow: the same with a double-length `ln x`, times `y`
//!   in double length, then the exp core.
//! - hypot: f64 with a double-length sum of squares and a corrected square root; scaled,
//!   so it never overflows or loses precision to underflow.
//! - cbrt: exponent divided by 3, two Halley steps (f64: plus a Newton step with an
//!   exact residual).
//! - powi: `powif` multiplies in f64 for `|n| <= 64`, else `powf`; `powi(x, n)` is
//!   `pow(x, n)`.
//!
//! Coefficients and tables come from `tools/libm_coeffs.py` (mpmath, Remez exchange);
//! the generated block at the end of this file is its verbatim output.

// The generated constants include the f64 roundings of pi/2, ln 2, sqrt 2, ...
#![allow(clippy::approx_constant)]

// ---------------------------------------------------------------------------------------
// Helpers

/// A double-length value `hi + lo`, `|lo| <= ulp(hi) / 2` (roughly).
#[derive(Clone, Copy)]
struct Dd {
    hi: f64,
    lo: f64,
}

/// 1.5 * 2^52: `(x + SHIFT) - SHIFT` rounds `|x| < 2^51` to an integer, and the low
/// 32 bits of `x + SHIFT` are that integer.
const SHIFT: f64 = 6755399441055744.0;
const INF32: u32 = 0x7F80_0000;
const INF64: u64 = 0x7FF0_0000_0000_0000;
const ABS64: u64 = 0x7FFF_FFFF_FFFF_FFFF;

#[inline]
fn fma(a: f64, b: f64, c: f64) -> f64 {
    a.mul_add(b, c)
}

/// `a + b` exactly (Knuth).
#[inline]
fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    Dd {
        hi: s,
        lo: (a - (s - bb)) + (b - bb),
    }
}

/// `a + b` exactly when `|a| >= |b|` or `a == 0` (Dekker).
#[inline]
fn fast_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd {
        hi: s,
        lo: b - (s - a),
    }
}

/// `a * b` exactly.
#[inline]
fn two_prod(a: f64, b: f64) -> Dd {
    let p = a * b;
    Dd {
        hi: p,
        lo: fma(a, b, -p),
    }
}

/// 2^e for -1022 <= e <= 1023.
#[inline]
fn pow2(e: i32) -> f64 {
    f64::from_bits(((e + 1023) as u64) << 52)
}

#[inline]
fn nan32() -> f32 {
    f32::from_bits(0x7FC0_0000)
}

#[inline]
fn nan64() -> f64 {
    f64::from_bits(0x7FF8_0000_0000_0000)
}

/// `x` (a NaN) with its quiet bit set.
#[inline]
fn quiet32(x: f32) -> f32 {
    f32::from_bits(x.to_bits() | 0x0040_0000)
}

#[inline]
fn quiet64(x: f64) -> f64 {
    f64::from_bits(x.to_bits() | 0x0008_0000_0000_0000)
}

#[inline]
fn neg_if32(neg: bool, x: f32) -> f32 {
    if neg {
        -x
    } else {
        x
    }
}

#[inline]
fn neg_if64(neg: bool, x: f64) -> f64 {
    if neg {
        -x
    } else {
        x
    }
}

// ---------------------------------------------------------------------------------------
// Argument reduction by pi/2

/// Payne-Hanek: for finite `|x| >= 2^20`, `x = n pi/2 + r` with `|r| <= pi/4`; writes
/// `r` (double length) and returns `n mod 4`. Exact up to the final roundings: the
/// product of the 53-bit mantissa with a 224-bit window of `2/pi` keeps 128 bits after
/// the binary point, which covers the deepest cancellation of any double (about 2^-61).
#[inline(never)]
fn rem_pio2_large(x: f64, out: &mut Dd) -> i32 {
    let bits = x.to_bits();
    let m = (bits & 0x000F_FFFF_FFFF_FFFF) | 0x0010_0000_0000_0000;
    // |x| = m * 2^e.
    let e = ((bits >> 52) & 0x7FF) as i32 - 1075;
    // Words of 2/pi before k0 only add multiples of 4 to x * 2/pi.
    let k0 = if e > 2 { (e - 2) >> 5 } else { 0 };
    let m0 = (m as u32) as u64;
    let m1 = m >> 32;
    let mut acc = [0u32; 9];
    let mut carry = 0u64;
    let mut i = 0;
    while i < 7 {
        let w = TWO_OVER_PI[(k0 + 6 - i) as usize] as u64;
        let t = m0 * w + carry;
        acc[i as usize] = t as u32;
        carry = t >> 32;
        i += 1;
    }
    acc[7] = carry as u32;
    carry = 0;
    i = 0;
    while i < 7 {
        let w = TWO_OVER_PI[(k0 + 6 - i) as usize] as u64;
        let t = m1 * w + acc[(i + 1) as usize] as u64 + carry;
        acc[(i + 1) as usize] = t as u32;
        carry = t >> 32;
        i += 1;
    }
    acc[8] = carry as u32;
    // The binary point of acc is at bit s.
    let s = 32 * (k0 + 7) - e;
    let mut q = bits32(&acc, s) & 3;
    let mut f0 = bits32(&acc, s - 32);
    let mut f1 = bits32(&acc, s - 64);
    let mut f2 = bits32(&acc, s - 96);
    let mut f3 = bits32(&acc, s - 128);
    let mut neg = false;
    if f0 >= 0x8000_0000 {
        // Round n up; the fraction becomes f - 1 = -(2^128 - F) / 2^128.
        q += 1;
        neg = true;
        f0 = !f0;
        f1 = !f1;
        f2 = !f2;
        f3 = !f3;
        f3 = f3.wrapping_add(1);
        if f3 == 0 {
            f2 = f2.wrapping_add(1);
            if f2 == 0 {
                f1 = f1.wrapping_add(1);
                if f1 == 0 {
                    f0 = f0.wrapping_add(1);
                }
            }
        }
    }
    // Normalise the 128-bit fraction (it is never below 2^-100).
    let mut sh = 0i32;
    while f0 == 0 && sh < 96 {
        f0 = f1;
        f1 = f2;
        f2 = f3;
        f3 = 0;
        sh += 32;
    }
    let lz = f0.leading_zeros();
    if lz > 0 && lz < 32 {
        f0 = (f0 << lz) | (f1 >> (32 - lz));
        f1 = (f1 << lz) | (f2 >> (32 - lz));
        f2 = (f2 << lz) | (f3 >> (32 - lz));
        f3 <<= lz;
        sh += lz as i32;
    }
    // The fraction as hi + lo (hi: the top 53 bits, exact).
    let a = (f0 as f64) * 4294967296.0 + ((f1 & 0xFFFF_F800) as f64);
    let b = ((f1 & 0x7FF) as f64) * 4294967296.0 + (f2 as f64);
    let scale = pow2(-64 - sh);
    let hi = a * scale;
    let lo = (b * 2.3283064365386963e-10 + (f3 as f64) * 5.421010862427522e-20) * scale;
    // r = fraction * pi/2.
    let p = hi * PIO2_HI;
    let pe = fma(hi, PIO2_HI, -p) + (hi * PIO2_LO + lo * PIO2_HI);
    let mut r = fast_two_sum(p, pe);
    if neg != (x < 0.0) {
        r.hi = -r.hi;
        r.lo = -r.lo;
    }
    *out = r;
    let n = q as i32;
    if x < 0.0 {
        -n
    } else {
        n
    }
}

/// Bits `pos .. pos + 32` of the little-endian 288-bit number `acc` (0 outside it).
fn bits32(acc: &[u32; 9], pos: i32) -> u32 {
    let w = pos >> 5;
    let b = (pos & 31) as u32;
    // (w as u32) < 9 also rejects a negative w.
    let lo = if (w as u32) < 9 { acc[w as usize] } else { 0 };
    let hi = if ((w + 1) as u32) < 9 {
        acc[(w + 1) as usize]
    } else {
        0
    };
    if b == 0 {
        lo
    } else {
        (lo >> b) | (hi << (32 - b))
    }
}

/// For pi/4 < |x| < 2^30: `x = n pi/2 + r`, `r` double length; returns `n`. n * PIO2_1
/// is exact inside the fma, x - n * PIO2_1 is a multiple of 2^-52 below 1 (or Sterbenz
/// for |x| < 1), so r1 is exact; the next two parts of pi/2 are subtracted in double
/// length.
#[inline]
fn rem_pio2(x: f64, r: &mut Dd) -> u32 {
    let t = fma(x, INV_PIO2, SHIFT);
    let n = t - SHIFT;
    let r1 = fma(-n, PIO2_1, x);
    let th = n * PIO2_2;
    let tl = fma(n, PIO2_2, -th);
    let s = two_sum(r1, -th);
    let lo = (s.lo - tl) - n * PIO2_3;
    *r = fast_two_sum(s.hi, lo);
    t.to_bits() as u32
}

// ---------------------------------------------------------------------------------------
// f32 trigonometry (evaluated in f64)

/// sin(r), |r| <= pi/4 (relative error 2^-37.5); r != -0.
#[inline]
fn sinf_k(r: f64) -> f64 {
    let z = r * r;
    let p = fma(z, fma(z, fma(z, SINF_3, SINF_2), SINF_1), SINF_0);
    fma(r * z, p, r)
}

/// cos(r), |r| <= pi/4 (relative error 2^-33.9).
#[inline]
fn cosf_k(r: f64) -> f64 {
    let z = r * r;
    fma(
        z,
        fma(z, fma(z, fma(z, COSF_3, COSF_2), COSF_1), COSF_0),
        1.0,
    )
}

/// f32 bits of 2^28: below it `rem_pio2f` reduces, from it up Payne-Hanek.
const BIG32: u32 = 0x4D80_0000;

/// For a nonzero f32 `x` (held exactly in f64) with |x| < 2^28: x = n pi/2 + r; writes
/// r, returns n (its low two bits are the quadrant). n * PIO2_1 is exact inside the fma
/// and x - n PIO2_1 is a multiple of 2^-52 below 2 (x is an f32), so r1 is exact; the
/// third part of pi/2 would change r by at most 2^-81, 2^-46 of the smallest |r| of an
/// f32 argument.
#[inline]
fn rem_pio2f(x: f64, r: &mut f64) -> u32 {
    let t = fma(x, INV_PIO2, SHIFT);
    let m = SHIFT - t;
    *r = fma(m, PIO2_2, fma(m, PIO2_1, x));
    t.to_bits() as u32
}

/// sin (`which` 0), cos (1) or tan (2) of an f32 that is ±0, at least 2^28 in
/// magnitude, infinite or NaN.
#[inline(never)]
fn trigf_rare(x: f32, which: u32) -> f32 {
    let ax = x.to_bits() & 0x7FFF_FFFF;
    if ax == 0 {
        return if which == 1 { 1.0 } else { x };
    }
    if ax >= INF32 {
        return if ax == INF32 { nan32() } else { quiet32(x) };
    }
    let mut d = Dd { hi: 0.0, lo: 0.0 };
    let n = rem_pio2_large(x as f64, &mut d) as u32;
    let r = d.hi;
    if which == 2 {
        let t = if n & 1 == 0 {
            sinf_k(r) / cosf_k(r)
        } else {
            -cosf_k(r) / sinf_k(r)
        };
        return t as f32;
    }
    let q = n + which;
    let v = if q & 1 == 0 { sinf_k(r) } else { cosf_k(r) };
    neg_if32(q & 2 != 0, v as f32)
}

/// Sine of `x` (radians).
#[inline]
pub fn sinf(x: f32) -> f32 {
    // One compare sends ±0, |x| >= 2^28, infinities and NaNs to the rare path.
    if (x.to_bits() & 0x7FFF_FFFF).wrapping_sub(1) >= BIG32 - 1 {
        return trigf_rare(x, 0);
    }
    let mut r = 0.0;
    let n = rem_pio2f(x as f64, &mut r);
    let v = if n & 1 == 0 { sinf_k(r) } else { cosf_k(r) };
    neg_if32(n & 2 != 0, v as f32)
}

/// Cosine of `x` (radians).
#[inline]
pub fn cosf(x: f32) -> f32 {
    if (x.to_bits() & 0x7FFF_FFFF).wrapping_sub(1) >= BIG32 - 1 {
        return trigf_rare(x, 1);
    }
    let mut r = 0.0;
    let n = rem_pio2f(x as f64, &mut r).wrapping_add(1);
    let v = if n & 1 == 0 { sinf_k(r) } else { cosf_k(r) };
    neg_if32(n & 2 != 0, v as f32)
}

/// Sine and cosine of `x` with one argument reduction.
#[inline]
pub fn sincosf(x: f32, s: &mut f32, c: &mut f32) {
    if (x.to_bits() & 0x7FFF_FFFF).wrapping_sub(1) >= BIG32 - 1 {
        *s = trigf_rare(x, 0);
        *c = trigf_rare(x, 1);
        return;
    }
    let mut r = 0.0;
    let n = rem_pio2f(x as f64, &mut r);
    let sv = sinf_k(r) as f32;
    let cv = cosf_k(r) as f32;
    if n & 1 == 0 {
        *s = neg_if32(n & 2 != 0, sv);
        *c = neg_if32(n.wrapping_add(1) & 2 != 0, cv);
    } else {
        *s = neg_if32(n & 2 != 0, cv);
        *c = neg_if32(n.wrapping_add(1) & 2 != 0, sv);
    }
}

/// Tangent of `x` (radians).
#[inline]
pub fn tanf(x: f32) -> f32 {
    if (x.to_bits() & 0x7FFF_FFFF).wrapping_sub(1) >= BIG32 - 1 {
        return trigf_rare(x, 2);
    }
    let mut r = 0.0;
    let n = rem_pio2f(x as f64, &mut r);
    let s = sinf_k(r);
    let c = cosf_k(r);
    let t = if n & 1 == 0 { s / c } else { -c / s };
    t as f32
}

// ---------------------------------------------------------------------------------------
// f32 inverse trigonometry (evaluated in f64)

/// |x| below which asin x and atan x round to x (f32: 2^-12).
const TINY32: u32 = 0x3980_0000;

/// atan(u / v) for finite 0 <= u <= v, v > 0 (relative error about 2^-33).
#[inline]
fn atanf_k(u: f64, v: f64) -> f64 {
    let mut num = u;
    let mut den = v;
    let mut base = 0.0;
    if u > v * TAN_PIO8 {
        // atan(t) = pi/4 + atan((t - 1) / (t + 1)).
        num = u - v;
        den = u + v;
        base = ATAN_TAB[32];
    }
    let t = num / den;
    let z = t * t;
    let p = fma(
        z,
        fma(z, fma(z, fma(z, ATANF_5, ATANF_4), ATANF_3), ATANF_2),
        ATANF_1,
    );
    let p = fma(z, p, ATANF_0);
    base + fma(t * z, p, t)
}

/// atan(|y| / |x|) in [0, pi/2] for finite |y|, |x| >= 0 not both 0.
#[inline]
fn atan2f_k(ay: f64, ax: f64) -> f64 {
    if ay <= ax {
        atanf_k(ay, ax)
    } else {
        PIO2_HI - atanf_k(ax, ay)
    }
}

/// Arc tangent of `y / x` in `[-pi, pi]`, using the signs of both to pick the quadrant.
#[inline]
pub fn atan2f(y: f32, x: f32) -> f32 {
    let ay = y.to_bits() & 0x7FFF_FFFF;
    let ax = x.to_bits() & 0x7FFF_FFFF;
    if ay.wrapping_sub(1) >= INF32 - 1 || ax.wrapping_sub(1) >= INF32 - 1 {
        return atan2f_rare(y, x);
    }
    let t = atan2f_k(f32::from_bits(ay) as f64, f32::from_bits(ax) as f64);
    let a = if x.to_bits() >> 31 != 0 { PI_HI - t } else { t };
    neg_if32(y.to_bits() >> 31 != 0, a as f32)
}

/// atan2f when either operand is ±0, infinite or NaN.
#[inline(never)]
fn atan2f_rare(y: f32, x: f32) -> f32 {
    if y.is_nan() {
        return quiet32(y);
    }
    if x.is_nan() {
        return quiet32(x);
    }
    let yneg = y.to_bits() >> 31 != 0;
    let xneg = x.to_bits() >> 31 != 0;
    let ay = y.to_bits() & 0x7FFF_FFFF;
    let ax = x.to_bits() & 0x7FFF_FFFF;
    let a = if ay == 0 {
        if !xneg {
            return y;
        }
        PI_HI
    } else if ax == 0 {
        PIO2_HI
    } else if ay == INF32 {
        if ax == INF32 {
            if xneg {
                THREE_PIO4_HI
            } else {
                ATAN_TAB[32]
            }
        } else {
            PIO2_HI
        }
    } else if xneg {
        // x = -inf, y finite.
        PI_HI
    } else {
        0.0
    };
    neg_if32(yneg, a as f32)
}

/// Arc tangent of `x`, in `[-pi/2, pi/2]`.
#[inline]
pub fn atanf(x: f32) -> f32 {
    let ax = x.to_bits() & 0x7FFF_FFFF;
    if ax.wrapping_sub(TINY32) >= INF32 - TINY32 {
        // Tiny (atan x rounds to x), infinite or NaN.
        return if ax < TINY32 {
            x
        } else if ax == INF32 {
            neg_if32(x.to_bits() >> 31 != 0, PIO2_HI as f32)
        } else {
            quiet32(x)
        };
    }
    let a = atan2f_k(f32::from_bits(ax) as f64, 1.0);
    neg_if32(x.to_bits() >> 31 != 0, a as f32)
}

/// Arc sine of `x` in `[-pi/2, pi/2]`; NaN outside `[-1, 1]`.
#[inline]
pub fn asinf(x: f32) -> f32 {
    let ax = x.to_bits() & 0x7FFF_FFFF;
    if ax.wrapping_sub(TINY32) > 0x3F80_0000 - TINY32 {
        // Tiny (asin x rounds to x), |x| > 1 or NaN.
        return if ax < TINY32 {
            x
        } else if ax > INF32 {
            quiet32(x)
        } else {
            nan32()
        };
    }
    let u = f32::from_bits(ax) as f64;
    // 1 - u^2 is exact or correctly rounded (u^2 has 48 bits).
    let v = fma(-u, u, 1.0).sqrt();
    neg_if32(x.to_bits() >> 31 != 0, atan2f_k(u, v) as f32)
}

/// Arc cosine of `x` in `[0, pi]`; NaN outside `[-1, 1]`.
#[inline]
pub fn acosf(x: f32) -> f32 {
    let ax = x.to_bits() & 0x7FFF_FFFF;
    if ax > 0x3F80_0000 {
        return if ax > INF32 { quiet32(x) } else { nan32() };
    }
    let u = f32::from_bits(ax) as f64;
    let v = fma(-u, u, 1.0).sqrt();
    let a = atan2f_k(v, u);
    let a = if x.to_bits() >> 31 != 0 { PI_HI - a } else { a };
    a as f32
}

// ---------------------------------------------------------------------------------------
// f32 exponentials and logarithms (evaluated in f64)

/// 2^y for -160 < y < 160 (relative error about 2^-38).
#[inline]
fn exp2f_k(y: f64) -> f64 {
    let t = y * 64.0 + SHIFT;
    let k = t.to_bits() as u32 as i32;
    // r = y - k/64 is exact, |r| <= 1/128.
    let r = y - (t - SHIFT) * 0.015625;
    let p = fma(r, fma(r, fma(r, EXP2F_2, EXP2F_1), EXP2F_0), 1.0);
    let j = (k & 63) as usize;
    EXP_TAB[2 * j] * p * pow2(k >> 6)
}

/// `2^x`.
#[inline]
pub fn exp2f(x: f32) -> f32 {
    // |x| < 126: a normal result, no special case.
    if x.to_bits() & 0x7FFF_FFFF >= 0x42FC_0000 {
        return exp2f_rare(x);
    }
    exp2f_k(x as f64) as f32
}

/// exp2f for |x| >= 126, infinities and NaN.
#[inline(never)]
fn exp2f_rare(x: f32) -> f32 {
    if x.is_nan() {
        return quiet32(x);
    }
    if x >= 128.0 {
        return f32::from_bits(INF32);
    }
    if x < -151.0 {
        return 0.0;
    }
    exp2f_k(x as f64) as f32
}

/// `e^x`.
#[inline]
pub fn expf(x: f32) -> f32 {
    // |x| < 87: a normal result, no special case.
    if x.to_bits() & 0x7FFF_FFFF >= 0x42AE_0000 {
        return expf_rare(x);
    }
    exp2f_k(x as f64 * LOG2E_HI) as f32
}

/// expf for |x| >= 87, infinities and NaN.
#[inline(never)]
fn expf_rare(x: f32) -> f32 {
    if x.is_nan() {
        return quiet32(x);
    }
    if x > 89.0 {
        return f32::from_bits(INF32);
    }
    if x < -104.0 {
        return 0.0;
    }
    exp2f_k(x as f64 * LOG2E_HI) as f32
}

/// ln(m) for x = 2^e m, m in [sqrt(1/2), sqrt(2)); x positive, finite, normal in f64,
/// with at most 24 significant bits (so 2 + f is exact). Relative error 2^-44.9.
#[inline]
fn logf_k(x: f64, e: &mut f64) -> f64 {
    let bits = x.to_bits();
    let hx = (bits >> 32) as u32 + (0x3FF0_0000 - 0x3FE6_A09E);
    *e = ((hx >> 20) as i32 - 1023) as f64;
    let hm = (hx & 0x000F_FFFF) + 0x3FE6_A09E;
    let m = f64::from_bits(((hm as u64) << 32) | (bits & 0xFFFF_FFFF));
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let p = fma(
        z,
        fma(z, fma(z, fma(z, LOGF_4, LOGF_3), LOGF_2), LOGF_1),
        LOGF_0,
    );
    fma(s * z, p, s + s)
}

/// True for a positive, finite, normal f32 (the logarithms' common case).
#[inline]
fn pos_normal32(x: f32) -> bool {
    x.to_bits().wrapping_sub(0x0080_0000) < INF32 - 0x0080_0000
}

/// The f32 logarithms when x is not a positive normal number: the special values, and
/// for a subnormal `x` the logarithm `which` (0: ln, 1: log2, 2: log10).
#[inline(never)]
fn logf_rare(x: f32, which: u32) -> f32 {
    if x == 0.0 {
        return -f32::from_bits(INF32);
    }
    if x.is_nan() {
        return quiet32(x);
    }
    if x < 0.0 {
        return nan32();
    }
    if x == f32::from_bits(INF32) {
        return x;
    }
    let mut e = 0.0;
    let l = logf_k(x as f64, &mut e);
    let r = match which {
        0 => fma(e, LN2_HI, l),
        1 => fma(l, LOG2E_HI, e),
        _ => fma(e, LOG10_2_HI, l * LOG10E_HI),
    };
    r as f32
}

/// Natural logarithm.
#[inline]
pub fn logf(x: f32) -> f32 {
    if !pos_normal32(x) {
        return logf_rare(x, 0);
    }
    let mut e = 0.0;
    let l = logf_k(x as f64, &mut e);
    fma(e, LN2_HI, l) as f32
}

/// Base-2 logarithm.
#[inline]
pub fn log2f(x: f32) -> f32 {
    if !pos_normal32(x) {
        return logf_rare(x, 1);
    }
    let mut e = 0.0;
    let l = logf_k(x as f64, &mut e);
    fma(l, LOG2E_HI, e) as f32
}

/// Base-10 logarithm.
#[inline]
pub fn log10f(x: f32) -> f32 {
    if !pos_normal32(x) {
        return logf_rare(x, 2);
    }
    let mut e = 0.0;
    let l = logf_k(x as f64, &mut e);
    fma(e, LOG10_2_HI, l * LOG10E_HI) as f32
}

/// 0: not an integer, 1: odd integer, 2: even integer; `ay` = |y| bits (finite, nonzero).
fn int_class32(ay: u32) -> i32 {
    let e = (ay >> 23) as i32 - 127;
    if e < 0 {
        return 0;
    }
    if e > 23 {
        return 2;
    }
    let sh = (23 - e) as u32;
    if ay & ((1u32 << sh) - 1) != 0 {
        return 0;
    }
    if (ay >> sh) & 1 != 0 {
        1
    } else {
        2
    }
}

/// x^y for finite nonzero `y` of integer class `yint` (see `int_class32`), x not NaN.
fn powf_k(x: f32, y: f64, yint: i32) -> f32 {
    let xneg = x.to_bits() >> 31 != 0;
    let ax = x.to_bits() & 0x7FFF_FFFF;
    let neg = xneg && yint == 1;
    let inf = f32::from_bits(INF32);
    if ax == 0 {
        return neg_if32(neg, if y < 0.0 { inf } else { 0.0 });
    }
    if ax == INF32 {
        return neg_if32(neg, if y < 0.0 { 0.0 } else { inf });
    }
    if xneg && yint == 0 {
        return nan32();
    }
    let mut e = 0.0;
    let l = logf_k(f32::from_bits(ax) as f64, &mut e);
    let w = y * fma(l, LOG2E_HI, e);
    let r = if w >= 128.0 {
        inf
    } else if w < -151.0 {
        0.0
    } else {
        exp2f_k(w) as f32
    };
    neg_if32(neg, r)
}

/// `x` raised to the power `y`.
#[inline]
pub fn powf(x: f32, y: f32) -> f32 {
    let ay = y.to_bits() & 0x7FFF_FFFF;
    if pos_normal32(x) && ay.wrapping_sub(1) < INF32 - 1 {
        // x > 0 normal, y finite nonzero: 2^(y log2 x), no sign, no special case.
        let mut e = 0.0;
        let l = logf_k(x as f64, &mut e);
        let w = y as f64 * fma(l, LOG2E_HI, e);
        return if w >= 128.0 {
            f32::from_bits(INF32)
        } else if w < -151.0 {
            0.0
        } else {
            exp2f_k(w) as f32
        };
    }
    powf_rare(x, y)
}

/// powf when x is not a positive normal number or y is ±0, infinite or NaN.
#[inline(never)]
fn powf_rare(x: f32, y: f32) -> f32 {
    let ay = y.to_bits() & 0x7FFF_FFFF;
    if ay == 0 || x == 1.0 {
        return 1.0;
    }
    if x.is_nan() {
        return quiet32(x);
    }
    if y.is_nan() {
        return quiet32(y);
    }
    if ay == INF32 {
        let ax = x.to_bits() & 0x7FFF_FFFF;
        if ax == 0x3F80_0000 {
            return 1.0;
        }
        return if (ax > 0x3F80_0000) == (y > 0.0) {
            f32::from_bits(INF32)
        } else {
            0.0
        };
    }
    powf_k(x, y as f64, int_class32(ay))
}

/// `x` raised to the integer power `n` (`powif(x, 0) = 1` for every x).
#[inline]
pub fn powif(x: f32, n: i32) -> f32 {
    if n == 0 {
        return 1.0;
    }
    if x.is_nan() {
        return quiet32(x);
    }
    if (n.wrapping_add(64) as u32) <= 128 {
        // |n| <= 64.
        // Square and multiply in f64: at most 13 roundings, relative error < 2^-49.
        let mut b = x as f64;
        let mut e = if n < 0 { -n } else { n } as u32;
        let mut acc = 1.0f64;
        loop {
            if e & 1 != 0 {
                acc *= b;
            }
            e >>= 1;
            if e == 0 {
                break;
            }
            b *= b;
        }
        if n < 0 {
            acc = 1.0 / acc;
        }
        return acc as f32;
    }
    powf_k(x, n as f64, if n & 1 != 0 { 1 } else { 2 })
}

/// `sqrt(x^2 + y^2)` without overflow or underflow.
#[inline]
pub fn hypotf(x: f32, y: f32) -> f32 {
    let ax = x.to_bits() & 0x7FFF_FFFF;
    let ay = y.to_bits() & 0x7FFF_FFFF;
    if ax == INF32 || ay == INF32 {
        return f32::from_bits(INF32);
    }
    if ax > INF32 {
        return quiet32(x);
    }
    if ay > INF32 {
        return quiet32(y);
    }
    let u = x as f64;
    let v = y as f64;
    // Both squares are exact in f64.
    fma(u, u, v * v).sqrt() as f32
}

/// For positive finite normal `x`: `x = m 2^(3k)`, m in [1, 8); writes m, returns k.
#[inline]
fn cbrt_split(x: f64, m: &mut f64) -> i32 {
    let bits = x.to_bits();
    let ex = (bits >> 52) as i32 - 1023;
    let k = (ex + 1200) / 3 - 400;
    let rem = ex - 3 * k;
    *m = f64::from_bits((bits & 0x000F_FFFF_FFFF_FFFF) | (((rem + 1023) as u64) << 52));
    k
}

/// cbrt(m) for m in [1, 8): a bit-level first guess (3.2% error), then two Halley steps
/// (relative error about 2^-45).
#[inline]
fn cbrt_k(m: f64) -> f64 {
    let hm = (m.to_bits() >> 32) as u32;
    let mut t = f64::from_bits(((hm / 3 + 0x2A9F_7626) as u64) << 32);
    let t3 = t * t * t;
    t *= (t3 + m + m) / (t3 + t3 + m);
    let t3 = t * t * t;
    t *= (t3 + m + m) / (t3 + t3 + m);
    t
}

/// Cube root (real; negative for negative `x`).
#[inline]
pub fn cbrtf(x: f32) -> f32 {
    let ax = x.to_bits() & 0x7FFF_FFFF;
    if ax == 0 || ax >= INF32 {
        return if ax > INF32 { quiet32(x) } else { x };
    }
    let mut m = 0.0;
    let k = cbrt_split(f32::from_bits(ax) as f64, &mut m);
    neg_if32(x < 0.0, (cbrt_k(m) * pow2(k)) as f32)
}

// ---------------------------------------------------------------------------------------
// f64 trigonometry

/// |x| below which sin x and tan x round to x and cos x to 1 (f64: 2^-27).
const TINY64: u64 = 0x3E40_0000_0000_0000;
/// High words of 2^-27, of pi/4 (at or below it: no reduction) and of 2^30 (from it up:
/// Payne-Hanek).
const TINY64_HI: u32 = 0x3E40_0000;
const PIO4_64_HI: u32 = 0x3FE9_21FB;
const BIG64_HI: u32 = 0x41D0_0000;

/// The high word of |x|.
#[inline]
fn hi_abs(x: f64) -> u32 {
    (x.to_bits() >> 32) as u32 & 0x7FFF_FFFF
}

/// sin(r.hi + r.lo), |r| <= pi/4.
fn sin_k(r: Dd) -> f64 {
    let x = r.hi;
    let z = x * x;
    let p = fma(
        z,
        fma(
            z,
            fma(z, fma(z, fma(z, fma(z, SIN_6, SIN_5), SIN_4), SIN_3), SIN_2),
            SIN_1,
        ),
        SIN_0,
    );
    // sin(x + y) = sin x + y cos x, cos x ~ 1 - z/2.
    x + fma(x * z, p, fma(-0.5 * z, r.lo, r.lo))
}

/// cos(r.hi + r.lo) = w + tail, |r| <= pi/4.
fn cos_parts(r: Dd, tail: &mut f64) -> f64 {
    let x = r.hi;
    let z = x * x;
    let zl = fma(x, x, -z);
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c = fma(z, fma(z, fma(z, fma(z, COS_5, COS_4), COS_3), COS_2), COS_1);
    let c = fma(z, c, COS_0);
    // (1 - w) - hz is the rounding error of w; cos(x + y) = cos x - y sin x.
    *tail = ((1.0 - w) - hz) + fma(z * z, c, -fma(0.5, zl, x * r.lo));
    w
}

fn cos_k(r: Dd) -> f64 {
    let mut tail = 0.0;
    let w = cos_parts(r, &mut tail);
    w + tail
}

/// tan(r) (`n` even) or -1/tan(r) (`n` odd), |r| <= pi/4: sin and cos in double
/// length, then a double-length quotient.
#[inline]
fn tan_k(r: Dd, n: u32) -> f64 {
    let h = r.hi;
    let z = h * h;
    let p = fma(
        z,
        fma(
            z,
            fma(z, fma(z, fma(z, fma(z, SIN_6, SIN_5), SIN_4), SIN_3), SIN_2),
            SIN_1,
        ),
        SIN_0,
    );
    let st = fma(h * z, p, fma(-0.5 * z, r.lo, r.lo));
    let s = fast_two_sum(h, st);
    let mut ct = 0.0;
    let w = cos_parts(r, &mut ct);
    let c = fast_two_sum(w, ct);
    let mut num = s;
    let mut den = c;
    if n & 1 != 0 {
        num = c;
        den = s;
    }
    let q = num.hi / den.hi;
    let rem = fma(-q, den.hi, num.hi) + (num.lo - q * den.lo);
    let t = q + rem / den.hi;
    neg_if64(n & 1 != 0, t)
}

/// For 2^-27 <= |x| < 2^30 (`hi` = the high word of |x|): x = n pi/2 + r.
#[inline]
fn reduce_med(x: f64, hi: u32, r: &mut Dd) -> u32 {
    if hi <= PIO4_64_HI {
        *r = Dd { hi: x, lo: 0.0 };
        return 0;
    }
    rem_pio2(x, r)
}

/// sin (`which` 0), cos (1) or tan (2) for |x| < 2^-27, |x| >= 2^30, infinities and NaN.
#[inline(never)]
fn trig_rare(x: f64, which: u32) -> f64 {
    let ax = x.to_bits() & ABS64;
    if ax < TINY64 {
        return if which == 1 { 1.0 } else { x };
    }
    if ax >= INF64 {
        return if ax == INF64 { nan64() } else { quiet64(x) };
    }
    let mut r = Dd { hi: 0.0, lo: 0.0 };
    let n = rem_pio2_large(x, &mut r) as u32;
    if which == 2 {
        return tan_k(r, n);
    }
    let q = n.wrapping_add(which);
    let v = if q & 1 == 0 { sin_k(r) } else { cos_k(r) };
    neg_if64(q & 2 != 0, v)
}

/// Sine of `x` (radians).
pub fn sin(x: f64) -> f64 {
    let hi = hi_abs(x);
    if hi.wrapping_sub(TINY64_HI) >= BIG64_HI - TINY64_HI {
        return trig_rare(x, 0);
    }
    let mut r = Dd { hi: 0.0, lo: 0.0 };
    let n = reduce_med(x, hi, &mut r);
    let v = if n & 1 == 0 { sin_k(r) } else { cos_k(r) };
    neg_if64(n & 2 != 0, v)
}

/// Cosine of `x` (radians).
pub fn cos(x: f64) -> f64 {
    let hi = hi_abs(x);
    if hi.wrapping_sub(TINY64_HI) >= BIG64_HI - TINY64_HI {
        return trig_rare(x, 1);
    }
    let mut r = Dd { hi: 0.0, lo: 0.0 };
    let n = reduce_med(x, hi, &mut r).wrapping_add(1);
    let v = if n & 1 == 0 { sin_k(r) } else { cos_k(r) };
    neg_if64(n & 2 != 0, v)
}

/// Sine and cosine of `x` with one argument reduction.
pub fn sincos(x: f64, s: &mut f64, c: &mut f64) {
    let hi = hi_abs(x);
    if hi.wrapping_sub(TINY64_HI) >= BIG64_HI - TINY64_HI {
        *s = trig_rare(x, 0);
        *c = trig_rare(x, 1);
        return;
    }
    let mut r = Dd { hi: 0.0, lo: 0.0 };
    let n = reduce_med(x, hi, &mut r);
    let sv = sin_k(r);
    let cv = cos_k(r);
    if n & 1 == 0 {
        *s = neg_if64(n & 2 != 0, sv);
        *c = neg_if64(n.wrapping_add(1) & 2 != 0, cv);
    } else {
        *s = neg_if64(n & 2 != 0, cv);
        *c = neg_if64(n.wrapping_add(1) & 2 != 0, sv);
    }
}

/// Tangent of `x` (radians).
pub fn tan(x: f64) -> f64 {
    let hi = hi_abs(x);
    if hi.wrapping_sub(TINY64_HI) >= BIG64_HI - TINY64_HI {
        return trig_rare(x, 2);
    }
    let mut r = Dd { hi: 0.0, lo: 0.0 };
    let n = reduce_med(x, hi, &mut r);
    tan_k(r, n)
}

// ---------------------------------------------------------------------------------------
// f64 inverse trigonometry

/// atan(u / v) in double length for finite 0 <= u <= v, 2^-600 < v < 2^1021.
fn atan_k(u: f64, v: f64) -> Dd {
    // Nearest c = k/16 to t = u/v; atan(t) = atan(c) + atan((u - c v) / (v + c u)).
    let kt = (u / v) * 16.0 + SHIFT;
    let k = (kt.to_bits() as u32 & 31) as usize;
    let c = (kt - SHIFT) * 0.0625;
    let p = c * v;
    let pl = fma(c, v, -p);
    // u - p is exact (Sterbenz): t is within 1/32 of c.
    let nh = u - p;
    let q = c * u;
    let ql = fma(c, u, -q);
    let d = two_sum(v, q);
    let dl = d.lo + ql;
    let th = nh / d.hi;
    let tl = (fma(-th, d.hi, nh) - pl - th * dl) / d.hi;
    let z = th * th;
    let pa = th * z * fma(z, fma(z, fma(z, ATAN_3, ATAN_2), ATAN_1), ATAN_0);
    let s = fast_two_sum(ATAN_TAB[2 * k], th);
    Dd {
        hi: s.hi,
        lo: s.lo + (ATAN_TAB[2 * k + 1] + (tl + pa)),
    }
}

/// `c - a` in double length (c = ch + cl a constant >= a).
fn dd_sub_from(ch: f64, cl: f64, a: Dd) -> Dd {
    let s = two_sum(ch, -a.hi);
    Dd {
        hi: s.hi,
        lo: s.lo + (cl - a.lo),
    }
}

/// Arc tangent of `y / x` in `[-pi, pi]`, using the signs of both to pick the quadrant.
pub fn atan2(y: f64, x: f64) -> f64 {
    let hy = hi_abs(y);
    let hx = hi_abs(x);
    // Both normal and finite; the rest (zeros, subnormals, infinities, NaNs) out of line.
    if hy.wrapping_sub(0x0010_0000) >= 0x7FE0_0000 || hx.wrapping_sub(0x0010_0000) >= 0x7FE0_0000 {
        return atan2_rare(y, x);
    }
    atan2_k(y, x)
}

/// atan2 for finite nonzero y and x.
#[inline]
fn atan2_k(y: f64, x: f64) -> f64 {
    let yneg = y.to_bits() >> 63 != 0;
    let xneg = x.to_bits() >> 63 != 0;
    let mut ay = y.abs();
    let mut ax = x.abs();
    // Scale so that v + c u cannot overflow and the residuals cannot underflow.
    let big = if hi_abs(y) > hi_abs(x) {
        hi_abs(y)
    } else {
        hi_abs(x)
    };
    if big >= 0x7FD0_0000 {
        ay *= 0.25;
        ax *= 0.25;
    } else if big < 0x20B0_0000 {
        ay *= 4.149515568880993e+180;
        ax *= 4.149515568880993e+180;
    }
    let swap = ay > ax;
    let mut a = if swap { atan_k(ax, ay) } else { atan_k(ay, ax) };
    if swap {
        a = dd_sub_from(PIO2_HI, PIO2_LO, a);
    }
    if xneg {
        a = dd_sub_from(PI_HI, PI_LO, a);
    }
    neg_if64(yneg, a.hi + a.lo)
}

/// atan2 when an operand is ±0, subnormal, infinite or NaN.
#[inline(never)]
fn atan2_rare(y: f64, x: f64) -> f64 {
    if y.is_nan() {
        return quiet64(y);
    }
    if x.is_nan() {
        return quiet64(x);
    }
    let yneg = y.to_bits() >> 63 != 0;
    let xneg = x.to_bits() >> 63 != 0;
    let ay = y.abs();
    let ax = x.abs();
    let inf = f64::from_bits(INF64);
    if ay == 0.0 {
        return if xneg { neg_if64(yneg, PI_HI) } else { y };
    }
    if ax == 0.0 {
        return neg_if64(yneg, PIO2_HI);
    }
    if ay == inf {
        let a = if ax == inf {
            if xneg {
                THREE_PIO4_HI
            } else {
                ATAN_TAB[32]
            }
        } else {
            PIO2_HI
        };
        return neg_if64(yneg, a);
    }
    if ax == inf {
        return neg_if64(yneg, if xneg { PI_HI } else { 0.0 });
    }
    // Subnormal operands.
    atan2_k(y, x)
}

/// Arc tangent of `x`, in `[-pi/2, pi/2]`.
pub fn atan(x: f64) -> f64 {
    let hx = hi_abs(x);
    if hx.wrapping_sub(TINY64_HI) >= 0x7FF0_0000 - TINY64_HI {
        // Tiny (atan x rounds to x), infinite or NaN.
        return if hx < TINY64_HI {
            x
        } else if x.is_nan() {
            quiet64(x)
        } else {
            neg_if64(x < 0.0, PIO2_HI)
        };
    }
    atan2_k(x, 1.0)
}

/// x^3 P(x^2) of asin(x) = x + x^3 P(x^2), |x| <= 1/2; `z` = x^2.
fn asin_tail(x: f64, z: f64) -> f64 {
    let mut p = fma(z, ASIN_14, ASIN_13);
    p = fma(z, p, ASIN_12);
    p = fma(z, p, ASIN_11);
    p = fma(z, p, ASIN_10);
    p = fma(z, p, ASIN_9);
    p = fma(z, p, ASIN_8);
    p = fma(z, p, ASIN_7);
    p = fma(z, p, ASIN_6);
    p = fma(z, p, ASIN_5);
    p = fma(z, p, ASIN_4);
    p = fma(z, p, ASIN_3);
    p = fma(z, p, ASIN_2);
    p = fma(z, p, ASIN_1);
    p = fma(z, p, ASIN_0);
    x * z * p
}

/// For 1/2 < a <= 1: asin(s) with s = sqrt((1 - a) / 2) as `2 asin(s) = w + tail`.
fn asin_half(a: f64, tail: &mut f64) -> f64 {
    let z = (1.0 - a) * 0.5;
    let s = z.sqrt();
    if z == 0.0 {
        *tail = 0.0;
        return 0.0;
    }
    // s + sl = sqrt(z) to double length; asin(s + sl) = asin(s) + sl / sqrt(1 - z).
    let sl = fma(-s, s, z) / (s + s);
    let t = asin_tail(s, z) + fma(0.5 * z, sl, sl);
    *tail = t + t;
    s + s
}

/// Arc sine of `x` in `[-pi/2, pi/2]`; NaN outside `[-1, 1]`.
pub fn asin(x: f64) -> f64 {
    let a = x.abs();
    if a > 1.0 || a.is_nan() {
        return if x.is_nan() { quiet64(x) } else { nan64() };
    }
    if x.to_bits() & ABS64 < TINY64 {
        return x;
    }
    let r = if a <= 0.5 {
        a + asin_tail(a, a * a)
    } else {
        let mut t = 0.0;
        let w = asin_half(a, &mut t);
        let d = two_sum(PIO2_HI, -w);
        d.hi + (d.lo + (PIO2_LO - t))
    };
    neg_if64(x < 0.0, r)
}

/// Arc cosine of `x` in `[0, pi]`; NaN outside `[-1, 1]`.
pub fn acos(x: f64) -> f64 {
    let a = x.abs();
    if a > 1.0 || a.is_nan() {
        return if x.is_nan() { quiet64(x) } else { nan64() };
    }
    if a <= 0.5 {
        let d = two_sum(PIO2_HI, -x);
        return d.hi + (d.lo + (PIO2_LO - asin_tail(x, x * x)));
    }
    let mut t = 0.0;
    let w = asin_half(a, &mut t);
    if x > 0.0 {
        w + t
    } else {
        let d = two_sum(PI_HI, -w);
        d.hi + (d.lo + (PI_LO - t))
    }
}

// ---------------------------------------------------------------------------------------
// f64 exponentials

/// (th + tail) * 2^e for th + tail in [1, 2) from the exp table, rounded once, also when
/// the result is subnormal.
#[inline]
fn exp_scale(th: f64, tail: f64, e: i32) -> f64 {
    let v = th + tail;
    if e > 1022 {
        return v * 2.0 * pow2(e - 1);
    }
    if e > -1022 || (e == -1022 && v >= 1.0) {
        return v * pow2(e);
    }
    // Subnormal (or just normal) result: add 1 so that the rounding of h + l happens on
    // the subnormal grid (2^-52 in units of 2^-1022).
    let sc = pow2(e + 1022);
    let yh = th * sc;
    let yl = tail * sc;
    let h = 1.0 + yh;
    let l = ((1.0 - h) + yh) + yl;
    ((h + l) - 1.0) * 2.2250738585072014e-308
}

/// e^(hi + lo) for -746 <= hi <= 710, |lo| <= 2^-40 |hi|.
#[inline]
fn exp_k(hi: f64, lo: f64) -> f64 {
    let t = hi * INV_LN2_64 + SHIFT;
    let k = t.to_bits() as u32 as i32;
    let kf = t - SHIFT;
    // kf * LN2_64_HI is exact (36 + 17 bits) and hi - kf * LN2_64_HI is exact (Sterbenz).
    let rh = fma(-kf, LN2_64_HI, hi);
    let rl = fma(-kf, LN2_64_LO, lo);
    let r = rh + rl;
    let dr = (rh - r) + rl;
    // e^r - 1 = r + r^2/2 + ...
    let p = fma(r, fma(r, fma(r, fma(r, EXP_3, EXP_2), EXP_1), EXP_0), 0.5);
    let q = fma(r * r, p, r) + dr;
    let j = (k & 63) as usize;
    let th = EXP_TAB[2 * j];
    let tail = fma(th, q, EXP_TAB[2 * j + 1]);
    exp_scale(th, tail, k >> 6)
}

/// `e^x`.
pub fn exp(x: f64) -> f64 {
    // |x| < 708: a normal result, no special case.
    if hi_abs(x) >= 0x4086_2000 {
        return exp_rare(x);
    }
    exp_k(x, 0.0)
}

/// exp for |x| >= 708, infinities and NaN.
#[inline(never)]
fn exp_rare(x: f64) -> f64 {
    if x.is_nan() {
        return quiet64(x);
    }
    if x > 709.782712893384 {
        return f64::from_bits(INF64);
    }
    if x < -745.2 {
        return 0.0;
    }
    exp_k(x, 0.0)
}

/// `2^x`.
pub fn exp2(x: f64) -> f64 {
    // |x| < 1022: a normal result, no special case.
    if hi_abs(x) >= 0x408F_F000 {
        return exp2_rare(x);
    }
    exp2_k(x)
}

/// exp2 for |x| >= 1022, infinities and NaN.
#[inline(never)]
fn exp2_rare(x: f64) -> f64 {
    if x.is_nan() {
        return quiet64(x);
    }
    if x >= 1024.0 {
        return f64::from_bits(INF64);
    }
    if x < -1076.0 {
        return 0.0;
    }
    exp2_k(x)
}

/// 2^x for -1076 <= x < 1024.
#[inline]
fn exp2_k(x: f64) -> f64 {
    let t = x * 64.0 + SHIFT;
    let k = t.to_bits() as u32 as i32;
    // Exact, |r| <= 1/128.
    let r = x - (t - SHIFT) * 0.015625;
    let p = fma(r, fma(r, fma(r, EXP2_5, EXP2_4), EXP2_3), EXP2_2);
    let q = r * fma(r, fma(r, p, EXP2_1), EXP2_0);
    let j = (k & 63) as usize;
    let th = EXP_TAB[2 * j];
    let tail = fma(th, q, EXP_TAB[2 * j + 1]);
    exp_scale(th, tail, k >> 6)
}

// ---------------------------------------------------------------------------------------
// f64 logarithms

/// x = 2^e m, m in [sqrt(1/2), sqrt(2)); x positive finite (subnormals included).
fn log_split(x: f64, e: &mut i32) -> f64 {
    let mut bits = x.to_bits();
    let mut adj = 0;
    if ((bits >> 32) as u32) < 0x0010_0000 {
        // Subnormal: scale by 2^54.
        bits = (x * 18014398509481984.0).to_bits();
        adj = -54;
    }
    let hx = (bits >> 32) as u32 + (0x3FF0_0000 - 0x3FE6_A09E);
    *e = (hx >> 20) as i32 - 1023 + adj;
    let hm = (hx & 0x000F_FFFF) + 0x3FE6_A09E;
    f64::from_bits(((hm as u64) << 32) | (bits & 0xFFFF_FFFF))
}

/// e * (ah + al) + ln(x / 2^e) * (bh + bl) for positive finite x, rounded once.
fn log_k(x: f64, ah: f64, al: f64, bh: f64, bl: f64) -> f64 {
    let mut e = 0;
    let m = log_split(x, &mut e);
    let f = m - 1.0;
    // ln(1 + f) = f - f^2/2 + s (f^2/2 + R(s)), s = f / (2 + f).
    let ff = two_prod(f, f);
    let hfsq = 0.5 * ff.hi;
    let s = f / (2.0 + f);
    let z = s * s;
    let mut r = fma(z, LOGR_7, LOGR_6);
    r = fma(z, r, LOGR_5);
    r = fma(z, r, LOGR_4);
    r = fma(z, r, LOGR_3);
    r = fma(z, r, LOGR_2);
    r = fma(z, r, LOGR_1);
    r = fma(z, r, LOGR_0);
    let tail = s * fma(z, r, hfsq);
    let u = fast_two_sum(f, -hfsq);
    let l = fast_two_sum(u.hi, fma(-0.5, ff.lo, u.lo) + tail);
    // Times (bh + bl), plus e (ah + al); e * ah is exact (ah has at most 42 bits).
    let ef = e as f64;
    let p = l.hi * bh;
    let pl = fma(l.hi, bh, -p) + fma(l.hi, bl, l.lo * bh);
    let a = two_sum(ef * ah, p);
    a.hi + (a.lo + fma(ef, al, pl))
}

/// True for a positive, finite, normal f64.
#[inline]
fn pos_normal64(x: f64) -> bool {
    ((x.to_bits() >> 32) as u32).wrapping_sub(0x0010_0000) < 0x7FE0_0000
}

/// The f64 logarithms when x is not a positive normal number: the special values, and
/// for a subnormal `x` the logarithm with the given constants (see `log_k`).
#[inline(never)]
fn log_rare(x: f64, ah: f64, al: f64, bh: f64, bl: f64) -> f64 {
    if x == 0.0 {
        return -f64::from_bits(INF64);
    }
    if x.is_nan() {
        return quiet64(x);
    }
    if x < 0.0 {
        return nan64();
    }
    if x == f64::from_bits(INF64) {
        return x;
    }
    log_k(x, ah, al, bh, bl)
}

/// Natural logarithm.
pub fn log(x: f64) -> f64 {
    if !pos_normal64(x) {
        return log_rare(x, LN2_42_HI, LN2_42_LO, 1.0, 0.0);
    }
    log_k(x, LN2_42_HI, LN2_42_LO, 1.0, 0.0)
}

/// Base-2 logarithm.
pub fn log2(x: f64) -> f64 {
    if !pos_normal64(x) {
        return log_rare(x, 1.0, 0.0, LOG2E_HI, LOG2E_LO);
    }
    log_k(x, 1.0, 0.0, LOG2E_HI, LOG2E_LO)
}

/// Base-10 logarithm.
pub fn log10(x: f64) -> f64 {
    if !pos_normal64(x) {
        return log_rare(x, LOG10_2_42_HI, LOG10_2_42_LO, LOG10E_HI, LOG10E_LO);
    }
    log_k(x, LOG10_2_42_HI, LOG10_2_42_LO, LOG10E_HI, LOG10E_LO)
}

// ---------------------------------------------------------------------------------------
// f64 pow, hypot, cbrt

/// ln(x) in double length (relative error about 2^-66) for positive finite x.
fn log_dd(x: f64) -> Dd {
    let mut e = 0;
    let m = log_split(x, &mut e);
    let f = m - 1.0;
    // s = f / (2 + f) in double length; 2 + f = dh + dl exactly.
    let dh = 2.0 + f;
    let dl = f - (dh - 2.0);
    let sh = f / dh;
    let sl = (fma(-sh, dh, f) - sh * dl) / dh;
    // ln(1 + f) = 2s + 2s^3/3 + s^5 Q(s^2); the first two terms in double length.
    let z = sh * sh;
    let zl = fma(sh, sh, -z) + 2.0 * sh * sl;
    let c = z * sh;
    let cl = fma(z, sh, -c) + fma(z, sl, zl * sh);
    let t3 = c * TWO_THIRDS_HI;
    let t3l = fma(c, TWO_THIRDS_HI, -t3) + fma(c, TWO_THIRDS_LO, cl * TWO_THIRDS_HI);
    let mut q = fma(z, LOGQ_7, LOGQ_6);
    q = fma(z, q, LOGQ_5);
    q = fma(z, q, LOGQ_4);
    q = fma(z, q, LOGQ_3);
    q = fma(z, q, LOGQ_2);
    q = fma(z, q, LOGQ_1);
    q = fma(z, q, LOGQ_0);
    let t5 = c * z * q;
    let a = fast_two_sum(sh + sh, t3);
    let lm = fast_two_sum(a.hi, a.lo + ((sl + sl) + t3l + t5));
    // + e ln 2 (e * LN2_42_HI exact).
    let ef = e as f64;
    let b = two_sum(ef * LN2_42_HI, lm.hi);
    fast_two_sum(b.hi, b.lo + fma(ef, LN2_42_LO, lm.lo))
}

/// 0: not an integer, 1: odd integer, 2: even integer; `ay` = |y| bits (finite, nonzero).
fn int_class64(ay: u64) -> i32 {
    let e = (ay >> 52) as i32 - 1023;
    if e < 0 {
        return 0;
    }
    if e > 52 {
        return 2;
    }
    let sh = (52 - e) as u32;
    if ay & ((1u64 << sh) - 1) != 0 {
        return 0;
    }
    if (ay >> sh) & 1 != 0 {
        1
    } else {
        2
    }
}

/// `x` raised to the power `y`.
pub fn pow(x: f64, y: f64) -> f64 {
    if pos_normal64(x) && hi_abs(y).wrapping_sub(0x0010_0000) < 0x7FE0_0000 {
        // x > 0 normal, y normal: no sign, no special case.
        return pow_k(x, y);
    }
    pow_rare(x, y)
}

/// |x|^y for finite nonzero x and y.
#[inline]
fn pow_k(x: f64, y: f64) -> f64 {
    if y == 1.0 {
        return x.abs();
    }
    if y == 2.0 {
        return x * x;
    }
    if y == -1.0 {
        return 1.0 / x.abs();
    }
    let l = log_dd(x.abs());
    let ph = y * l.hi;
    if ph > 710.0 {
        return f64::from_bits(INF64);
    }
    if ph < -746.0 {
        return 0.0;
    }
    let pl = fma(y, l.hi, -ph) + y * l.lo;
    exp_k(ph, pl)
}

/// pow when x is not a positive normal number or y is not a normal number.
#[inline(never)]
fn pow_rare(x: f64, y: f64) -> f64 {
    let ay = y.to_bits() & ABS64;
    if ay == 0 || x == 1.0 {
        return 1.0;
    }
    if x.is_nan() {
        return quiet64(x);
    }
    if y.is_nan() {
        return quiet64(y);
    }
    let ax = x.to_bits() & ABS64;
    let inf = f64::from_bits(INF64);
    if ay == INF64 {
        if ax == 0x3FF0_0000_0000_0000 {
            return 1.0;
        }
        return if (ax > 0x3FF0_0000_0000_0000) == (y > 0.0) {
            inf
        } else {
            0.0
        };
    }
    let yint = int_class64(ay);
    let xneg = x.to_bits() >> 63 != 0;
    let neg = xneg && yint == 1;
    if ax == 0 {
        return neg_if64(neg, if y < 0.0 { inf } else { 0.0 });
    }
    if ax == INF64 {
        return neg_if64(neg, if y < 0.0 { 0.0 } else { inf });
    }
    if xneg && yint == 0 {
        return nan64();
    }
    neg_if64(neg, pow_k(x, y))
}

/// `x` raised to the integer power `n`: `pow(x, n)`.
pub fn powi(x: f64, n: i32) -> f64 {
    pow(x, n as f64)
}

/// `sqrt(x^2 + y^2)` without overflow or underflow.
pub fn hypot(x: f64, y: f64) -> f64 {
    let ax = x.to_bits() & ABS64;
    let ay = y.to_bits() & ABS64;
    if ax == INF64 || ay == INF64 {
        return f64::from_bits(INF64);
    }
    if ax > INF64 {
        return quiet64(x);
    }
    if ay > INF64 {
        return quiet64(y);
    }
    let mut u = f64::from_bits(if ax > ay { ax } else { ay });
    let mut v = f64::from_bits(if ax > ay { ay } else { ax });
    if v == 0.0 {
        return u;
    }
    // Scale into a range where the squares neither overflow nor lose bits to underflow.
    let mut scale = 1.0;
    if u > 3.273390607896142e+150 {
        u *= 2.409919865102884e-181;
        v *= 2.409919865102884e-181;
        scale = 4.149515568880993e+180;
    } else if u < 3.054936363499605e-151 {
        u *= 4.149515568880993e+180;
        v *= 4.149515568880993e+180;
        scale = 2.409919865102884e-181;
    }
    let a = two_prod(u, u);
    let b = two_prod(v, v);
    let s = two_sum(a.hi, b.hi);
    let sl = s.lo + a.lo + b.lo;
    let h = s.hi.sqrt();
    // One Newton correction with the exact residual s - h^2.
    let r = h + (fma(-h, h, s.hi) + sl) / (h + h);
    r * scale
}

/// Cube root (real; negative for negative `x`).
pub fn cbrt(x: f64) -> f64 {
    let ax = x.to_bits() & ABS64;
    if ax == 0 || ax >= INF64 {
        return if ax > INF64 { quiet64(x) } else { x };
    }
    let mut a = f64::from_bits(ax);
    let mut adj = 0;
    if ax < 0x0010_0000_0000_0000 {
        a *= 18014398509481984.0;
        adj = -18;
    }
    let mut m = 0.0;
    let k = cbrt_split(a, &mut m) + adj;
    let t = cbrt_k(m);
    // Newton step t - (t^3 - m) / (3 t^2) with t^3 - m computed to double length.
    let t2 = two_prod(t, t);
    let c = t2.hi * t;
    let cl = fma(t2.hi, t, -c) + t2.lo * t;
    let res = (c - m) + cl;
    let t = t - res / (3.0 * t2.hi);
    neg_if64(x < 0.0, t * pow2(k))
}

// ---- generated by runtime/prelude/tools/libm_coeffs.py ----

// SINF: sin(r) = r + sum; max rel error 2^-37.5 on [0, 0.786184]
const SINF_0: f64 = -0.16666666640588204; // x^3
const SINF_1: f64 = 0.008333329280524732; // x^5
const SINF_2: f64 = -0.00019839304415545037; // x^7
const SINF_3: f64 = 2.718046471915294e-06; // x^9

// COSF: cos(r) = 1 + sum; max rel error 2^-33.9 on [0, 0.786184]
const COSF_0: f64 = -0.49999999691959274; // x^2
const COSF_1: f64 = 0.0416666200728295; // x^4
const COSF_2: f64 = -0.001388667266433482; // x^6
const COSF_3: f64 = 2.4382721757614827e-05; // x^8

// ATANF: atan(t) = t + sum; max rel error 2^-33.4 on [0, 0.414628]
const ATANF_0: f64 = -0.3333333321610087; // x^3
const ATANF_1: f64 = 0.19999969811645904; // x^5
const ATANF_2: f64 = -0.14283859292881484; // x^7
const ATANF_3: f64 = 0.11066597230459582; // x^9
const ATANF_4: f64 = -0.08591467862577522; // x^11
const ATANF_5: f64 = 0.04966589321380944; // x^13

// EXP2F: 2^r = 1 + sum (|r| <= 1/128); max rel error 2^-36.7 on [-0.0078125, 0.0078125]
const EXP2F_0: f64 = 0.6931471805587035; // x^1
const EXP2F_1: f64 = 0.24022694724246188; // x^2
const EXP2F_2: f64 = 0.05550421039187574; // x^3

// LOGF: ln((1+s)/(1-s)) = 2s + sum; max rel error 2^-44.9 on [0, 0.17159]
const LOGF_0: f64 = 0.6666666667577797; // x^3
const LOGF_1: f64 = 0.3999999562925554; // x^5
const LOGF_2: f64 = 0.28572108416080255; // x^7
const LOGF_3: f64 = 0.2217621788622979; // x^9
const LOGF_4: f64 = 0.1958375669030999; // x^11

// SIN: sin(r) = r + sum; max rel error 2^-57.1 on [0, 0.786184]
const SIN_0: f64 = -0.16666666666666666; // x^3
const SIN_1: f64 = 0.008333333333333331; // x^5
const SIN_2: f64 = -0.00019841269841265485; // x^7
const SIN_3: f64 = 2.755731921957456e-06; // x^9
const SIN_4: f64 = -2.505210628080545e-08; // x^11
const SIN_5: f64 = 1.6058534739206274e-10; // x^13
const SIN_6: f64 = -7.586663847492685e-13; // x^15

// COS: cos(r) = 1 - r^2/2 + sum; max rel error 2^-60.1 on [0, 0.786184]
const COS_0: f64 = 0.041666666666666664; // x^4
const COS_1: f64 = -0.0013888888888886795; // x^6
const COS_2: f64 = 2.480158729812051e-05; // x^8
const COS_3: f64 = -2.755731698292085e-07; // x^10
const COS_4: f64 = 2.087609086310249e-09; // x^12
const COS_5: f64 = -1.1378872176595547e-11; // x^14

// ATAN: atan(t) = t + sum (|t| <= 1/32); max rel error 2^-62.2 on [0, 0.0312812]
const ATAN_0: f64 = -0.33333333333332754; // x^3
const ATAN_1: f64 = 0.19999999994236317; // x^5
const ATAN_2: f64 = -0.14285696492942754; // x^7
const ATAN_3: f64 = 0.11089459142489091; // x^9

// ASIN: asin(x) = x + sum (|x| <= 1/2); max rel error 2^-58.5 on [0, 0.50005]
const ASIN_0: f64 = 0.16666666666666666; // x^3
const ASIN_1: f64 = 0.075; // x^5
const ASIN_2: f64 = 0.04464285714285728; // x^7
const ASIN_3: f64 = 0.0303819444444046; // x^9
const ASIN_4: f64 = 0.022372159095941136; // x^11
const ASIN_5: f64 = 0.017352764084863515; // x^13
const ASIN_6: f64 = 0.013964857156634264; // x^15
const ASIN_7: f64 = 0.011551465433061252; // x^17
const ASIN_8: f64 = 0.009767147719734786; // x^19
const ASIN_9: f64 = 0.008328413662964093; // x^21
const ASIN_10: f64 = 0.007786275354500409; // x^23
const ASIN_11: f64 = 0.003983443800812806; // x^25
const ASIN_12: f64 = 0.014194912896709627; // x^27
const ASIN_13: f64 = -0.01266934816899814; // x^29
const ASIN_14: f64 = 0.023874297279242347; // x^31

// EXP: e^r = 1 + r + r^2/2 + sum (|r| <= ln2/128); max rel error 2^-67.9 on [-0.00546936, 0.00546936]
const EXP_0: f64 = 0.16666666666664448; // x^3
const EXP_1: f64 = 0.04166666666665557; // x^4
const EXP_2: f64 = 0.008333339268642714; // x^5
const EXP_3: f64 = 0.0013888900017594162; // x^6

// EXP2: 2^r = 1 + sum (|r| <= 1/128); max rel error 2^-62.2 on [-0.00782031, 0.00782031]
const EXP2_0: f64 = 0.6931471805599453; // x^1
const EXP2_1: f64 = 0.24022650695910072; // x^2
const EXP2_2: f64 = 0.05550410866478949; // x^3
const EXP2_3: f64 = 0.009618129107622608; // x^4
const EXP2_4: f64 = 0.0013333572138672495; // x^5
const EXP2_5: f64 = 0.00015403546557855738; // x^6

// LOGR: ln((1+s)/(1-s)) = 2s + s*R(s), R = sum; max abs error 2^-59.7 on [0, 0.17159]
const LOGR_0: f64 = 0.6666666666666666; // x^2
const LOGR_1: f64 = 0.40000000000000463; // x^4
const LOGR_2: f64 = 0.2857142857104374; // x^6
const LOGR_3: f64 = 0.22222222343109138; // x^8
const LOGR_4: f64 = 0.18181800175134805; // x^10
const LOGR_5: f64 = 0.15386026556174437; // x^12
const LOGR_6: f64 = 0.1327367999671236; // x^14
const LOGR_7: f64 = 0.13042635858907217; // x^16

// LOGQ: ln((1+s)/(1-s)) = 2s + 2s^3/3 + s^5*Q(s), Q = sum; max abs error 2^-55.1 on [0, 0.17159]
const LOGQ_0: f64 = 0.4; // x^0
const LOGQ_1: f64 = 0.28571428571429375; // x^2
const LOGQ_2: f64 = 0.22222222221650972; // x^4
const LOGQ_3: f64 = 0.1818181833640265; // x^6
const LOGQ_4: f64 = 0.1538459486371597; // x^8
const LOGQ_5: f64 = 0.1333480965542694; // x^10
const LOGQ_6: f64 = 0.11706112805158675; // x^12
const LOGQ_7: f64 = 0.11724386843227659; // x^14

// 2^(j/64), j = 0..63, as (hi, lo) pairs: hi = f64(2^(j/64)), lo = f64(2^(j/64) - hi).
static EXP_TAB: [f64; 128] = [
    1.0,
    0.0,
    1.0108892860517005,
    -1.5234778603368577e-17,
    1.0218971486541166,
    5.109225028973444e-17,
    1.0330248790212284,
    7.600838874027088e-18,
    1.0442737824274138,
    8.551889705537965e-17,
    1.0556451783605572,
    1.759325738772092e-18,
    1.0671404006768237,
    -7.899853966841582e-17,
    1.0787607977571199,
    -6.656660436056593e-17,
    1.0905077326652577,
    -3.046782079812471e-17,
    1.102382583307841,
    5.2660368715706944e-17,
    1.1143867425958924,
    1.0410278456845571e-16,
    1.1265216186082418,
    5.165856758795457e-17,
    1.1387886347566916,
    8.912812676025408e-17,
    1.1511892299529827,
    3.250710218863827e-17,
    1.1637248587775775,
    3.8292048369240935e-17,
    1.1763969916502812,
    5.554203254218079e-17,
    1.189207115002721,
    3.982015231465646e-17,
    1.202156731452703,
    6.644981499252301e-17,
    1.215247359980469,
    -7.712630692681488e-17,
    1.22848053610687,
    -1.89878163130253e-17,
    1.241857812073484,
    4.658027591836937e-17,
    1.255380757024691,
    -6.7113898212968784e-18,
    1.2690509571917332,
    2.667932131342186e-18,
    1.2828700160787783,
    1.713594918243561e-17,
    1.2968395546510096,
    2.5382502794888315e-17,
    1.3109612115247644,
    -7.181536135519454e-17,
    1.3252366431597413,
    -2.8587312100388614e-17,
    1.339667524053303,
    8.927282594831732e-17,
    1.3542555469368927,
    7.70094837980299e-17,
    1.3690024229745905,
    9.593797919118849e-17,
    1.383909881963832,
    -6.770511658794786e-17,
    1.3989796725383112,
    -9.614213209051323e-17,
    1.4142135623730951,
    -9.667293313452913e-17,
    1.42961333839197,
    -1.2031642489053655e-17,
    1.4451808069770467,
    -3.0237581349939873e-17,
    1.460917794180647,
    -5.600377186075216e-17,
    1.4768261459394993,
    -3.483994556892796e-17,
    1.4929077282912648,
    1.4192920154284036e-17,
    1.5091644275934228,
    -1.016455327754295e-16,
    1.5255981507445384,
    -1.1024941712342561e-16,
    1.5422108254079407,
    7.949834809697621e-17,
    1.559004400237837,
    3.7812070533575275e-17,
    1.5759808451078865,
    -1.0136916471278304e-17,
    1.593142151342267,
    -1.0094406542311964e-16,
    1.6104903319492543,
    2.4707192569797888e-17,
    1.6280274218573478,
    -6.712955084707084e-17,
    1.645755478153965,
    -1.0125679913674773e-16,
    1.6636765803267364,
    5.8909926967131e-17,
    1.681792830507429,
    8.199010020581497e-17,
    1.7001063537185235,
    -8.0237193703977e-18,
    1.718619298122478,
    -1.851380418263111e-17,
    1.7373338352737062,
    3.164389299292957e-17,
    1.7562521603732995,
    2.960140695448873e-17,
    1.7753764925265212,
    6.429731796556572e-17,
    1.7947090750031072,
    1.8227458427912087e-17,
    1.8142521755003989,
    -9.969531538920349e-17,
    1.8340080864093424,
    3.283107224245627e-17,
    1.8539791250833855,
    9.761887490727594e-17,
    1.8741676341103,
    -6.122763413004143e-17,
    1.8945759815869656,
    3.4034035352165297e-17,
    1.9152065613971474,
    -1.0619946056195963e-16,
    1.9360617934922943,
    1.0332385960676326e-16,
    1.9571441241754002,
    8.960767791036668e-17,
    1.978456026387951,
    4.0388753109278167e-17,
];

// atan(k/16), k = 0..16, as (hi, lo) pairs.
static ATAN_TAB: [f64; 34] = [
    0.0,
    0.0,
    0.06241880999595735,
    -1.5490756308295046e-18,
    0.12435499454676144,
    -3.1253241424539383e-18,
    0.18534794999569476,
    4.180692268843079e-18,
    0.24497866312686414,
    1.0698755618734451e-17,
    0.3028848683749714,
    -1.1010827903001369e-17,
    0.35877067027057225,
    -2.4623815582638635e-17,
    0.4124104415973873,
    -1.587652227770689e-17,
    0.4636476090008061,
    2.2698777452961687e-17,
    0.5123894603107377,
    -2.5462781472855804e-17,
    0.5585993153435624,
    -5.4556305485916264e-18,
    0.6022873461349642,
    2.950430737228402e-17,
    0.6435011087932844,
    1.5834785051444286e-17,
    0.6823165548747481,
    6.943223671560008e-18,
    0.7188299996216245,
    -2.1478388444456983e-17,
    0.7531512809621944,
    -2.4256934659182068e-17,
    0.7853981633974483,
    3.061616997868383e-17,
];

// 2/pi in 32-bit words: word k holds the fraction bits 32k+1 ..= 32k+32.
static TWO_OVER_PI: [u32; 40] = [
    0xA2F9836E, 0x4E441529, 0xFC2757D1, 0xF534DDC0, 0xDB629599, 0x3C439041, 0xFE5163AB, 0xDEBBC561,
    0xB7246E3A, 0x424DD2E0, 0x06492EEA, 0x09D1921C, 0xFE1DEB1C, 0xB129A73E, 0xE88235F5, 0x2EBB4484,
    0xE99C7026, 0xB45F7E41, 0x3991D639, 0x835339F4, 0x9C845F8B, 0xBDF9283B, 0x1FF897FF, 0xDE05980F,
    0xEF2F118B, 0x5A0A6D1F, 0x6D367ECF, 0x27CB09B7, 0x4F463F66, 0x9E5FEA2D, 0x7527BAC7, 0xEBE5F17B,
    0x3D0739F7, 0x8A5292EA, 0x6BFB5FB1, 0x1F8D5D08, 0x56033046, 0xFC7B6BAB, 0xF0CFBC20, 0x9AF4361D,
];

const PIO2_HI: f64 = 1.5707963267948966;
const PIO2_LO: f64 = 6.123233995736766e-17;
const PI_HI: f64 = 3.141592653589793;
const PI_LO: f64 = 1.2246467991473532e-16;
const LN2_HI: f64 = 0.6931471805599453;
const LN2_LO: f64 = 2.3190468138462996e-17;
const LOG2E_HI: f64 = 1.4426950408889634;
const LOG2E_LO: f64 = 2.0355273740931033e-17;
const LOG10E_HI: f64 = 0.4342944819032518;
const LOG10E_LO: f64 = 1.098319650216765e-17;
const LOG10_2_HI: f64 = 0.3010299956639812;
const LOG10_2_LO: f64 = -2.8037281277851704e-18;
const TWO_THIRDS_HI: f64 = 0.6666666666666666;
const TWO_THIRDS_LO: f64 = 3.700743415417188e-17;
const THREE_PIO4_HI: f64 = 2.356194490192345;
const THREE_PIO4_LO: f64 = 9.184850993605148e-17;
const INV_PIO2: f64 = 0.6366197723675814;
const PIO2_1: f64 = 1.5707963267948966;
const PIO2_2: f64 = 6.123233995736766e-17;
const PIO2_3: f64 = -1.4973849048591698e-33;
const LN2_42_HI: f64 = 0.6931471805598903; // 42 significant bits
const LN2_42_LO: f64 = 5.497923018708371e-14;
const LOG10_2_42_HI: f64 = 0.30102999566395283; // 42 significant bits
const LOG10_2_42_LO: f64 = 2.8363394551044964e-14;
const LN2_64_HI: f64 = 0.010830424696223417; // 36 significant bits
const LN2_64_LO: f64 = 2.572804622327669e-14;
const INV_LN2_64: f64 = 92.33248261689366;
const TAN_PIO8: f64 = 0.41421356237309503;

// ---- end of generated code ----
