//! IEEE 754-2008 arithmetic as MIPS32r6 defines it (NaN-2008, ABS-2008, FCSR rounding
//! modes, cause/flag/enable bits), for single and double precision.
//!
//! Results are computed with the host's round-to-nearest arithmetic plus an exact
//! residual sign (error-free transforms), from which inexact, overflow, underflow and the
//! directed rounding modes are derived. Single-precision add/sub/mul/div take a fast path
//! when the mode is round-to-nearest and the result is a normal number (only Inexact can
//! arise then); everything else goes through the general code. NaN results are produced
//! explicitly (never taken from the host), so they are bit-exact on every host:
//! - operations on NaN inputs return the first signalling NaN (fs before ft), else the
//!   first quiet NaN, quieted (QEMU's MIPS rule); an sNaN input raises Invalid;
//! - invalid operations (inf - inf, 0 * inf, 0/0, inf/inf, sqrt(-x)) return the default
//!   NaN (`0x7FC00000` / `0x7FF8000000000000`).
//!
//! Choices where the manual leaves room: underflow is detected after rounding (tiny =
//! rounded result below the smallest normal, as QEMU) and signalled only when inexact; FCSR.FS
//! (flush to zero) is ignored — denormals are always computed exactly; `recip` and `rsqrt`
//! are computed as `1/x` and `1/sqrt(x)` with a rounding each (as QEMU does).

/// FCSR exception bit values (shifted by 2 for Flags, 7 for Enables, 12 for Cause).
pub const EX_INEXACT: u32 = 1;
/// Underflow.
pub const EX_UNDERFLOW: u32 = 2;
/// Overflow.
pub const EX_OVERFLOW: u32 = 4;
/// Division by zero.
pub const EX_DIVZERO: u32 = 8;
/// Invalid operation.
pub const EX_INVALID: u32 = 16;

const CAUSE_MASK: u32 = 0x3F << 12;

/// An enabled floating-point exception was raised (the instruction traps).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FpTrap {
    /// The cause bits (`EX_*`).
    pub cause: u32,
}

/// Names the exceptions in a cause mask, e.g. `"invalid operation, inexact"`.
pub fn describe_exceptions(cause: u32) -> String {
    let names = [
        (EX_INVALID, "invalid operation"),
        (EX_DIVZERO, "division by zero"),
        (EX_OVERFLOW, "overflow"),
        (EX_UNDERFLOW, "underflow"),
        (EX_INEXACT, "inexact"),
    ];
    let v: Vec<&str> = names
        .iter()
        .filter(|(b, _)| cause & b != 0)
        .map(|(_, n)| *n)
        .collect();
    v.join(", ")
}

/// Writes the cause field; traps if an enabled exception is raised, else accumulates flags.
#[inline(always)]
pub fn update(fcsr: &mut u32, exc: u32) -> Result<(), FpTrap> {
    // Branch-free on the common path: one store of cause and flags together.
    let f = (*fcsr & !CAUSE_MASK) | (exc << 12);
    if exc & (f >> 7) & 0x1F != 0 {
        *fcsr = f;
        return Err(FpTrap { cause: exc });
    }
    *fcsr = f | (exc << 2);
    Ok(())
}

/// Rounding mode from FCSR.RM.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rm {
    /// Round to nearest, ties to even.
    Nearest,
    /// Toward zero.
    Zero,
    /// Toward +infinity.
    Up,
    /// Toward -infinity.
    Down,
}

/// The rounding mode selected by `fcsr`.
#[inline(always)]
pub fn rm(fcsr: u32) -> Rm {
    match fcsr & 3 {
        0 => Rm::Nearest,
        1 => Rm::Zero,
        2 => Rm::Up,
        _ => Rm::Down,
    }
}

/// A binary floating-point format (implemented for `f32` and `f64`).
pub trait Float: Copy + PartialOrd + PartialEq + std::fmt::Debug {
    /// Raw bits type.
    type Bits: Copy + PartialEq;
    /// Default quiet NaN bits.
    const DEFAULT_NAN: Self::Bits;
    /// Largest finite value.
    const MAX: Self;
    /// Smallest positive normal.
    const MIN_NORMAL: Self;
    /// Positive zero.
    const ZERO: Self;
    /// From raw bits.
    fn from_b(b: Self::Bits) -> Self;
    /// To raw bits.
    fn to_b(self) -> Self::Bits;
    /// NaN test.
    fn nan(self) -> bool;
    /// Signalling NaN test (quiet bit clear).
    fn snan_bits(b: Self::Bits) -> bool;
    /// Sets the quiet bit.
    fn quiet_bits(b: Self::Bits) -> Self::Bits;
    /// Sign bit set.
    fn neg_sign(self) -> bool;
    /// Next representable value toward +inf.
    fn up(self) -> Self;
    /// Next representable value toward -inf.
    fn down(self) -> Self;
    /// Absolute value.
    fn fabs(self) -> Self;
    /// Negation.
    fn fneg(self) -> Self;
    /// Is infinite.
    fn inf(self) -> bool;
}

