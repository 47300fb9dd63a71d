//! Ray/scene intersection: a watertight ray/triangle test (Woop, Benthin and Wald,
//! "Watertight Ray/Triangle Intersection", JCGT 2013), a robust slab test for BVH boxes,
//! and closest-hit / any-hit BVH traversal.

use super::hw;
use super::math::Vec3;
use super::ray::{Hit, Ray};
use super::scene;
use super::scene::{BvhNode, Triangle};

/// Maximum BVH depth supported by the traversal stack.
pub const STACK_SIZE: u32 = 64;

/// `1 + 2 * gamma(3)` with `gamma(n) = n*eps / (1 - n*eps)`, `eps = 2^-24`: scaling the
/// far slab distance by this makes the box test conservative under f32 rounding.
const SLAB_FAR_SCALE: f32 = 1.000_000_4;

/// Constants of pbrt's bound on the rounding error of a triangle hit's `t` (times
/// `|det|`), from `gamma(n) = n u / (1 - n u)`, `u = 2^-24`, rounded up:
/// `6 gamma(3)` (the `maxE` terms), `6 (gamma(2) + 2 gamma(5))` and `12 gamma(5)` (three
/// times `deltaE = 2 (gamma(2) X Y + gamma(5) (Y + Z) X + gamma(5) (X + Z) Y)` with
/// `X = Y`).
const ERR_T: f32 = 1.072_884e-6;
const ERR_XY: f32 = 4.291_536e-6;
const ERR_Z: f32 = 3.576_280_3e-6;

/// Per-ray constants of the watertight triangle test.
///
/// The edge functions are products of two sheared coordinates, and the scaled distance
/// adds a third factor, so in plain f32 they overflow for coordinates beyond about 1e12 and
/// underflow below about 1e-13. The sheared x and y coordinates are therefore multiplied by
/// a power of two, [`TriRay::scale`], that brings the magnitude of the ray origin and of the
/// scene to about 1: the edge functions and the determinant then stay near 1 and the
/// scaled distance near the hit distance at every scale, and the distance and barycentrics
/// come out unscaled (the factor cancels in their quotients). Multiplying by a power of two
/// is exact, so wherever the plain computation was in range the result is bit for bit the
/// same.
#[derive(Clone, Copy)]
pub struct TriRay {
    pub origin: Vec3,
    pub kx: u32,
    pub ky: u32,
    pub kz: u32,
    pub sx: f32,
    pub sy: f32,
    pub sz: f32,
    /// The power of two the sheared x and y coordinates are multiplied by.
    pub scale: f32,
    /// `scale * |dir[kz]|`: converts a z distance in units of the ray parameter to
    /// scaled units (for the error bound).
    pub scale_dz: f32,
}

impl TriRay {
    /// Precomputes the shear/permutation of `ray` and the scale for triangles whose
    /// coordinates are at most about `bound` in magnitude (for example [`scene_bound`]).
    /// The bound need not be tight: the test stays exact for triangles within a factor of
    /// about 2^±30 of `max(bound, |origin|)`.
    #[inline(always)]
    pub fn new(ray: &Ray, bound: f32) -> TriRay {
        let kz = ray.dir.max_dimension();
        let a: u32 = if kz == 2 { 0 } else { kz + 1 };
        let b: u32 = if a == 2 { 0 } else { a + 1 };
        let dz = ray.dir.get(kz);
        // Swap x and y for a negative z so the winding does not depend on the sign.
        let kx = if dz < 0.0 { b } else { a };
        let ky = if dz < 0.0 { a } else { b };
        let scale = super::math::pow2_scale(super::max(ray.origin.max_abs(), bound));
        TriRay {
            origin: ray.origin,
            kx,
            ky,
            kz,
            sx: ray.dir.get(kx) / dz,
            sy: ray.dir.get(ky) / dz,
            sz: 1.0 / dz,
            scale,
            scale_dz: scale * dz.abs(),
        }
    }

