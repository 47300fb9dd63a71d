//! Rays, hit records and surface points with their ray-origin offsets.

use super::math::Vec3;
use super::scene::Triangle;

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

/// Relative rounding-error bound of a hit point computed from barycentrics: pbrt's
/// `gamma(7) = 7u / (1 - 7u)` (`u = 2^-24`) for `b0 v0 + b1 v1 + b2 v2` with inexact
/// barycentrics (pbrt-v3 section 3.9), taken as 2^-20 = 16u. The margin stands in for
/// pbrt's final step, which rounds the offset origin one ulp further away per component
/// (here the addition `p + n * offset` may round back by up to `u |p|`), and for the
/// conservative `t > error` test pbrt's triangle intersection adds (ours rejects `t <= 0`
/// only).
pub const POINT_ERROR: f32 = 1.0 / 1_048_576.0;

/// A ray's hit on a triangle, ready for shading and for spawning new rays.
///
/// Ray origins are offset from the surface by the hit point's own rounding error
/// (pbrt's method): the error is relative to the magnitude of the coordinates, so the
/// offset is right at every scene scale, unlike a fixed epsilon, which is too large for
/// tiny scenes (rays leave the scene) and too small for huge ones (rays hit the surface
/// they leave).
#[derive(Clone, Copy)]
pub struct SurfacePoint {
    /// The hit point, `b0 v0 + b1 v1 + b2 v2` from the hit's barycentrics (on the triangle
    /// up to rounding, however inaccurate the hit distance).
    pub p: Vec3,
    /// Unit geometric normal, turned to face the incoming ray.
    pub n: Vec3,
    /// Distance along `n` that clears `p`'s rounding error: `dot(|n|, err)` with
    /// `err = POINT_ERROR * (|b0 v0| + |b1 v1| + |b2 v2|)` per component.
    pub offset: f32,
}

impl SurfacePoint {
    /// The point where `ray` hit triangle `tri` (`hit` from the same triangle).
    pub fn new(ray: &Ray, hit: &Hit, tri: &Triangle) -> SurfacePoint {
        let p0 = tri.v0.scale(1.0 - hit.u - hit.v);
        let p1 = tri.v1.scale(hit.u);
        let p2 = tri.v2.scale(hit.v);
        let mut n = tri.normal();
        if n.dot(ray.dir) > 0.0 {
            n = -n;
        }
        SurfacePoint {
            p: p0 + p1 + p2,
            n,
            offset: POINT_ERROR * n.abs().dot(p0.abs() + p1.abs() + p2.abs()),
        }
    }

    /// Origin for rays leaving on the side of the surface the incoming ray came from
    /// (reflected, diffuse and shadow rays): `p` moved `offset` along `n`. Such rays
    /// cannot hit the surface they leave, so they may start their search at `t = 0`.
    pub fn origin(&self) -> Vec3 {
        self.p + self.n.scale(self.offset)
    }

    /// Origin for rays leaving on the other side (transmitted rays).
    pub fn origin_below(&self) -> Vec3 {
        self.p - self.n.scale(self.offset)
    }
}