macro_rules! impl_float {
    ($t:ty, $b:ty, $dn:expr, $qb:expr) => {
        impl Float for $t {
            type Bits = $b;
            const DEFAULT_NAN: $b = $dn;
            const MAX: $t = <$t>::MAX;
            const MIN_NORMAL: $t = <$t>::MIN_POSITIVE;
            const ZERO: $t = 0.0;
            #[inline(always)]
            fn from_b(b: $b) -> $t {
                <$t>::from_bits(b)
            }
            #[inline(always)]
            fn to_b(self) -> $b {
                self.to_bits()
            }
            #[inline(always)]
            fn nan(self) -> bool {
                self.is_nan()
            }
            #[inline(always)]
            fn snan_bits(b: $b) -> bool {
                <$t>::from_bits(b).is_nan() && b & $qb == 0
            }
            #[inline(always)]
            fn quiet_bits(b: $b) -> $b {
                b | $qb
            }
            #[inline(always)]
            fn neg_sign(self) -> bool {
                self.is_sign_negative()
            }
            #[inline(always)]
            fn up(self) -> $t {
                self.next_up()
            }
            #[inline(always)]
            fn down(self) -> $t {
                self.next_down()
            }
            #[inline(always)]
            fn fabs(self) -> $t {
                <$t>::from_bits(self.to_bits() & !(1 << (<$b>::BITS - 1)))
            }
            #[inline(always)]
            fn fneg(self) -> $t {
                <$t>::from_bits(self.to_bits() ^ (1 << (<$b>::BITS - 1)))
            }
            #[inline(always)]
            fn inf(self) -> bool {
                self.is_infinite()
            }
        }
    };
}
impl_float!(f32, u32, 0x7FC0_0000, 0x0040_0000);
impl_float!(f64, u64, 0x7FF8_0000_0000_0000, 0x0008_0000_0000_0000);

/// NaN propagation for two operands, at least one a NaN: (result bits, exceptions).
#[inline(never)]
pub fn nan2<F: Float>(a: F::Bits, b: F::Bits) -> (F::Bits, u32) {
    let (sa, sb) = (F::snan_bits(a), F::snan_bits(b));
    let exc = if sa || sb { EX_INVALID } else { 0 };
    let pick = if sa {
        a
    } else if sb {
        b
    } else if F::from_b(a).nan() {
        a
    } else {
        b
    };
    (F::quiet_bits(pick), exc)
}

/// Finishes a rounded result: `r` is the round-to-nearest result of finite operands and
/// `sgn` the sign of (exact - r) (-1, 0, 1). Applies the rounding mode and reports
/// overflow, underflow and inexact.
#[inline(always)]
fn finish<F: Float>(r: F, sgn: i8, mode: Rm, overflowed: bool) -> (F, u32) {
    if overflowed {
        let neg = r.neg_sign();
        let v = match mode {
            Rm::Nearest => r,
            Rm::Zero => {
                if neg {
                    F::MAX.fneg()
                } else {
                    F::MAX
                }
            }
            Rm::Up => {
                if neg {
                    F::MAX.fneg()
                } else {
                    r
                }
            }
            Rm::Down => {
                if neg {
                    r
                } else {
                    F::MAX
                }
            }
        };
        return (v, EX_OVERFLOW | EX_INEXACT);
    }
    if sgn == 0 {
        return (r, 0);
    }
    let mut v = r;
    match mode {
        Rm::Nearest => {}
        Rm::Zero => {
            if r > F::ZERO && sgn < 0 {
                v = r.down();
            } else if r < F::ZERO && sgn > 0 {
                v = r.up();
            }
        }
        Rm::Up => {
            if sgn > 0 {
                v = r.up();
            }
        }
        Rm::Down => {
            if sgn < 0 {
                v = r.down();
            }
        }
    }
    // A directed step may leave zero with the wrong sign (e.g. -tiny rounded up): IEEE keeps
    // the sign of the exact result.
    if v == F::ZERO && (sgn < 0) != v.neg_sign() && r != F::ZERO {
        v = v.fneg();
    }
    // Directed modes never round a finite result to infinity beyond MAX.
    if v.inf() && !r.inf() {
        return (v, EX_OVERFLOW | EX_INEXACT);
    }
    // Tininess is detected after rounding (QEMU's MIPS model): the rounded result is below
    // the smallest normal in magnitude.
    let exc = if v.fabs() < F::MIN_NORMAL {
        EX_UNDERFLOW | EX_INEXACT
    } else {
        EX_INEXACT
    };
    (v, exc)
}

#[inline(always)]
fn sign_of<T: PartialOrd + Default>(x: T) -> i8 {
    let z = T::default();
    if x > z {
        1
    } else if x < z {
        -1
    } else {
        0
    }
}