    /// Tests `tri` for a hit with `t_min < t < hit.t`; on a hit updates `hit.t`, `hit.u`,
    /// `hit.v` (not `hit.tri`) and returns true. Edges and vertices shared by two
    /// triangles are hit by at least one of them.
    pub fn intersect(&self, tri: &Triangle, t_min: f32, hit: &mut Hit) -> bool {
        let a = tri.v0 - self.origin;
        let b = tri.v1 - self.origin;
        let c = tri.v2 - self.origin;
        let az = a.get(self.kz);
        let bz = b.get(self.kz);
        let cz = c.get(self.kz);
        let k = self.scale;
        let ax = (a.get(self.kx) - self.sx * az) * k;
        let ay = (a.get(self.ky) - self.sy * az) * k;
        let bx = (b.get(self.kx) - self.sx * bz) * k;
        let by = (b.get(self.ky) - self.sy * bz) * k;
        let cx = (c.get(self.kx) - self.sx * cz) * k;
        let cy = (c.get(self.ky) - self.sy * cz) * k;
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        // Exactly on an edge in single precision: decide in double precision.
        if u == 0.0 || v == 0.0 || w == 0.0 {
            u = ((cx as f64) * (by as f64) - (cy as f64) * (bx as f64)) as f32;
            v = ((ax as f64) * (cy as f64) - (ay as f64) * (cx as f64)) as f32;
            w = ((bx as f64) * (ay as f64) - (by as f64) * (ax as f64)) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return false;
        }
        let det = u + v + w;
        if det == 0.0 {
            return false;
        }
        let azt = self.sz * az;
        let bzt = self.sz * bz;
        let czt = self.sz * cz;
        let t_scaled = u * azt + v * bzt + w * czt;
        // Compare t = t_scaled / det against the interval without dividing.
        if det > 0.0 {
            if t_scaled <= t_min * det || t_scaled >= hit.t * det {
                return false;
            }
        } else if t_scaled >= t_min * det || t_scaled <= hit.t * det {
            return false;
        }
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;
        // Guard the rounding of the division against the interval once more.
        if t <= t_min || t >= hit.t {
            return false;
        }
        // pbrt's conservative test (pbrt-v3 section 3.9.6): a hit closer than the bound on
        // the rounding error of `t` might be behind the origin, as when a ray leaves the
        // surface it starts on ([`super::ray::SurfacePoint`]); reject it. Here x and y
        // carry the scale `k` (the edge functions `k²`) and z is in units of `t`
        // (`z * sz`); the shear's error in x and y involves the plain z, `max_zt * |dz|`,
        // scaled like x and y. pbrt's bound `3 (gamma3 maxE maxZt + deltaE maxZt +
        // deltaZ maxE) / |det|` is compared multiplied by `|det|` (no division), with the
        // largest |x| and |y| taken together and `maxE <= |det|` (u, v, w share a sign).
        let max_zt = super::max(azt.abs(), super::max(bzt.abs(), czt.abs()));
        let max_xy = super::max(
            super::max(ax.abs(), super::max(bx.abs(), cx.abs())),
            super::max(ay.abs(), super::max(by.abs(), cy.abs())),
        );
        let kz = self.scale_dz * max_zt;
        let bound = max_zt * (ERR_T * det.abs() + max_xy * (ERR_XY * max_xy + ERR_Z * kz));
        let t_det = if det > 0.0 { t_scaled } else { -t_scaled };
        if t_det <= bound {
            return false;
        }
        hit.t = t;
        hit.u = v * inv_det;
        hit.v = w * inv_det;
        true
    }
}

/// Largest absolute coordinate of BVH node `n`'s box.
#[inline(always)]
pub fn node_bound(n: &BvhNode) -> f32 {
    super::max(n.min.max_abs(), n.max.max_abs())
}

/// Largest absolute coordinate of the scene: of the BVH's root box, or, without a BVH, of
/// every triangle vertex. The bound [`TriRay::new`] wants.
pub fn scene_bound() -> f32 {
    if scene::bvh_node_count() > 0 {
        return node_bound(&scene::bvh_node_at(scene::bvh_base(), 0));
    }
    let mut m: f32 = 0.0;
    let n = scene::triangle_count();
    let mut i: u32 = 0;
    while i < n {
        let t = scene::triangle(i);
        m = super::max(
            m,
            super::max(t.v0.max_abs(), super::max(t.v1.max_abs(), t.v2.max_abs())),
        );
        i += 1;
    }
    m
}

/// Per-ray constants of the slab test.
#[derive(Clone, Copy)]
pub struct BoxRay {
    pub origin: Vec3,
    /// `1 / dir` per component (±inf for zero components).
    pub inv: Vec3,
    pub neg_x: bool,
    pub neg_y: bool,
    pub neg_z: bool,
}

impl BoxRay {
    /// Precomputes the inverse direction and its signs.
    pub fn new(ray: &Ray) -> BoxRay {
        let inv = Vec3::new(1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z);
        BoxRay {
            origin: ray.origin,
            inv,
            neg_x: inv.x < 0.0,
            neg_y: inv.y < 0.0,
            neg_z: inv.z < 0.0,
        }
    }

    /// Entry distance of the ray into the box `[lo, hi]` clipped to `[t_min, t_max]`, or
    /// `INFINITY` on a miss.
    ///
    /// Robust: near/far planes are chosen by the direction's sign, so a zero direction
    /// component gives ±inf distances, and the 0 × inf = NaN of a ray lying in a slab
    /// plane is ignored by `trax::max`/`trax::min` (IEEE maxNum/minNum): such a ray is
    /// treated as inside that slab. The far distance is scaled up by
    /// `1 + 2 gamma(3)` to absorb rounding.
    pub fn entry(&self, lo: Vec3, hi: Vec3, t_min: f32, t_max: f32) -> f32 {
        let nx = if self.neg_x { hi.x } else { lo.x };
        let fx = if self.neg_x { lo.x } else { hi.x };
        let ny = if self.neg_y { hi.y } else { lo.y };
        let fy = if self.neg_y { lo.y } else { hi.y };
        let nz = if self.neg_z { hi.z } else { lo.z };
        let fz = if self.neg_z { lo.z } else { hi.z };
        let tnx = (nx - self.origin.x) * self.inv.x;
        let tfx = (fx - self.origin.x) * self.inv.x;
        let tny = (ny - self.origin.y) * self.inv.y;
        let tfy = (fy - self.origin.y) * self.inv.y;
        let tnz = (nz - self.origin.z) * self.inv.z;
        let tfz = (fz - self.origin.z) * self.inv.z;
        let near = super::max(super::max(tnx, tny), super::max(tnz, t_min));
        let far = super::min(super::min(tfx, tfy), tfz) * SLAB_FAR_SCALE;
        let far = super::min(far, t_max);
        if near <= far {
            near
        } else {
            super::INFINITY
        }
    }

