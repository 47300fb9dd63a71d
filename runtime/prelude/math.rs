//! 3-vectors (points, directions and linear RGB colours) and scalar helpers.

/// A 3-component f32 vector; also used for linear RGB colours (`x` = red).
#[derive(Clone, Copy)]
pub struct Vec3 {
    pub x: f32,
    pub y: f32,
    pub z: f32,
}

impl Vec3 {
    /// `(x, y, z)`.
    pub fn new(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3 { x, y, z }
    }

    /// `(s, s, s)`.
    pub fn splat(s: f32) -> Vec3 {
        Vec3 { x: s, y: s, z: s }
    }

    /// `(0, 0, 0)`.
    pub fn zero() -> Vec3 {
        Vec3 {
            x: 0.0,
            y: 0.0,
            z: 0.0,
        }
    }

    /// Component `i` (0 = x, 1 = y, otherwise z).
    pub fn get(&self, i: u32) -> f32 {
        if i == 0 {
            self.x
        } else if i == 1 {
            self.y
        } else {
            self.z
        }
    }

    /// Every component multiplied by `s`.
    pub fn scale(self, s: f32) -> Vec3 {
        Vec3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// Dot product.
    pub fn dot(self, o: Vec3) -> f32 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// Squared length (overflows for components beyond about 1e19 and underflows below
    /// about 1e-19; see [`Vec3::length`]).
    pub fn length_squared(self) -> f32 {
        self.dot(self)
    }

    /// Length, at every scale. The squared length overflows for components beyond about
    /// 1e19 and underflows below about 1e-19; then it is computed on the vector multiplied
    /// by [`pow2_scale`] of its largest component and divided by that factor again (both
    /// exact). Bit for bit `length_squared().sqrt()` wherever that one works.
    pub fn length(self) -> f32 {
        let d = self.dot(self);
        if in_range(d) {
            return d.sqrt();
        }
        let k = pow2_scale(self.max_abs());
        let s = self.scale(k);
        s.dot(s).sqrt() / k
    }

    /// Unit vector in the same direction (uses `trax.invsqrt`), at every scale: when the
    /// squared length overflows or underflows, the vector is first multiplied by the power
    /// of two that brings its largest component to about 1 ([`pow2_scale`], exact). Bit for
    /// bit `self.scale(invsqrt(self.dot(self)))` wherever that one works.
    pub fn normalize(self) -> Vec3 {
        let d = self.dot(self);
        if in_range(d) {
            return self.scale(super::invsqrt(d));
        }
        let s = self.scale(pow2_scale(self.max_abs()));
        s.scale(super::invsqrt(s.dot(s)))
    }

    /// Component-wise minimum.
    pub fn min(self, o: Vec3) -> Vec3 {
        Vec3 {
            x: super::min(self.x, o.x),
            y: super::min(self.y, o.y),
            z: super::min(self.z, o.z),
        }
    }

    /// Component-wise maximum.
    pub fn max(self, o: Vec3) -> Vec3 {
        Vec3 {
            x: super::max(self.x, o.x),
            y: super::max(self.y, o.y),
            z: super::max(self.z, o.z),
        }
    }

    /// Largest absolute value of the components (the vector's magnitude, up to a factor
    /// of at most √3).
    pub fn max_abs(self) -> f32 {
        super::max(self.x.abs(), super::max(self.y.abs(), self.z.abs()))
    }

    /// Smallest component.
    pub fn min_component(self) -> f32 {
        super::min(self.x, super::min(self.y, self.z))
    }

    /// Largest component.
    pub fn max_component(self) -> f32 {
        super::max(self.x, super::max(self.y, self.z))
    }

    /// Component-wise absolute value.
    pub fn abs(self) -> Vec3 {
        Vec3 {
            x: self.x.abs(),
            y: self.y.abs(),
            z: self.z.abs(),
        }
    }

    /// Index (0, 1 or 2) of the component with the largest absolute value.
    pub fn max_dimension(self) -> u32 {
        let a = self.abs();
        if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        }
    }

    /// Each component clamped to `[lo, hi]`.
    pub fn clamp(self, lo: f32, hi: f32) -> Vec3 {
        Vec3 {
            x: clampf(self.x, lo, hi),
            y: clampf(self.y, lo, hi),
            z: clampf(self.z, lo, hi),
        }
    }

