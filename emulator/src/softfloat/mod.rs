//! The soft-float core: IEEE 754-2008 arithmetic for the scalar FPU ([`crate::fpu`],
//! binary32/binary64 under FCSR) and for MSA lanes ([`crate::msa`], binary16/32/64 under
//! MSACSR). One rounding mode type ([`Round`]), one set of exception flags (`FLAG_*`, the
//! bit order of the Cause/Flags/Enables fields of both FCSR and MSACSR), one NaN policy.
//!
//! Every operation has an exact path (module `exact`: operands unpacked to integers,
//! computed exactly, rounded once) and, where the host can give the same answer, a fast
//! path (module `fast`) tried first: arithmetic in round to nearest whose result is a
//! finite number above the smallest normal (or an exact zero or infinity), and compares,
//! min/max, rounding to integral values and integer conversions in any mode. The fast path answers only when its result
//! and flags are provably those of the exact path (checked by this module's tests).
//!
//! Policy (MIPS32r6 with NaN-2008 and ABS-2008; QEMU's choices where the architecture
//! leaves room, since QEMU is the test suite's oracle for both units):
//! - NaN encoding is NaN-2008 (quiet bit = most significant fraction bit set). An invalid
//!   operation with no NaN input gives the default NaN (`0x7FC00000`, `0x7FF8000000000000`,
//!   `0x7E00`). A NaN input propagates, quieted: the first signalling NaN among the
//!   operands in operand order (`fs`/`ws` before `ft`/`wt`; for fused multiply-add the
//!   accumulator first) wins, otherwise the first quiet NaN in the same order. Any
//!   signalling NaN input raises Invalid; so does `inf * 0` in a fused multiply-add even
//!   when the accumulator is a quiet NaN.
//! - Tininess is detected after rounding (as if the exponent range were unbounded);
//!   Underflow is raised when a tiny result is also inexact, or (IEEE trapped underflow,
//!   [`Env::trap_underflow`], MSA only) when Underflow is enabled, except for binary16
//!   results and min/max.
//! - Flush to zero ([`Env::ftz`], MSACSR.FS; the scalar FPU ignores FCSR.FS and always
//!   computes subnormals exactly): subnormal inputs read as zero of the same sign, raising
//!   Inexact (compares excepted), and subnormal results become zero of the same sign,
//!   raising Underflow and Inexact.
//! - Conversions to integers (r6 semantics): NaN gives 0, out-of-range values saturate;
//!   both raise Invalid (and not Inexact).
//! - MSA `frcp` is correctly rounded `1/x`; `frsqrt` is `1/sqrt(x)` as two correctly
//!   rounded steps. The architecture allows approximations here, so unless the operation
//!   is invalid or divides by zero, or the reciprocal's operand is infinite or its result a
//!   NaN, they raise exactly Inexact. (Scalar `recip`/`rsqrt` are the same two steps with
//!   the steps' own flags, as QEMU does.)
//! - `ftq` saturation raises Overflow and Inexact; a NaN gives 0 and raises Invalid.
//!
//! `rustc_apfloat` (0.2.3, LLVM's APFloat in Rust; Apache-2.0 WITH LLVM-exception; kept by
//! rust-lang for rustc and Miri, API declared unstable) was evaluated as the exact path and
//! kept as a test oracle instead (`tests/softfloat_apfloat.rs`). Its non-NaN results agree
//! with this core on 3.6M boundary-biased add/sub/mul/div/fma cases in binary16/32/64 and
//! all four modes, and on round-to-integral and i32 conversion; but it differs from
//! MIPS/QEMU where it matters here: it propagates the first NaN operand rather than the first signalling
//! one, raises no Overflow when a directed mode rounds to the largest finite number, judges
//! tininess on the format-rounded result (no Underflow for a tiny value rounded up to the
//! smallest normal), and has no square root, flush to zero or trapped-underflow rule. The
//! NaN, overflow, tininess, sqrt, FTZ, min/max and fixed-point code would all stay, so it
//! would replace only rounding and the integer kernels. Its speed on the exact path is
//! about ours (50-110 ns per operation here) except binary64 division (440 ns against
//! 66 ns); it builds in 1.5 s.

mod exact;
mod fast;
#[doc(hidden)]
pub mod testgen;

pub use exact::{exp2, from_fixed, log2, rcp, rsqrt, to_fixed};
pub use fast::{vector_fast, FastOp};

use fast::Op;

/// Inexact flag bit (as in the Cause/Flags/Enables fields of FCSR and MSACSR).
pub const FLAG_I: u32 = 1;
/// Underflow flag bit.
pub const FLAG_U: u32 = 2;
/// Overflow flag bit.
pub const FLAG_O: u32 = 4;
/// Divide-by-zero flag bit.
pub const FLAG_Z: u32 = 8;
/// Invalid-operation flag bit.
pub const FLAG_V: u32 = 16;