    /// [`BoxRay::entry`] on a BVH node's box.
    pub fn node_entry(&self, n: &BvhNode, t_min: f32, t_max: f32) -> f32 {
        self.entry(n.min, n.max, t_min, t_max)
    }
}

/// Closest hit along `ray` with `t_min < t < t_max` over the whole scene (BVH if the
/// scene has one, otherwise every triangle). Counts one ray (`trax.stat 0`).
pub fn intersect(ray: &Ray, t_min: f32, t_max: f32) -> Hit {
    hw::count_ray();
    let mut hit = Hit::none(t_max);
    let base = scene::bvh_base();
    if scene::bvh_node_count() == 0 {
        let tr = TriRay::new(ray, scene_bound());
        let n = scene::triangle_count();
        let mut i: u32 = 0;
        while i < n {
            if tr.intersect(&scene::triangle(i), t_min, &mut hit) {
                hit.tri = i;
            }
            i += 1;
        }
        return hit;
    }
    let br = BoxRay::new(ray);
    let mut stack: [u32; 64] = [0; 64];
    let mut sp: usize = 0;
    let mut node = scene::bvh_node_at(base, 0);
    if br.node_entry(&node, t_min, hit.t) == super::INFINITY {
        return hit;
    }
    let tr = TriRay::new(ray, node_bound(&node));
    loop {
        if node.is_leaf() {
            let mut i = node.a;
            while i < node.a + node.b {
                if tr.intersect(&scene::triangle(i), t_min, &mut hit) {
                    hit.tri = i;
                }
                i += 1;
            }
        } else {
            let left = scene::bvh_node_at(base, node.a);
            let right = scene::bvh_node_at(base, node.a + 1);
            let tl = br.node_entry(&left, t_min, hit.t);
            let tr_ = br.node_entry(&right, t_min, hit.t);
            let hit_l = tl != super::INFINITY;
            let hit_r = tr_ != super::INFINITY;
            if hit_l && hit_r {
                // Visit the nearer child first; the other waits on the stack.
                if tl <= tr_ {
                    stack[sp] = node.a + 1;
                    node = left;
                } else {
                    stack[sp] = node.a;
                    node = right;
                }
                sp += 1;
                continue;
            } else if hit_l {
                node = left;
                continue;
            } else if hit_r {
                node = right;
                continue;
            }
        }
        // Pop the next subtree still in front of the closest hit.
        let mut found = false;
        while sp > 0 {
            sp -= 1;
            let n = scene::bvh_node_at(base, stack[sp]);
            if br.node_entry(&n, t_min, hit.t) != super::INFINITY {
                node = n;
                found = true;
                break;
            }
        }
        if !found {
            return hit;
        }
    }
}

/// True if anything blocks `ray` with `t_min < t < t_max` (shadow rays). Counts one ray.
pub fn occluded(ray: &Ray, t_min: f32, t_max: f32) -> bool {
    hw::count_ray();
    let mut hit = Hit::none(t_max);
    let base = scene::bvh_base();
    if scene::bvh_node_count() == 0 {
        let tr = TriRay::new(ray, scene_bound());
        let n = scene::triangle_count();
        let mut i: u32 = 0;
        while i < n {
            if tr.intersect(&scene::triangle(i), t_min, &mut hit) {
                return true;
            }
            i += 1;
        }
        return false;
    }
    let br = BoxRay::new(ray);
    let tr = TriRay::new(ray, node_bound(&scene::bvh_node_at(base, 0)));
    let mut stack: [u32; 64] = [0; 64];
    let mut sp: usize = 1;
    stack[0] = 0;
    while sp > 0 {
        sp -= 1;
        let node = scene::bvh_node_at(base, stack[sp]);
        if br.node_entry(&node, t_min, t_max) == super::INFINITY {
            continue;
        }
        if node.is_leaf() {
            let mut i = node.a;
            while i < node.a + node.b {
                if tr.intersect(&scene::triangle(i), t_min, &mut hit) {
                    return true;
                }
                i += 1;
            }
        } else {
            stack[sp] = node.a;
            stack[sp + 1] = node.a + 1;
            sp += 2;
        }
    }
    false
}
