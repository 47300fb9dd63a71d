//! The fused box and triangle intersection pipelines (`trax.boxtest`, `trax.tritest`):
//! one instruction per test once the inputs are in coprocessor-2 registers. Results are
//! defined by the runtime's `pipes.rs` (shared with the emulator and the host), which
//! the prelude also compiles as ordinary kernel code: [`box_test_soft`] and
//! [`tri_test_soft`] compute the same bits on the general-purpose units, for chips
//! without the pipelines ([`available`]) and TMs in another mode.

use super::bvh::RayTests;
use super::hw;
use super::layout;
use super::math::Vec3;
use super::ray::{Hit, Ray};
use super::scene::Triangle;

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

/// One ray's box and triangle tests with the pipelines' semantics (hits at `t > 0`) for a
/// TM in `trax.setpipe` mode `mode`: box tests on the box pipeline in mode 1, triangle
/// tests on the triangle pipeline in mode 2, the others by the same computation in
/// software. The choice changes the cost, never a result. A traversal's tests
/// ([`super::bvh::Traversal`]).
///
/// In a pipeline mode, making the tests loads the ray into the pipeline's input
/// registers once (§3.2.3: the program loads a ray, then a box or triangle per test); they
/// serve this value's tests until the thread loads another ray: by making another
/// `PipeTests` or by a one-off [`box_test`] or [`tri_test`], which load their own.
#[derive(Clone, Copy)]
pub struct PipeTests {
    pub ray: Ray,
    /// `1 / dir` per component.
    pub inv_dir: Vec3,
    /// The TM's `trax.setpipe` mode.
    pub mode: u32,
}

impl PipeTests {
    /// The tests of `ray` on a TM in mode `mode` (0 general purpose, 1 box pipeline, 2
    /// triangle pipeline).
    pub fn new(ray: &Ray, mode: u32) -> PipeTests {
        let inv_dir = Vec3::new(1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z);
        if mode == 1 {
            hw::pipe_load_ray(arr(ray.origin), arr(inv_dir));
        } else if mode == 2 {
            hw::pipe_load_ray(arr(ray.origin), arr(ray.dir));
        }
        PipeTests {
            ray: *ray,
            inv_dir,
            mode,
        }
    }

    /// The triangle test's hit on `tri`.
    pub fn tri(&self, tri: &Triangle) -> PipeHit {
        if self.mode == 2 {
            let t = hw::pipe_tri(arr(tri.v0), arr(tri.v1), arr(tri.v2));
            PipeHit {
                t,
                u: hw::pipe_tri_u(),
                v: hw::pipe_tri_v(),
            }
        } else {
            tri_test_soft(&self.ray, tri)
        }
    }
}

impl RayTests for PipeTests {
    #[inline(always)]
    fn box_entry(&self, node: u32, t_max: f32) -> f32 {
        let e = if self.mode == 1 {
            // The box's words go from memory straight to the pipeline's registers.
            let w = |k: u32| f32::from_bits(hw::load_u32(node + 4 * k));
            hw::pipe_box(w(0), w(1), w(2), w(3), w(4), w(5))
        } else {
            let lo = super::scene::load_vec3(node + layout::BVH_MIN);
            let hi = super::scene::load_vec3(node + layout::BVH_MAX);
            box_test_soft(self.ray.origin, self.inv_dir, lo, hi)
        };
        if e <= t_max {
            e
        } else {
            super::INFINITY
        }
    }

    #[inline(always)]
    fn tri_hit(&self, tri: u32, hit: &mut Hit) -> bool {
        let h = if self.mode == 2 {
            let w = |k: u32| f32::from_bits(hw::load_u32(tri + 4 * k));
            let t = hw::pipe_tri([w(0), w(1), w(2)], [w(3), w(4), w(5)], [w(6), w(7), w(8)]);
            PipeHit {
                t,
                u: hw::pipe_tri_u(),
                v: hw::pipe_tri_v(),
            }
        } else {
            tri_test_soft(&self.ray, &super::scene::triangle_stored(tri))
        };
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
