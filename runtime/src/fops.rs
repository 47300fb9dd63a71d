//! Exact results of the TRaX extension's f32 operations (`trax.fmin`, `trax.fmax`,
//! `trax.invsqrt`).
//!
//! Shared verbatim by the emulator (through `trax_runtime::fops`) and the host
//! implementation of the kernel prelude (`prelude/hw_host.rs` includes it with
//! `#[path]`), so a kernel gives bit-identical results on both. Dependency-free.

/// `trax.fmin`: IEEE 754-2008 minNum. A quiet or signalling NaN operand is ignored when
/// the other is a number (both NaN: the first, quieted); `min(-0, +0) = -0`.
pub fn fmin(a: f32, b: f32) -> f32 {
    if a.is_nan() {
        if b.is_nan() {
            return quiet(a);
        }
        return b;
    }
    if b.is_nan() || a < b {
        return a;
    }
    if b < a {
        return b;
    }
    // Equal: differs only for zeros of opposite sign; prefer -0.
    f32::from_bits(a.to_bits() | b.to_bits())
}

/// `trax.fmax`: IEEE 754-2008 maxNum, NaN handling as [`fmin`]; `max(-0, +0) = +0`.
pub fn fmax(a: f32, b: f32) -> f32 {
    if a.is_nan() {
        if b.is_nan() {
            return quiet(a);
        }
        return b;
    }
    if b.is_nan() || a > b {
        return a;
    }
    if b > a {
        return b;
    }
    f32::from_bits(a.to_bits() & b.to_bits())
}

/// `trax.invsqrt`: `1 / sqrt(x)`, evaluated in f64 and rounded once to f32.
///
/// Special cases follow from that: `+0 -> +inf`, `-0 -> -inf`, `+inf -> +0`,
/// negative or NaN -> quiet NaN.
pub fn invsqrt(x: f32) -> f32 {
    if x.is_nan() {
        return quiet(x);
    }
    (1.0 / (x as f64).sqrt()) as f32
}

/// The NaN `x` with its quiet bit set (NaN-2008 encoding).
fn quiet(x: f32) -> f32 {
    f32::from_bits(x.to_bits() | 0x0040_0000)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_max_numbers_and_nans() {
        assert_eq!(fmin(1.0, 2.0), 1.0);
        assert_eq!(fmax(1.0, 2.0), 2.0);
        assert_eq!(fmin(f32::NAN, 3.0), 3.0);
        assert_eq!(fmin(3.0, f32::NAN), 3.0);
        assert_eq!(fmax(f32::NAN, -3.0), -3.0);
        assert!(fmin(f32::NAN, f32::NAN).is_nan());
        let snan = f32::from_bits(0x7F80_0001);
        assert_eq!(fmax(snan, snan).to_bits(), 0x7FC0_0001);
        assert_eq!(fmin(f32::NEG_INFINITY, 0.0), f32::NEG_INFINITY);
    }

    #[test]
    fn signed_zeros() {
        assert_eq!(fmin(0.0, -0.0).to_bits(), (-0.0f32).to_bits());
        assert_eq!(fmin(-0.0, 0.0).to_bits(), (-0.0f32).to_bits());
        assert_eq!(fmax(0.0, -0.0).to_bits(), 0.0f32.to_bits());
        assert_eq!(fmax(-0.0, 0.0).to_bits(), 0.0f32.to_bits());
    }

    #[test]
    fn invsqrt_values() {
        assert_eq!(invsqrt(4.0), 0.5);
        assert_eq!(invsqrt(0.0), f32::INFINITY);
        assert_eq!(invsqrt(-0.0), f32::NEG_INFINITY);
        assert_eq!(invsqrt(f32::INFINITY), 0.0);
        assert!(invsqrt(-1.0).is_nan());
        assert!(invsqrt(f32::NAN).is_nan());
        let x = 2.0f32;
        assert!((invsqrt(x) - std::f32::consts::FRAC_1_SQRT_2).abs() <= f32::EPSILON);
    }
}
