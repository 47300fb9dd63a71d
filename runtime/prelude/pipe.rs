//! The fused box and triangle intersection pipelines (`trax.boxtest`, `trax.tritest`):
//! one instruction per test once the inputs are in coprocessor-2 registers. Results are
//! defined by the runtime's `pipes.rs` (shared with the emulator and the host), which
//! the prelude also compiles as ordinary kernel code: [`box_test_soft`] and
//! [`tri_test_soft`] compute the same bits on the general-purpose units, for chips
//! without the pipelines ([`available`]) and TMs in another mode.

use super::bvh::RayTests;
use super::hw;
use super::math::Vec3;
use super::ray::{Hit, Ray};
use super::scene::{BvhNode, Triangle};

/// Bit of the box pipeline (`trax.setpipe 1`) in [`super::scene::pipe_modes`].
pub const MODE_BOX: u32 = 1 << 1;
/// Bit of the triangle pipeline (`trax.setpipe 2`) in [`super::scene::pipe_modes`].
pub const MODE_TRI: u32 = 1 << 2;

/// True when this chip's TMs can be configured as both pipelines (the scene header's
/// `pipe_modes`, from the chip config).
pub fn available() -> bool {
    super::scene::pipe_modes() & (MODE_BOX | MODE_TRI) == MODE_BOX | MODE_TRI
}

/// A triangle-pipeline result.
#[derive(Clone, Copy)]
pub struct PipeHit {
    /// Hit distance, `INFINITY` on a miss.
    pub t: f32,
    /// Barycentric weight of vertex 1.
    pub u: f32,
    /// Barycentric weight of vertex 2.
    pub v: f32,
}

fn arr(v: Vec3) -> [f32; 3] {
    [v.x, v.y, v.z]
}

/// Entry distance (>= 0) of the ray from `origin` with inverse direction `inv_dir` into
/// the box `[lo, hi]`, or `INFINITY` on a miss.
pub fn box_test(origin: Vec3, inv_dir: Vec3, lo: Vec3, hi: Vec3) -> f32 {
    hw::pipe_box_test(arr(origin), arr(inv_dir), arr(lo), arr(hi))
}

/// [`box_test`] in software: the same result, in any mode.
pub fn box_test_soft(origin: Vec3, inv_dir: Vec3, lo: Vec3, hi: Vec3) -> f32 {
    hw::soft_box_test(arr(origin), arr(inv_dir), arr(lo), arr(hi))
}

/// [`tri_test`] in software: the same result, in any mode.
pub fn tri_test_soft(ray: &Ray, tri: &Triangle) -> PipeHit {
    let (t, u, v) = hw::soft_tri_test(
        arr(ray.origin),
        arr(ray.dir),
        arr(tri.v0),
        arr(tri.v1),
        arr(tri.v2),
    );
    PipeHit { t, u, v }
}

/// The triangle pipeline on `ray` and `tri`.
pub fn tri_test(ray: &Ray, tri: &Triangle) -> PipeHit {
    let t = hw::pipe_tri_test(
        arr(ray.origin),
        arr(ray.dir),
        arr(tri.v0),
        arr(tri.v1),
        arr(tri.v2),
    );
    PipeHit {
        t,
        u: hw::pipe_tri_u(),
        v: hw::pipe_tri_v(),
    }
}

/// Configures this TM's shared units as general-purpose units (`trax.setpipe 0`).
pub fn use_general_units() {
    hw::set_pipe_general();
}

/// Configures this TM's shared units as a box-test pipeline (`trax.setpipe 1`).
pub fn use_box_pipeline() {
    hw::set_pipe_box();
}

/// Configures this TM's shared units as a triangle-test pipeline (`trax.setpipe 2`).
pub fn use_triangle_pipeline() {
    hw::set_pipe_tri();
}

/// One ray's box and triangle tests with the pipelines' semantics (hits at `t > 0`), each
/// run by its pipeline (the TM must be in that mode) or by the same computation in
/// software: the choice changes the cost, never a result. A traversal's tests
/// ([`super::bvh::Traversal`]).
#[derive(Clone, Copy)]
pub struct PipeTests {
    pub ray: Ray,
    /// `1 / dir` per component.
    pub inv_dir: Vec3,
    /// Box tests on the box pipeline (`trax.boxtest`).
    pub box_pipe: bool,
    /// Triangle tests on the triangle pipeline (`trax.tritest`).
    pub tri_pipe: bool,
}

impl PipeTests {
    /// The tests of `ray`, on the pipelines chosen.
    pub fn new(ray: &Ray, box_pipe: bool, tri_pipe: bool) -> PipeTests {
        PipeTests {
            ray: *ray,
            inv_dir: Vec3::new(1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z),
            box_pipe,
            tri_pipe,
        }
    }

    /// The triangle test's hit on `tri`.
    pub fn tri(&self, tri: &Triangle) -> PipeHit {
        if self.tri_pipe {
            tri_test(&self.ray, tri)
        } else {
            tri_test_soft(&self.ray, tri)
        }
    }
}

impl RayTests for PipeTests {
    fn box_entry(&self, n: &BvhNode, t_max: f32) -> f32 {
        let e = if self.box_pipe {
            box_test(self.ray.origin, self.inv_dir, n.min, n.max)
        } else {
            box_test_soft(self.ray.origin, self.inv_dir, n.min, n.max)
        };
        if e <= t_max {
            e
        } else {
            super::INFINITY
        }
    }

    fn tri_hit(&self, tri: &Triangle, hit: &mut Hit) -> bool {
        let h = self.tri(tri);
        if h.t < hit.t {
            hit.t = h.t;
            hit.u = h.u;
            hit.v = h.v;
            true
        } else {
            false
        }
    }
}