#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Exact sign of the sum of `terms` (Shewchuk's expansion sum; exact unless an
/// intermediate overflows).
fn exact_sum_sign(terms: &[f64]) -> i8 {
    let mut e: Vec<f64> = Vec::with_capacity(terms.len() * 2);
    for &t in terms {
        let mut q = t;
        let mut next = Vec::with_capacity(e.len() + 1);
        for &c in &e {
            let (s, h) = two_sum(q, c);
            if h != 0.0 {
                next.push(h);
            }
            q = s;
        }
        if q != 0.0 {
            next.push(q);
        }
        e = next;
    }
    // Components are non-overlapping and increase in magnitude: the last one decides.
    e.last().map_or(0, |&x| sign_of(x))
}

/// Result of an arithmetic operation: bits and raised exceptions.
pub type FpResult<B> = (B, u32);

/// The binary operations with a rounding step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    /// Addition.
    Add,
    /// Subtraction.
    Sub,
    /// Multiplication.
    Mul,
    /// Division.
    Div,
}

/// Single-precision binary arithmetic.
///
/// Fast path: in round-to-nearest (the host's mode) a normal result means no operand was
/// a NaN or infinite and nothing overflowed, underflowed or divided by zero, so the host
/// result is the answer and only Inexact needs an exactness test.
#[inline(always)]
pub fn bin_s(op: BinOp, a: u32, b: u32, fcsr: u32) -> FpResult<u32> {
    let (x, y) = (f32::from_bits(a), f32::from_bits(b));
    let r = match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
    };
    if fcsr & 3 == 0 && r.is_normal() {
        let inexact = match op {
            // TwoSum: the exact error of the rounded sum.
            BinOp::Add | BinOp::Sub => {
                let yy = if op == BinOp::Add { y } else { -y };
                let bb = r - x;
                (x - (r - bb)) + (yy - bb) != 0.0
            }
            // Products of two f32 significands are exact in f64.
            BinOp::Mul => x as f64 * y as f64 != r as f64,
            BinOp::Div => r as f64 * y as f64 != x as f64,
        };
        return (r.to_bits(), if inexact { EX_INEXACT } else { 0 });
    }
    bin_s_slow(op, a, b, fcsr)
}

/// [`bin_s`] for special operands and results and the directed rounding modes.
#[inline(never)]
fn bin_s_slow(op: BinOp, a: u32, b: u32, fcsr: u32) -> FpResult<u32> {
    let (x, y) = (f32::from_bits(a), f32::from_bits(b));
    if x.is_nan() || y.is_nan() {
        return nan2::<f32>(a, b);
    }
    let r = match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
    };
    if r.is_nan() {
        return (f32::DEFAULT_NAN, EX_INVALID);
    }
    if op == BinOp::Div && y == 0.0 {
        return if x.is_infinite() {
            (r.to_bits(), 0)
        } else {
            (r.to_bits(), EX_DIVZERO)
        };
    }
    if r.is_infinite() {
        let overflow = x.is_finite() && y.is_finite();
        let (v, e) = finish(r, 0, rm(fcsr), overflow);
        return (v.to_bits(), e);
    }
    let (xd, yd, rd) = (x as f64, y as f64, r as f64);
    let sgn = match op {
        BinOp::Add | BinOp::Sub => {
            let yy = if op == BinOp::Add { y } else { -y };
            // TwoSum in f32: exact error of the rounded sum.
            let bb = r - x;
            let err = (x - (r - bb)) + (yy - bb);
            sign_of(err)
        }
        BinOp::Mul => sign_of(xd * yd - rd),
        BinOp::Div => {
            if x.is_infinite() || y.is_infinite() {
                0
            } else {
                sign_of(xd - rd * yd) * sign_of(yd)
            }
        }
    };
    let mode = rm(fcsr);
    if sgn == 0 {
        if r == 0.0 && mode == Rm::Down && matches!(op, BinOp::Add | BinOp::Sub) {
            // Exact zero sum: -0 in round-toward-negative unless both addends are +0.
            let yy = if op == BinOp::Add { y } else { -y };
            let both_pos = !x.is_sign_negative() && !yy.is_sign_negative();
            return (if both_pos { 0 } else { 0x8000_0000 }, 0);
        }
        return (r.to_bits(), 0);
    }
    let (v, e) = finish(r, sgn, mode, false);
    (v.to_bits(), e)
}

/// Scales a pair so an fma-computed residual cannot underflow.
const SCALE_UP: f64 = 1.3407807929942597e154; // 2^512

