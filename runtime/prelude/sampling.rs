//! Random sampling helpers built on `trax::rand` (deterministic per thread).

use super::math::Vec3;
use super::scene::Triangle;

/// An orthonormal basis around a unit normal `n`.
#[derive(Clone, Copy)]
pub struct Onb {
    pub t: Vec3,
    pub b: Vec3,
    pub n: Vec3,
}

impl Onb {
    /// A basis with `n` as its third axis (Duff et al. 2017, branch on the sign of z).
    pub fn new(n: Vec3) -> Onb {
        let sign: f32 = if n.z < 0.0 { -1.0 } else { 1.0 };
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Onb {
            t: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            b: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            n,
        }
    }

    /// Local coordinates `l` (z along `n`) to world space.
    pub fn to_world(self, l: Vec3) -> Vec3 {
        self.t.scale(l.x) + self.b.scale(l.y) + self.n.scale(l.z)
    }
}

/// A uniformly random point of the unit disk, as `(x, y, 0)` (rejection sampling).
pub fn unit_disk() -> Vec3 {
    loop {
        let x = 2.0 * super::rand() - 1.0;
        let y = 2.0 * super::rand() - 1.0;
        if x * x + y * y < 1.0 {
            return Vec3::new(x, y, 0.0);
        }
    }
}

/// A cosine-weighted random direction in the hemisphere around unit normal `n`
/// (Malley's method; pdf = cos(theta) / pi).
pub fn cosine_hemisphere(n: Vec3) -> Vec3 {
    let d = unit_disk();
    let z = super::max(0.0, 1.0 - d.x * d.x - d.y * d.y).sqrt();
    Onb::new(n).to_world(Vec3::new(d.x, d.y, z))
}

/// A uniformly random direction on the unit sphere.
pub fn unit_sphere() -> Vec3 {
    loop {
        let p = Vec3::new(
            2.0 * super::rand() - 1.0,
            2.0 * super::rand() - 1.0,
            2.0 * super::rand() - 1.0,
        );
        let l2 = p.length_squared();
        if l2 < 1.0 && l2 > 1e-8 {
            return p.scale(super::invsqrt(l2));
        }
    }
}

/// A uniformly random point of triangle `tri`.
pub fn triangle_point(tri: &Triangle) -> Vec3 {
    let su = super::rand().sqrt();
    let r2 = super::rand();
    tri.point(r2 * su, 1.0 - su)
}

/// What next-event estimation needs about a point `q` sampled on an emitting triangle,
/// seen from `p`: [`emitter_geometry`].
#[derive(Clone, Copy)]
pub struct EmitterGeometry {
    /// Unit direction from `p` to `q`.
    pub dir: Vec3,
    /// Distance from `p` to `q`.
    pub dist: f32,
    /// Squared distance, in the same units as `area` (see there).
    pub dist2: f32,
    /// The triangle's area, in units where `area / dist2` is the true ratio: the plain
    /// values when both are normal f32s, else both multiplied by the same power of two
    /// squared (a huge scene's squares overflow, a tiny one's underflow).
    pub area: f32,
    /// The triangle's unit geometric normal ([`Triangle::normal`]).
    pub normal: Vec3,
}

/// Direction, distance, area-to-distance-squared ratio and the emitter's normal, from `p`
/// to the point `q` of triangle `tri`, right at every scale. Bit for bit the plain
/// `length_squared`, `sqrt`, `scale(1 / dist)`, `Triangle::area` and `Triangle::normal`
/// wherever those neither overflow nor underflow.
pub fn emitter_geometry(tri: &Triangle, p: Vec3, q: Vec3) -> EmitterGeometry {
    let d = q - p;
    let dist2 = d.length_squared();
    let c = tri.normal_unnormalized();
    let c2 = c.dot(c);
    if super::math::in_range(dist2) && super::math::in_range(c2) {
        let dist = dist2.sqrt();
        return EmitterGeometry {
            dir: d.scale(1.0 / dist),
            dist,
            dist2,
            area: 0.5 * c2.sqrt(),
            normal: c.scale(super::invsqrt(c2)),
        };
    }
    let k = super::math::pow2_scale(d.max_abs());
    let ds = d.scale(k);
    let dist2 = ds.length_squared();
    let dist_s = dist2.sqrt();
    EmitterGeometry {
        dir: ds.scale(1.0 / dist_s),
        dist: dist_s / k,
        dist2,
        area: tri.area_scaled(k),
        normal: tri.normal(),
    }
}
