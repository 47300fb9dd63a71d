//! The fused box and triangle intersection pipelines (`trax.boxtest`, `trax.tritest`):
//! one instruction per test once the inputs are in coprocessor-2 registers. Results are
//! defined by the runtime's `pipes.rs` (shared with the emulator and the host).

use super::hw;
use super::math::Vec3;
use super::ray::Ray;
use super::scene::Triangle;

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