/// Double-precision binary arithmetic.
#[inline(never)]
pub fn bin_d(op: BinOp, a: u64, b: u64, fcsr: u32) -> FpResult<u64> {
    let (x, y) = (f64::from_bits(a), f64::from_bits(b));
    if x.is_nan() || y.is_nan() {
        return nan2::<f64>(a, b);
    }
    let r = match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
    };
    if r.is_nan() {
        return (f64::DEFAULT_NAN, EX_INVALID);
    }
    if op == BinOp::Div && y == 0.0 {
        return if x.is_infinite() {
            (r.to_bits(), 0)
        } else {
            (r.to_bits(), EX_DIVZERO)
        };
    }
    if r.is_infinite() {
        let overflow = x.is_finite() && y.is_finite();
        let (v, e) = finish(r, 0, rm(fcsr), overflow);
        return (v.to_bits(), e);
    }
    let small = r.abs() < 1e-250 || x.abs() < 1e-250;
    let sgn = match op {
        BinOp::Add | BinOp::Sub => {
            let yy = if op == BinOp::Add { y } else { -y };
            let bb = r - x;
            let err = (x - (r - bb)) + (yy - bb);
            sign_of(err)
        }
        BinOp::Mul => {
            if r == 0.0 && x != 0.0 && y != 0.0 {
                // The product underflowed to zero.
                if (x < 0.0) != (y < 0.0) {
                    -1
                } else {
                    1
                }
            } else if small {
                // Scale the smaller operand (exactly) so the residual cannot underflow.
                let (a, b) = if x.abs() < y.abs() { (x, y) } else { (y, x) };
                sign_of((a * SCALE_UP).mul_add(b, -(r * SCALE_UP)))
            } else {
                sign_of(x.mul_add(y, -r))
            }
        }
        BinOp::Div => {
            if x.is_infinite() || y.is_infinite() {
                0
            } else if r == 0.0 && x != 0.0 {
                // The quotient underflowed to zero.
                if (x < 0.0) != (y < 0.0) {
                    -1
                } else {
                    1
                }
            } else if small {
                sign_of((-(r * SCALE_UP)).mul_add(y, x * SCALE_UP)) * sign_of(y)
            } else {
                sign_of((-r).mul_add(y, x)) * sign_of(y)
            }
        }
    };
    let mode = rm(fcsr);
    if sgn == 0 {
        if r == 0.0 && mode == Rm::Down && matches!(op, BinOp::Add | BinOp::Sub) {
            let yy = if op == BinOp::Add { y } else { -y };
            let both_pos = !x.is_sign_negative() && !yy.is_sign_negative();
            return (if both_pos { 0 } else { 1 << 63 }, 0);
        }
        return (r.to_bits(), 0);
    }
    let (v, e) = finish(r, sgn, mode, false);
    (v.to_bits(), e)
}

/// Square root (single).
pub fn sqrt_s(a: u32, fcsr: u32) -> FpResult<u32> {
    let x = f32::from_bits(a);
    if x.is_nan() {
        return nan2::<f32>(a, a);
    }
    if x == 0.0 {
        return (a, 0);
    }
    if x < 0.0 {
        return (f32::DEFAULT_NAN, EX_INVALID);
    }
    let r = x.sqrt();
    if r.is_infinite() {
        return (r.to_bits(), 0);
    }
    let rd = r as f64;
    let sgn = sign_of(x as f64 - rd * rd);
    let (v, e) = finish(r, sgn, rm(fcsr), false);
    (v.to_bits(), e & !EX_UNDERFLOW)
}

/// Square root (double).
pub fn sqrt_d(a: u64, fcsr: u32) -> FpResult<u64> {
    let x = f64::from_bits(a);
    if x.is_nan() {
        return nan2::<f64>(a, a);
    }
    if x == 0.0 {
        return (a, 0);
    }
    if x < 0.0 {
        return (f64::DEFAULT_NAN, EX_INVALID);
    }
    let r = x.sqrt();
    if r.is_infinite() {
        return (r.to_bits(), 0);
    }
    let sgn = if x < 1e-250 {
        let rs = r * 1.157920892373162e77; // 2^256: residual scaled by 2^512
        sign_of((-rs).mul_add(rs, x * SCALE_UP))
    } else {
        sign_of((-r).mul_add(r, x))
    };
    let (v, e) = finish(r, sgn, rm(fcsr), false);
    (v.to_bits(), e & !EX_UNDERFLOW)
}

/// Fused multiply-add `c + a*b` (or `c - a*b` when `sub`), single precision.
///
/// NaN rule (QEMU, NaN-2008): `inf * 0 + c` is invalid and returns `c` quieted when `c`
/// is a NaN, else the default NaN; otherwise sNaN before qNaN, in the order c, a, b.
pub fn fma_s(c: u32, a: u32, b: u32, sub: bool, fcsr: u32) -> FpResult<u32> {
    let (x, y, z) = (f32::from_bits(a), f32::from_bits(b), f32::from_bits(c));
    let x = if sub { -x } else { x };
    if let Some(r) = fma_nan::<f32>(c, a, b) {
        return r;
    }
    let r = x.mul_add(y, z);
    if r.is_nan() {
        return (f32::DEFAULT_NAN, EX_INVALID);
    }
    if r.is_infinite() {
        let overflow = x.is_finite() && y.is_finite() && z.is_finite();
        let (v, e) = finish(r, 0, rm(fcsr), overflow);
        return (v.to_bits(), e);
    }
    let p = x as f64 * y as f64; // exact
    let zd = z as f64;
    let sgn = exact_sum_sign(&[p, zd, -(r as f64)]);
    let mode = rm(fcsr);
    if sgn == 0 && r == 0.0 {
        return (
            fma_zero_sign(p == 0.0 && p.is_sign_negative(), p, zd, mode) as u32,
            0,
        );
    }
    let (v, e) = finish(r, sgn, mode, false);
    (v.to_bits(), e)
}