    /// `self + (o - self) * t`.
    pub fn lerp(self, o: Vec3, t: f32) -> Vec3 {
        self + (o - self).scale(t)
    }

    /// Mirror reflection of direction `self` about unit normal `n`.
    pub fn reflect(self, n: Vec3) -> Vec3 {
        self - n.scale(2.0 * self.dot(n))
    }

    /// Relative luminance of a linear RGB colour (Rec. 709 weights).
    pub fn luminance(self) -> f32 {
        0.2126 * self.x + 0.7152 * self.y + 0.0722 * self.z
    }

    /// True if every component is zero.
    pub fn is_black(self) -> bool {
        self.x == 0.0 && self.y == 0.0 && self.z == 0.0
    }
}

impl std::ops::Add for Vec3 {
    type Output = Vec3;
    fn add(self, o: Vec3) -> Vec3 {
        Vec3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl std::ops::Sub for Vec3 {
    type Output = Vec3;
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

/// Component-wise product (colour filtering).
impl std::ops::Mul for Vec3 {
    type Output = Vec3;
    fn mul(self, o: Vec3) -> Vec3 {
        Vec3 {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }
}

/// Component-wise quotient.
impl std::ops::Div for Vec3 {
    type Output = Vec3;
    fn div(self, o: Vec3) -> Vec3 {
        Vec3 {
            x: self.x / o.x,
            y: self.y / o.y,
            z: self.z / o.z,
        }
    }
}

impl std::ops::Neg for Vec3 {
    type Output = Vec3;
    fn neg(self) -> Vec3 {
        Vec3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl std::ops::AddAssign for Vec3 {
    fn add_assign(&mut self, o: Vec3) {
        self.x = self.x + o.x;
        self.y = self.y + o.y;
        self.z = self.z + o.z;
    }
}

impl std::ops::SubAssign for Vec3 {
    fn sub_assign(&mut self, o: Vec3) {
        self.x = self.x - o.x;
        self.y = self.y - o.y;
        self.z = self.z - o.z;
    }
}

impl std::ops::MulAssign for Vec3 {
    fn mul_assign(&mut self, o: Vec3) {
        self.x = self.x * o.x;
        self.y = self.y * o.y;
        self.z = self.z * o.z;
    }
}

impl std::ops::DivAssign for Vec3 {
    fn div_assign(&mut self, o: Vec3) {
        self.x = self.x / o.x;
        self.y = self.y / o.y;
        self.z = self.z / o.z;
    }
}

/// The power of two `k` with `m * k` in `[1, 2)`, for `m >= 0`: the factor that brings a
/// quantity of magnitude `m` to about 1. Multiplying by it is exact (absent overflow and
/// underflow), so a computation done on `k`-scaled inputs gives exactly `k^n` times the
/// unscaled result wherever the unscaled one neither overflows nor underflows, and stays
/// accurate at every other scale. `k` is a normal f32: `m` is clamped to at most 2^126
/// first (so huge, infinite and NaN `m` get 2^-126), and zero and subnormal `m` get 2^127.
/// A few integer instructions on the bits of `m` (the same function as the runtime's
/// `pipes::pow2_scale`, which the fused triangle pipeline uses).
#[inline(always)]
pub fn pow2_scale(m: f32) -> f32 {
    let m = super::min(m, POW2_126);
    f32::from_bits(0x7F00_0000 - (m.to_bits() & 0x7F80_0000))
}

/// 2^126, the largest magnitude [`pow2_scale`] scales (to 2^-126, a normal f32).
pub const POW2_126: f32 = 8.507_059e37;

/// True if `x` lies between the smallest
/// positive normal f32 and the largest finite one (false for zero, subnormals, infinities
/// and NaN): a squared length in this range has lost nothing to underflow or overflow.
pub fn in_range(x: f32) -> bool {
    // Positive normal f32s are the bit patterns 0x0080_0000 ..= 0x7F7F_FFFF (integer
    // instructions only: cheaper here than two float compares).
    x.to_bits().wrapping_sub(0x0080_0000) < 0x7F00_0000
}

/// `x` clamped to `[lo, hi]` (NaN stays NaN).
pub fn clampf(x: f32, lo: f32, hi: f32) -> f32 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}
