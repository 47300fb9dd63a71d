//! Random operands for testing floating point (this module's unit tests,
//! `tests/fpu_qemu.rs`, `tests/softfloat_apfloat.rs`): uniform bits find little, so the
//! operands are biased to the places where soft-float goes wrong.

use super::Fmt;

/// A deterministic xorshift64 generator.
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// A value below `n`.
    pub fn below(&mut self, n: u64) -> u64 {
        self.u64() % n
    }

    /// Operand bits of format `f`: zeros, subnormals, the smallest and largest normals,
    /// infinities, quiet and signalling NaNs; exponents whose products, quotients and sums
    /// land near the underflow or overflow threshold (and, for binary64, near binary32's
    /// underflow threshold, for narrowing); integers and halves; small integers; uniform
    /// bits.
    pub fn operand(&mut self, f: Fmt) -> u64 {
        let x = self.u64();
        let fb = f.frac_bits();
        let sign = (x >> 63) * f.sign_bit();
        let m = self.u64() & ((1 << fb) - 1);
        let emax = f.exp_mask();
        let e = |lo: u64, n: u64| ((lo + (x >> 40) % n) & emax) << fb;
        let mid = emax / 2;
        match x % 12 {
            0 => {
                let edge = [
                    0,
                    1,
                    (1 << fb) - 1,
                    1 << fb,
                    (1 << fb) + 1,
                    f.max_finite(false),
                    f.inf(false),
                    f.default_nan(),
                    f.inf(false) | 1,
                    f.one(),
                    f.one() + 1,
                    f.default_nan() | 0x15,
                ];
                edge[(x >> 20) as usize % edge.len()] | sign
            }
            1 => sign | m,
            2 | 3 => sign | e(mid / 4, mid / 2) | m,
            4 => sign | e(mid - 4, 8) | m,
            5 => sign | e(emax - 10, 10) | m,
            6 => sign | e(1, 5) | m,
            7 if f == Fmt::D => sign | e(1023 - 160, 40) | m,
            8 => sign | e(mid + 20, 50) | (m & !0xFFFF),
            9 => {
                let v = (x >> 32) % 4000;
                let v = v as f64 - 2000.0;
                match f {
                    Fmt::S => (v as f32).to_bits() as u64,
                    Fmt::D => v.to_bits(),
                    Fmt::H => sign | m,
                }
            }
            _ => x & (u64::MAX >> (64 - f.width())),
        }
    }
}