fn fma_zero_sign(_neg_p: bool, p: f64, z: f64, mode: Rm) -> u64 {
    // Exact zero result: +0 unless both terms are -0, or round-toward-negative with
    // terms of opposite signs.
    let (np, nz) = (p.is_sign_negative(), z.is_sign_negative());
    let neg = if np == nz { np } else { mode == Rm::Down };
    if neg {
        0x8000_0000
    } else {
        0
    }
}

/// Fused multiply-add `c + a*b` (or `c - a*b`), double precision.
///
/// The rounding residual is summed exactly (error-free transforms and an expansion sum).
pub fn fma_d(c: u64, a: u64, b: u64, sub: bool, fcsr: u32) -> FpResult<u64> {
    let (x, y, z) = (f64::from_bits(a), f64::from_bits(b), f64::from_bits(c));
    let x = if sub { -x } else { x };
    if let Some(r) = fma_nan::<f64>(c, a, b) {
        return r;
    }
    let r = x.mul_add(y, z);
    if r.is_nan() {
        return (f64::DEFAULT_NAN, EX_INVALID);
    }
    if r.is_infinite() {
        let overflow = x.is_finite() && y.is_finite() && z.is_finite();
        let (v, e) = finish(r, 0, rm(fcsr), overflow);
        return (v.to_bits(), e);
    }
    // When every term is tiny, scale up (exactly) so the product's error term is exact.
    let tiny = |v: f64| v.abs() < 1e-250;
    let k = if tiny(x * y) && tiny(z) && tiny(r) {
        SCALE_UP
    } else {
        1.0
    };
    let xs = x * k;
    let ph = xs * y;
    let pl = xs.mul_add(y, -ph);
    let mut sgn = exact_sum_sign(&[ph, pl, z * k, -(r * k)]);
    if sgn == 0 && ph == 0.0 && x != 0.0 && y != 0.0 {
        // The product underflowed below every other term: it alone decides.
        sgn = if (x < 0.0) != (y < 0.0) { -1 } else { 1 };
    }
    let mode = rm(fcsr);
    if sgn == 0 && r == 0.0 {
        let neg = fma_zero_sign(false, ph, z, mode) != 0;
        return (if neg { 1 << 63 } else { 0 }, 0);
    }
    let (v, e) = finish(r, sgn, mode, false);
    (v.to_bits(), e)
}

fn fma_nan<F: Float>(c: F::Bits, a: F::Bits, b: F::Bits) -> Option<FpResult<F::Bits>> {
    let (x, y, z) = (F::from_b(a), F::from_b(b), F::from_b(c));
    let infzero = (x.inf() && y == F::ZERO) || (y.inf() && x == F::ZERO);
    if infzero && !z.nan() {
        return Some((F::DEFAULT_NAN, EX_INVALID));
    }
    if !(x.nan() || y.nan() || z.nan()) {
        return None;
    }
    let any_snan = F::snan_bits(a) || F::snan_bits(b) || F::snan_bits(c);
    let mut exc = if any_snan || infzero { EX_INVALID } else { 0 };
    let pick = if F::snan_bits(c) {
        c
    } else if F::snan_bits(a) {
        a
    } else if F::snan_bits(b) {
        b
    } else if z.nan() {
        c
    } else if x.nan() {
        a
    } else {
        b
    };
    if infzero {
        exc |= EX_INVALID;
    }
    Some((F::quiet_bits(pick), exc))
}

/// `min`/`max`/`mina`/`maxa` (IEEE 754-2008 minNum/maxNum, QEMU NaN rules).
pub fn minmax<F: Float>(a: F::Bits, b: F::Bits, is_max: bool, mag: bool) -> FpResult<F::Bits> {
    let (x, y) = (F::from_b(a), F::from_b(b));
    if x.nan() || y.nan() {
        let (sa, sb) = (F::snan_bits(a), F::snan_bits(b));
        if !sa && !sb {
            if !x.nan() {
                return (a, 0);
            }
            if !y.nan() {
                return (b, 0);
            }
        }
        return nan2::<F>(a, b);
    }
    if mag {
        let (ax, ay) = (x.fabs(), y.fabs());
        if ax < ay {
            return (if is_max { b } else { a }, 0);
        }
        if ay < ax {
            return (if is_max { a } else { b }, 0);
        }
    }
    // Equal (incl. +0 == -0): min prefers the negative, max the positive. Non-short-
    // circuit operators: the comparisons are data, better as flags than branches.
    let eq = x == y;
    let by_sign = is_max != x.neg_sign();
    let by_order = if is_max { x > y } else { x < y };
    let pick_a = (eq & by_sign) | (!eq & by_order);
    (if pick_a { a } else { b }, 0)
}

