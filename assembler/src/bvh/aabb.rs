//! Axis-aligned boxes.

use crate::scene::Vec3;

/// An axis-aligned box. The empty box has `min = +inf`, `max = -inf`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (identity of [`Aabb::union`]).
    pub const EMPTY: Aabb = Aabb {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    /// Box of one triangle.
    #[inline]
    pub fn of_triangle(t: &[Vec3; 3]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for v in t {
            b.grow(*v);
        }
        b
    }

    /// Extends the box to hold a point.
    #[inline]
    pub fn grow(&mut self, p: Vec3) {
        for (i, &c) in p.iter().enumerate() {
            self.min[i] = fmin(self.min[i], c);
            self.max[i] = fmax(self.max[i], c);
        }
    }

    /// Smallest box holding both.
    #[inline]
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: [0, 1, 2].map(|i| fmin(self.min[i], o.min[i])),
            max: [0, 1, 2].map(|i| fmax(self.max[i], o.max[i])),
        }
    }

    /// Whether the box holds no point.
    #[inline]
    pub fn is_empty(&self) -> bool {
        (0..3).any(|i| self.min[i] > self.max[i])
    }

    /// Surface area (0 for the empty or a degenerate box). Overflows to `inf` for extents
    /// beyond about 1e19; see [`Aabb::area_scaled`] and [`Aabb::area_f64`].
    #[inline]
    pub fn area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = [0, 1, 2].map(|i| self.max[i] - self.min[i]);
        2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    }

    /// The power of two that brings the box's largest extent into `[1, 2)` (1 for a point
    /// box, an empty box or an infinite extent). SAH costs compare areas within one node,
    /// so they are computed as [`Aabb::area_scaled`] with the node's factor: multiplying by
    /// a power of two is exact, so the comparisons are unchanged wherever the plain areas
    /// neither overflow nor underflow (extents from about 1e-19 to 1e19), and at every
    /// other scale they stay finite and accurate.
    pub fn area_scale(&self) -> f32 {
        if self.is_empty() {
            return 1.0;
        }
        let m = (0..3).fold(0.0f32, |m, i| fmax(m, self.max[i] - self.min[i]));
        pow2_inverse(m)
    }

    /// Surface area times `k²` (0 for the empty box), the extents multiplied by `k` first.
    #[inline]
    pub fn area_scaled(&self, k: f32) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = [0, 1, 2].map(|i| (self.max[i] - self.min[i]) * k);
        2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    }

    /// Surface area in f64 (never overflows for finite f32 boxes).
    pub fn area_f64(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let d = [0, 1, 2].map(|i| self.max[i] as f64 - self.min[i] as f64);
        2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    }

    /// Centre point.
    #[inline]
    pub fn center(&self) -> Vec3 {
        [0, 1, 2].map(|i| 0.5 * self.min[i] + 0.5 * self.max[i])
    }

    /// Whether `o` lies inside this box (boundaries included).
    pub fn contains(&self, o: &Aabb) -> bool {
        (0..3).all(|i| self.min[i] <= o.min[i] && o.max[i] <= self.max[i])
    }
}

/// `2^-e` for the exponent `e` of `m` (`m * 2^-e` is in `[1, 2)`); 1 for zero, infinite or
/// NaN `m`.
pub(crate) fn pow2_inverse(m: f32) -> f32 {
    if !(m > 0.0 && m.is_finite()) {
        return 1.0;
    }
    // Exponent of a normal or subnormal m, from the f64 form (exact for every f32).
    // Clamped so the factor is a finite f32 (2^-127 is subnormal but exact).
    let e = ((((m as f64).to_bits() >> 52) & 0x7ff) as i32 - 1023).clamp(-127, 127);
    f64::powi(2.0, -e) as f32
}

/// Minimum of two floats (no NaN handling: BVH input is checked to be finite), which
/// compiles to a single `minss`.
#[inline(always)]
pub(crate) fn fmin(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// Maximum of two floats (see [`fmin`]).
#[inline(always)]
pub(crate) fn fmax(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}