/// [`compare`] result bit: unordered (a NaN operand).
pub const REL_UN: u8 = 1;
/// [`compare`] result bit: equal.
pub const REL_EQ: u8 = 2;
/// [`compare`] result bit: less than.
pub const REL_LT: u8 = 4;

/// Names the exceptions in a flag mask, e.g. `"invalid operation, inexact"`.
pub fn describe_flags(flags: u32) -> String {
    let names = [
        (FLAG_V, "invalid operation"),
        (FLAG_Z, "division by zero"),
        (FLAG_O, "overflow"),
        (FLAG_U, "underflow"),
        (FLAG_I, "inexact"),
    ];
    let v: Vec<&str> = names
        .iter()
        .filter(|(b, _)| flags & b != 0)
        .map(|(_, n)| *n)
        .collect();
    v.join(", ")
}

/// IEEE rounding mode (the RM field encoding of FCSR and MSACSR).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Round {
    /// Round to nearest, ties to even (RM = 0).
    Nearest = 0,
    /// Round toward zero (RM = 1).
    Zero = 1,
    /// Round toward +infinity (RM = 2).
    Up = 2,
    /// Round toward -infinity (RM = 3).
    Down = 3,
}

impl Round {
    /// The mode selected by a 2-bit RM field (the low bits of `rm`).
    #[inline(always)]
    pub fn from_rm(rm: u32) -> Round {
        match rm & 3 {
            0 => Round::Nearest,
            1 => Round::Zero,
            2 => Round::Up,
            _ => Round::Down,
        }
    }
}

/// Floating-point format of an operand.
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
    #[inline(always)]
    fn p(self) -> i32 {
        match self {
            Fmt::H => 11,
            Fmt::S => 24,
            Fmt::D => 53,
        }
    }

    /// Exponent bias (also the maximum unbiased exponent).
    #[inline(always)]
    fn bias(self) -> i32 {
        match self {
            Fmt::H => 15,
            Fmt::S => 127,
            Fmt::D => 1023,
        }
    }

    /// Total width in bits.
    #[inline(always)]
    pub fn width(self) -> u32 {
        match self {
            Fmt::H => 16,
            Fmt::S => 32,
            Fmt::D => 64,
        }
    }

    #[inline(always)]
    fn frac_bits(self) -> u32 {
        self.p() as u32 - 1
    }

    #[inline(always)]
    fn exp_mask(self) -> u64 {
        (1u64 << (self.width() - 1 - self.frac_bits())) - 1
    }

    /// The sign bit.
    #[inline(always)]
    pub fn sign_bit(self) -> u64 {
        1u64 << (self.width() - 1)
    }

    #[inline(always)]
    fn quiet_bit(self) -> u64 {
        1u64 << (self.frac_bits() - 1)
    }

    /// The default quiet NaN.
    #[inline(always)]
    pub fn default_nan(self) -> u64 {
        (self.exp_mask() << self.frac_bits()) | self.quiet_bit()
    }

    /// 1.0.
    #[inline(always)]
    pub fn one(self) -> u64 {
        (self.bias() as u64) << self.frac_bits()
    }

    #[inline(always)]
    fn inf(self, sign: bool) -> u64 {
        (self.exp_mask() << self.frac_bits()) | if sign { self.sign_bit() } else { 0 }
    }

    #[inline(always)]
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

    /// Environment from an FCSR value: its rounding mode (RM bits 1..0); FS is ignored
    /// and underflow is signalled only when inexact, whatever the enables. No flags raised.
    #[inline(always)]
    pub fn from_fcsr(fcsr: u32) -> Env {
        Env {
            mode: Round::from_rm(fcsr),
            ftz: false,
            trap_underflow: false,
            flags: 0,
        }
    }
}

/// Runs an exact-path operation on a copy of `env` in an out-of-line function and copies
/// the environment back: the caller's environment is never address-taken, so on the fast
/// path it stays in registers.
#[inline(always)]
fn slow(env: &mut Env, g: impl FnOnce(&mut Env) -> u64) -> u64 {
    let (r, e) = out_of_line(*env, g);
    *env = e;
    r
}

#[inline(never)]
fn out_of_line(mut env: Env, g: impl FnOnce(&mut Env) -> u64) -> (u64, Env) {
    let r = g(&mut env);
    (r, env)
}

/// `a + b`.
#[inline(always)]
pub fn add(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = fast::try_lane(env, f, Op::Add, a, b, 0) {
        return r;
    }
    slow(env, move |e| exact::add_exact(e, f, a, b))
}