/// `cmp.cond.fmt`: true if the condition holds; raises Invalid for sNaN operands, and for
/// any NaN with the signalling conditions (`cond & 8`).
pub fn compare<F: Float>(a: F::Bits, b: F::Bits, cond: u8) -> (bool, u32) {
    let (x, y) = (F::from_b(a), F::from_b(b));
    // Non-short-circuit operators: the outcome is data, better as flags than branches.
    let un = x.nan() | y.nan();
    let exc = if un & ((cond & 8 != 0) | F::snan_bits(a) | F::snan_bits(b)) {
        EX_INVALID
    } else {
        0
    };
    let eq = !un & (x == y);
    let lt = !un & (x < y);
    let v = ((cond & 1 != 0) & un) | ((cond & 2 != 0) & eq) | ((cond & 4 != 0) & lt);
    (v ^ (cond & 16 != 0), exc)
}

/// `class.fmt` mask.
pub fn class<F: Float>(a: F::Bits) -> u32 {
    let x = F::from_b(a);
    let neg = x.neg_sign();
    let bit = if x.nan() {
        if F::snan_bits(a) {
            0
        } else {
            1
        }
    } else if x.inf() {
        2
    } else if x == F::ZERO {
        5
    } else if x.fabs() < F::MIN_NORMAL {
        4
    } else {
        3
    };
    if bit >= 2 && !neg {
        1 << (bit + 4)
    } else {
        1 << bit
    }
}

/// Integer rounding kinds for conversions and `rint`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntRound {
    /// Use FCSR.RM.
    Current,
    /// Nearest, ties to even.
    Nearest,
    /// Toward zero.
    Trunc,
    /// Toward +inf.
    Ceil,
    /// Toward -inf.
    Floor,
}

fn round_int(x: f64, how: IntRound, fcsr: u32) -> f64 {
    let how = if how == IntRound::Current {
        match rm(fcsr) {
            Rm::Nearest => IntRound::Nearest,
            Rm::Zero => IntRound::Trunc,
            Rm::Up => IntRound::Ceil,
            Rm::Down => IntRound::Floor,
        }
    } else {
        how
    };
    match how {
        IntRound::Nearest | IntRound::Current => x.round_ties_even(),
        IntRound::Trunc => x.trunc(),
        IntRound::Ceil => x.ceil(),
        IntRound::Floor => x.floor(),
    }
}

/// Float (given as f64, exact for single inputs) to i32 with r6 saturation: NaN gives 0,
/// out-of-range values saturate; both raise Invalid.
pub fn to_i32(x: f64, how: IntRound, fcsr: u32) -> FpResult<u32> {
    if x.is_nan() {
        return (0, EX_INVALID);
    }
    let r = round_int(x, how, fcsr);
    if r >= 2147483648.0 {
        return (i32::MAX as u32, EX_INVALID);
    }
    if r < -2147483648.0 {
        return (i32::MIN as u32, EX_INVALID);
    }
    ((r as i32) as u32, if r != x { EX_INEXACT } else { 0 })
}

/// Float to i64 with r6 saturation.
pub fn to_i64(x: f64, how: IntRound, fcsr: u32) -> FpResult<u64> {
    if x.is_nan() {
        return (0, EX_INVALID);
    }
    let r = round_int(x, how, fcsr);
    if r >= 9223372036854775808.0 {
        return (i64::MAX as u64, EX_INVALID);
    }
    if r < -9223372036854775808.0 {
        return (i64::MIN as u64, EX_INVALID);
    }
    ((r as i64) as u64, if r != x { EX_INEXACT } else { 0 })
}

/// `rint.fmt`: round to an integral value in the current rounding mode.
pub fn rint<F: Float>(
    a: F::Bits,
    fcsr: u32,
    to_f64: fn(F) -> f64,
    from_f64: fn(f64) -> F,
) -> FpResult<F::Bits> {
    let x = F::from_b(a);
    if x.nan() {
        return nan2::<F>(a, a);
    }
    let xd = to_f64(x);
    let r = round_int(xd, IntRound::Current, fcsr);
    let mut v = from_f64(r);
    // Keep the sign of zero results (e.g. rint(-0.3) = -0).
    if r == 0.0 && x.neg_sign() {
        v = F::ZERO.fneg();
    }
    (v.to_b(), if r != xd { EX_INEXACT } else { 0 })
}

/// `cvt.s.d`: rounds an f64 to f32 in the current mode.
pub fn f64_to_f32(v: f64, fcsr: u32) -> FpResult<u32> {
    if v.is_nan() {
        let b = v.to_bits();
        let bits = ((b >> 63) as u32) << 31 | 0x7F80_0000 | ((b >> 29) as u32 & 0x007F_FFFF);
        let snan = b & (1 << 51) == 0;
        return (bits | 0x0040_0000, if snan { EX_INVALID } else { 0 });
    }
    if v.is_infinite() {
        return ((v as f32).to_bits(), 0);
    }
    let r = v as f32;
    if r.is_infinite() {
        let (x, e) = finish(r, 0, rm(fcsr), true);
        return (x.to_bits(), e);
    }
    let sgn = sign_of(v - r as f64); // exact: r is the nearest f32 to v
    if sgn == 0 {
        return (r.to_bits(), 0);
    }
    let (x, e) = finish(r, sgn, rm(fcsr), false);
    (x.to_bits(), e)
}

