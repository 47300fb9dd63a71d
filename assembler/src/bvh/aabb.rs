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

    /// Surface area (0 for the empty or a degenerate box), computed so that boxes from
    /// 1e-6 to 1e6 neither overflow nor produce NaN.
    #[inline]
    pub fn area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = [0, 1, 2].map(|i| self.max[i] - self.min[i]);
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
