//! Rays and hit records.

use super::math::Vec3;

/// Triangle index of a [`Hit`] that hit nothing.
pub const NO_HIT: u32 = 0xFFFF_FFFF;

/// A ray `origin + t * dir`.
#[derive(Clone, Copy)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along `dir` (not normalised here).
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray { origin, dir }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir.scale(t)
    }
}

/// The closest intersection found so far.
#[derive(Clone, Copy)]
pub struct Hit {
    /// Ray parameter of the hit (the search limit while `tri == NO_HIT`).
    pub t: f32,
    /// Index of the triangle hit, or [`NO_HIT`].
    pub tri: u32,
    /// Barycentric weight of vertex 1.
    pub u: f32,
    /// Barycentric weight of vertex 2.
    pub v: f32,
}

impl Hit {
    /// No hit yet, searching up to `t_max`.
    pub fn none(t_max: f32) -> Hit {
        Hit {
            t: t_max,
            tri: NO_HIT,
            u: 0.0,
            v: 0.0,
        }
    }

    /// True if a triangle was hit.
    pub fn is_hit(&self) -> bool {
        self.tri != NO_HIT
    }
}