/// `cvt.d.s`: exact widening; NaNs keep their payload and are quieted.
pub fn f32_to_f64(a: u32) -> FpResult<u64> {
    let x = f32::from_bits(a);
    if x.is_nan() {
        let bits =
            ((a >> 31) as u64) << 63 | 0x7FF0_0000_0000_0000 | ((a as u64 & 0x007F_FFFF) << 29);
        let snan = a & 0x0040_0000 == 0;
        return (bits | (1 << 51), if snan { EX_INVALID } else { 0 });
    }
    ((x as f64).to_bits(), 0)
}

/// Integer (i64) to f64 in the current rounding mode.
pub fn i64_to_f64(v: i64, fcsr: u32) -> FpResult<u64> {
    let r = v as f64;
    // Residual in integer arithmetic (r is within i64 range except at 2^63).
    let diff = if r >= 9223372036854775808.0 {
        -((r as i128 - v as i128).signum() as i8)
    } else {
        ((v as i128) - (r as i64 as i128)).signum() as i8
    };
    if diff == 0 {
        return (r.to_bits(), 0);
    }
    let (x, e) = finish(r, diff, rm(fcsr), false);
    (x.to_bits(), e)
}

/// Integer (i64) to f32 in the current rounding mode.
pub fn i64_to_f32(v: i64, fcsr: u32) -> FpResult<u32> {
    let r = v as f32;
    let ri = r as f64 as i128;
    let diff = ((v as i128) - ri).signum() as i8;
    if diff == 0 {
        return (r.to_bits(), 0);
    }
    let (x, e) = finish(r, diff, rm(fcsr), false);
    (x.to_bits(), e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bin_s_fast_path_matches_the_general_path() {
        // Edge values (zeros, subnormals, the normal boundary, near overflow, NaNs,
        // infinities) plus pseudo-random bit patterns, every operation and rounding mode.
        let mut vals: Vec<u32> = vec![
            0,
            0x8000_0000,
            1,
            0x8000_0001,
            0x007F_FFFF,
            0x0080_0000,
            0x0080_0001,
            0x3F80_0000,
            0x3F80_0001,
            0xBF80_0000,
            0x3EAA_AAAB,
            0x4040_0000,
            0x7F7F_FFFF,
            0xFF7F_FFFF,
            0x7F00_0000,
            0x0100_0000,
            0x7F80_0000,
            0xFF80_0000,
            0x7FC0_0000,
            0x7F80_0001,
        ];
        let mut x = 0x1234_5678_9ABC_DEF0u64;
        for _ in 0..300 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            vals.push((x >> 32) as u32);
        }
        for &a in &vals {
            for &b in &vals {
                for op in [BinOp::Add, BinOp::Sub, BinOp::Mul, BinOp::Div] {
                    for rm in 0..4 {
                        assert_eq!(
                            bin_s(op, a, b, rm),
                            bin_s_slow(op, a, b, rm),
                            "{op:?} {a:#010x} {b:#010x} rm {rm}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn nan_rules() {
        let qa = 0x7FC0_0001u32;
        let sb = 0x7F80_0002u32;
        assert_eq!(nan2::<f32>(qa, sb), (0x7FC0_0002, EX_INVALID));
        assert_eq!(nan2::<f32>(qa, 0x3F80_0000), (qa, 0));
        // inf - inf is the default NaN (not the host's negative NaN).
        let inf = f32::INFINITY.to_bits();
        assert_eq!(bin_s(BinOp::Sub, inf, inf, 0), (0x7FC0_0000, EX_INVALID));
    }

    #[test]
    fn inexact_and_rounding_modes() {
        let one = 1.0f32.to_bits();
        let tiny = 1e-10f32.to_bits();
        assert_eq!(bin_s(BinOp::Add, one, tiny, 0), (one, EX_INEXACT));
        assert_eq!(
            bin_s(BinOp::Add, one, tiny, 2).0,
            1.0f32.next_up().to_bits()
        );
        assert_eq!(
            bin_s(BinOp::Sub, one, tiny, 1).0,
            1.0f32.next_down().to_bits()
        );
        assert_eq!(bin_s(BinOp::Add, one, one, 0), (2.0f32.to_bits(), 0));
        // Overflow in round-toward-zero gives MAX.
        let m = f32::MAX.to_bits();
        assert_eq!(bin_s(BinOp::Add, m, m, 1), (m, EX_OVERFLOW | EX_INEXACT));
        assert_eq!(
            bin_s(BinOp::Add, m, m, 0),
            (f32::INFINITY.to_bits(), EX_OVERFLOW | EX_INEXACT)
        );
        // x - x = -0 in round-down.
        assert_eq!(bin_s(BinOp::Sub, one, one, 3).0, 0x8000_0000);
        assert_eq!(bin_s(BinOp::Sub, one, one, 0).0, 0);
        // Division by zero.
        assert_eq!(
            bin_s(BinOp::Div, one, 0, 0),
            (f32::INFINITY.to_bits(), EX_DIVZERO)
        );
        assert_eq!(bin_s(BinOp::Div, 0, 0, 0), (0x7FC0_0000, EX_INVALID));
        // 1/3 inexact in double.
        let (q, e) = bin_d(BinOp::Div, 1f64.to_bits(), 3f64.to_bits(), 0);
        assert_eq!((f64::from_bits(q), e), (1.0 / 3.0, EX_INEXACT));
        let (q, _) = bin_d(BinOp::Div, 1f64.to_bits(), 3f64.to_bits(), 2);
        assert_eq!(f64::from_bits(q), (1.0f64 / 3.0).next_up());
    }

    #[test]
    fn underflow() {
        let a = 1e-30f32.to_bits();
        let (r, e) = bin_s(BinOp::Mul, a, a, 0);
        assert_eq!(r, 0);
        assert_eq!(e, EX_UNDERFLOW | EX_INEXACT);
        // Exact subnormal result: no underflow.
        let s = f32::from_bits(2).to_bits();
        assert_eq!(bin_s(BinOp::Add, s, s, 0), (4, 0));
    }

    #[test]
    fn conversions_saturate() {
        assert_eq!(to_i32(f64::NAN, IntRound::Trunc, 0), (0, EX_INVALID));
        assert_eq!(
            to_i32(3e9, IntRound::Trunc, 0),
            (i32::MAX as u32, EX_INVALID)
        );
        assert_eq!(
            to_i32(-3e9, IntRound::Trunc, 0),
            (i32::MIN as u32, EX_INVALID)
        );
        assert_eq!(
            to_i32(-2147483648.0, IntRound::Trunc, 0),
            (i32::MIN as u32, 0)
        );
        assert_eq!(to_i32(2.5, IntRound::Nearest, 0), (2, EX_INEXACT));
        assert_eq!(to_i32(-2.5, IntRound::Floor, 0), (-3i32 as u32, EX_INEXACT));
        assert_eq!(to_i32(2.5, IntRound::Current, 2), (3, EX_INEXACT));
        assert_eq!(
            to_i64(1e30, IntRound::Trunc, 0),
            (i64::MAX as u64, EX_INVALID)
        );
    }

    #[test]
    fn min_max_class_compare() {
        let (p0, n0) = (0u32, 0x8000_0000u32);
        assert_eq!(minmax::<f32>(p0, n0, false, false).0, n0);
        assert_eq!(minmax::<f32>(p0, n0, true, false).0, p0);
        let q = 0x7FC0_0000u32;
        assert_eq!(
            minmax::<f32>(q, 1.0f32.to_bits(), false, false),
            (1.0f32.to_bits(), 0)
        );
        assert_eq!(
            minmax::<f32>((-3.0f32).to_bits(), 2.0f32.to_bits(), false, true).0,
            2.0f32.to_bits()
        );
        assert_eq!(class::<f32>(n0), 1 << 5);
        assert_eq!(class::<f32>(p0), 1 << 9);
        assert_eq!(class::<f32>(f32::NEG_INFINITY.to_bits()), 1 << 2);
        assert_eq!(class::<f32>(1), 1 << 8);
        assert_eq!(class::<f32>(0x7F80_0001), 1);
        assert_eq!(compare::<f32>(q, p0, 1), (true, 0)); // un
        assert_eq!(compare::<f32>(q, p0, 9), (true, EX_INVALID)); // sun
        assert_eq!(compare::<f32>(p0, n0, 2), (true, 0)); // eq: +0 == -0
        assert_eq!(compare::<f32>(q, p0, 19), (false, 0)); // ne: ordered and not equal
    }

    #[test]
    fn fused_multiply_add() {
        let (a, b, c) = (1.5f32.to_bits(), 2.0f32.to_bits(), 0.25f32.to_bits());
        assert_eq!(fma_s(c, a, b, false, 0), (3.25f32.to_bits(), 0));
        assert_eq!(fma_s(c, a, b, true, 0), ((-2.75f32).to_bits(), 0));
        let inf = f32::INFINITY.to_bits();
        assert_eq!(fma_s(c, inf, 0, false, 0), (0x7FC0_0000, EX_INVALID));
    }

    #[test]
    fn narrowing() {
        assert_eq!(f64_to_f32(0.1, 0).1, EX_INEXACT);
        assert_eq!(
            f64_to_f32(1e300, 0),
            (f32::INFINITY.to_bits(), EX_OVERFLOW | EX_INEXACT)
        );
        assert_eq!(
            f64_to_f32(f64::from_bits(0x7FF0_0000_0000_0001), 0).1,
            EX_INVALID
        );
        assert_eq!(
            i64_to_f32(16_777_217, 0),
            (16_777_216f32.to_bits(), EX_INEXACT)
        );
        assert_eq!(i64_to_f32(16_777_217, 2).0, 16_777_218f32.to_bits());
    }
}