/// `a - b`.
#[inline(always)]
pub fn sub(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = fast::try_lane(env, f, Op::Add, a, b ^ f.sign_bit(), 0) {
        return r;
    }
    slow(env, move |e| exact::sub_exact(e, f, a, b))
}

/// `a * b`.
#[inline(always)]
pub fn mul(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = fast::try_lane(env, f, Op::Mul, a, b, 0) {
        return r;
    }
    slow(env, move |e| exact::mul_exact(e, f, a, b))
}

/// `a / b`.
#[inline(always)]
pub fn div(env: &mut Env, f: Fmt, a: u64, b: u64) -> u64 {
    if let Some(r) = fast::try_lane(env, f, Op::Div, a, b, 0) {
        return r;
    }
    slow(env, move |e| exact::div_exact(e, f, a, b))
}

/// Square root.
#[inline(always)]
pub fn sqrt(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if let Some(r) = fast::try_lane(env, f, Op::Sqrt, a, 0, 0) {
        return r;
    }
    slow(env, move |e| exact::sqrt_exact(e, f, a))
}

/// Fused `c + a*b` (or `c - a*b` when `negate` is set), rounded once.
#[inline(always)]
pub fn fma(env: &mut Env, f: Fmt, a: u64, b: u64, c: u64, negate: bool) -> u64 {
    let na = if negate { a ^ f.sign_bit() } else { a };
    if let Some(r) = fast::try_lane(env, f, Op::Fma, na, b, c) {
        return r;
    }
    slow(env, move |e| exact::fma_exact(e, f, a, b, c, negate))
}

/// The arithmetic operations [`arith`] runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arith {
    /// `a + b`.
    Add,
    /// `a - b`.
    Sub,
    /// `a * b`.
    Mul,
    /// `a / b`.
    Div,
    /// `sqrt(a)`.
    Sqrt,
    /// `c + a*b`, rounded once.
    Madd,
    /// `c - a*b`, rounded once.
    Msub,
}

/// `op` in format `f` under the FCSR rounding-mode bits `rm` (low two bits) in the scalar
/// FPU's environment ([`Env::from_fcsr`]): the result and the raised flags. The same
/// operations as [`add`], [`sub`], [`mul`], [`div`], [`sqrt`] and [`fma`], shaped for
/// the interpreter's hot loop: the fast path needs only `rm`, and the environment is
/// built on the exact path alone.
#[inline(always)]
pub fn arith(op: Arith, f: Fmt, a: u64, b: u64, c: u64, rm: u32) -> (u64, u32) {
    if rm & 3 == 0 {
        let neg = f.sign_bit();
        let lane = match op {
            Arith::Add => fast::lane(f, Op::Add, a, b, 0),
            Arith::Sub => fast::lane(f, Op::Add, a, b ^ neg, 0),
            Arith::Mul => fast::lane(f, Op::Mul, a, b, 0),
            Arith::Div => fast::lane(f, Op::Div, a, b, 0),
            Arith::Sqrt => fast::lane(f, Op::Sqrt, a, 0, 0),
            Arith::Madd => fast::lane(f, Op::Fma, a, b, c),
            Arith::Msub => fast::lane(f, Op::Fma, a ^ neg, b, c),
        };
        if let Some((r, inexact)) = lane {
            return (r, inexact as u32 * FLAG_I);
        }
    }
    arith_exact(op, f, a, b, c, rm)
}

#[inline(never)]
fn arith_exact(op: Arith, f: Fmt, a: u64, b: u64, c: u64, rm: u32) -> (u64, u32) {
    let e = &mut Env::from_fcsr(rm);
    let r = match op {
        Arith::Add => exact::add_exact(e, f, a, b),
        Arith::Sub => exact::sub_exact(e, f, a, b),
        Arith::Mul => exact::mul_exact(e, f, a, b),
        Arith::Div => exact::div_exact(e, f, a, b),
        Arith::Sqrt => exact::sqrt_exact(e, f, a),
        Arith::Madd => exact::fma_exact(e, f, a, b, c, false),
        Arith::Msub => exact::fma_exact(e, f, a, b, c, true),
    };
    (r, e.flags)
}

/// IEEE comparison: `REL_UN`, `REL_EQ`, `REL_LT` or 0 (greater). Signalling compares
/// raise Invalid on any NaN, quiet compares only on signalling NaNs. Compares never
/// raise Inexact (not even when flushing subnormal inputs).
///
/// The bits are those of the MIPS `cmp.cond.fmt` condition field, so a condition holds
/// when `cond & rel & 7 != 0`, negated by `cond & 16`.
#[inline(always)]
pub fn compare(env: &mut Env, f: Fmt, a: u64, b: u64, signaling: bool) -> u8 {
    if !env.ftz {
        if let Some(r) = fast::compare(env, f, a, b, signaling) {
            return r;
        }
    }
    slow(env, move |e| {
        exact::compare_exact(e, f, a, b, signaling) as u64
    }) as u8
}

/// [`compare`] when neither operand is a NaN: the relation (`REL_EQ`, `REL_LT` or 0), and
/// no exception is raised (with or without flush to zero: zero compares equal to a
/// subnormal of either sign only when flushing, so callers that flush must not use it).
/// `None` for a NaN operand or binary16.
#[inline(always)]
pub fn compare_ordered(f: Fmt, a: u64, b: u64) -> Option<u8> {
    fast::compare_ordered(f, a, b)
}

/// Whether a `cmp.cond.fmt` condition (bits: unordered 1, equal 2, less 4, negate 16;
/// bit 8, signalling, is the caller's business) holds for a [`compare`] result.
#[inline(always)]
pub fn cond_holds(rel: u8, cond: u8) -> bool {
    (rel & cond & 7 != 0) ^ (cond & 16 != 0)
}

/// Which operand a min/max picks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MinMax {
    /// `max`, `fmax`.
    Max,
    /// `min`, `fmin`.
    Min,
    /// `maxa`, `fmax_a` (larger magnitude).
    MaxA,
    /// `mina`, `fmin_a` (smaller magnitude).
    MinA,
}

/// IEEE 754-2008 maxNum/minNum (and the magnitude forms): a quiet NaN loses against a
/// number; signalling NaNs raise Invalid and propagate; `max(-0, +0) = +0`,
/// `min(-0, +0) = -0`; for the magnitude forms equal magnitudes fall back to the plain
/// form.
#[inline(always)]
pub fn min_max(env: &mut Env, f: Fmt, a: u64, b: u64, kind: MinMax) -> u64 {
    if !env.ftz {
        if let Some(r) = fast::min_max(f, a, b, kind) {
            return r;
        }
    }
    slow(env, move |e| exact::min_max_exact(e, f, a, b, kind))
}

/// `class.fmt`/`fclass` bit mask: 0 sNaN, 1 qNaN, 2..5 negative
/// infinity/normal/subnormal/zero, 6..9 the same positive. Raises nothing.
pub fn class(f: Fmt, a: u64) -> u64 {
    let neg = a & f.sign_bit() != 0;
    let e = (a >> f.frac_bits()) & f.exp_mask();
    let frac = a & ((1u64 << f.frac_bits()) - 1);
    // 0 infinity, 1 normal, 2 subnormal, 3 zero.
    let k = if e == f.exp_mask() {
        if frac != 0 {
            return if frac & f.quiet_bit() == 0 { 1 } else { 2 };
        }
        0
    } else if e != 0 {
        1
    } else if frac != 0 {
        2
    } else {
        3
    };
    if neg {
        1 << (2 + k)
    } else {
        1 << (6 + k)
    }
}

/// Converts to a `bits`-wide integer (signed or unsigned) rounding per `mode`.
///
/// NaN gives 0; out-of-range values saturate; both raise Invalid (and not Inexact).
#[inline(always)]
pub fn to_int(env: &mut Env, f: Fmt, a: u64, mode: Round, signed: bool, bits: u32) -> u64 {
    if !env.ftz {
        if let Some(r) = fast::to_int(env, f, a, mode, signed, bits) {
            return r;
        }
    }
    slow(env, move |e| {
        exact::to_int_exact(e, f, a, mode, signed, bits)
    })
}

/// Converts an integer to format `f`, rounding per the environment.
#[inline(always)]
pub fn from_int(env: &mut Env, f: Fmt, v: i128) -> u64 {
    if let Some(r) = fast::from_int(env, f, v) {
        return r;
    }
    slow(env, move |e| exact::from_int_exact(e, f, v))
}

/// Rounds to an integral value in the same format (`rint`, `frint`), raising Inexact.
#[inline(always)]
pub fn rint(env: &mut Env, f: Fmt, a: u64) -> u64 {
    if !env.ftz {
        if let Some(r) = fast::rint(env, f, a) {
            return r;
        }
    }
    slow(env, move |e| exact::rint_exact(e, f, a))
}

/// Converts between formats (`cvt.d.s`, `fexupl/r` widen exactly; `cvt.s.d`, `fexdo`
/// narrow with rounding). NaNs keep their sign and the top of their payload and are
/// quieted; a signalling NaN raises Invalid.
#[inline(always)]
pub fn convert(env: &mut Env, from: Fmt, to: Fmt, a: u64) -> u64 {
    if let Some(r) = fast::convert(env, from, to, a) {
        return r;
    }
    slow(env, move |e| exact::convert_exact(e, from, to, a))
}

#[cfg(test)]
mod tests;
