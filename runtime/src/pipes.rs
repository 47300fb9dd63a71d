//! Exact results of the fused intersection pipelines (`trax.boxtest`, `trax.tritest`).
//!
//! Shared verbatim by the emulator and the host implementation of the kernel prelude
//! (`prelude/hw_host.rs` includes it with `#[path]`, next to `fops.rs`), so a kernel using
//! the pipelines gives bit-identical results on both. Dependency-free; every operation is
//! written out in a fixed order because f32 rounding depends on it.

use super::fops;

/// `trax.boxtest`: entry distance of the ray (`origin`, `inv_dir` = 1/direction per
/// component) into the box `[lo, hi]`, clipped below at 0, or `+inf` on a miss.
///
/// Robust slab test: each axis's near and far planes are chosen by the sign of `inv_dir`
/// (so a zero direction component, `inv_dir = ±inf`, gives ±inf distances), the NaN of
/// `0 * inf` (a ray lying in a slab plane) is dropped by IEEE maxNum/minNum
/// ([`fops::fmax`]/[`fops::fmin`]), so such a ray counts as inside that slab, and the far
/// distance is scaled by `1 + 2 gamma(3)` (`gamma(n) = n eps / (1 - n eps)`) to absorb
/// rounding. A box touched only at one point or edge is hit.
pub fn box_test(origin: [f32; 3], inv_dir: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> f32 {
    let mut tmin = f32::NEG_INFINITY;
    let mut tmax = f32::INFINITY;
    for a in 0..3 {
        let neg = inv_dir[a] < 0.0;
        let near = if neg { hi[a] } else { lo[a] };
        let far = if neg { lo[a] } else { hi[a] };
        tmin = fops::fmax(tmin, (near - origin[a]) * inv_dir[a]);
        tmax = fops::fmin(tmax, (far - origin[a]) * inv_dir[a]);
    }
    let entry = fops::fmax(tmin, 0.0);
    if tmax * SLAB_FAR_SCALE >= entry {
        entry
    } else {
        f32::INFINITY
    }
}

/// `1 + 2 gamma(3)` for f32 (`eps = 2^-24`), rounded up.
pub const SLAB_FAR_SCALE: f32 = 1.000_000_4;

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `trax.tritest`: Möller–Trumbore ray/triangle test. Returns `(t, u, v)`: the hit
/// distance (`+inf` on a miss, and for hits at `t <= 0`) and the barycentric weights of
/// `v1` and `v2` (both 0 on a miss).
pub fn tri_test(
    origin: [f32; 3],
    dir: [f32; 3],
    v0: [f32; 3],
    v1: [f32; 3],
    v2: [f32; 3],
) -> (f32, f32, f32) {
    let miss = (f32::INFINITY, 0.0, 0.0);
    let e1 = sub(v1, v0);
    let e2 = sub(v2, v0);
    let p = cross(dir, e2);
    let det = dot(e1, p);
    if det == 0.0 || det.is_nan() {
        return miss;
    }
    let inv = 1.0 / det;
    let s = sub(origin, v0);
    let u = dot(s, p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return miss;
    }
    let q = cross(s, e1);
    let v = dot(dir, q) * inv;
    if !(v >= 0.0 && u + v <= 1.0) {
        return miss;
    }
    let t = dot(e2, q) * inv;
    if t > 0.0 {
        (t, u, v)
    } else {
        miss
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_hits_misses_and_degenerate_rays() {
        let (lo, hi) = ([0.0; 3], [1.0; 3]);
        let inv = |d: [f32; 3]| d.map(|x| 1.0 / x);
        assert_eq!(
            box_test([-1.0, 0.5, 0.5], inv([1.0, 0.0, 0.0]), lo, hi),
            1.0
        );
        assert_eq!(
            box_test([-1.0, 2.0, 0.5], inv([1.0, 0.0, 0.0]), lo, hi),
            f32::INFINITY
        );
        // Inside: entry clipped to 0. Behind: miss.
        assert_eq!(box_test([0.5; 3], inv([1.0, 1.0, 1.0]), lo, hi), 0.0);
        assert_eq!(
            box_test([0.5, 0.5, 2.0], inv([0.0, 0.0, 1.0]), lo, hi),
            f32::INFINITY
        );
        // In a face plane (0 * inf = NaN is ignored), on an edge, with -0 components.
        assert_eq!(
            box_test([0.0, 0.5, -2.0], inv([0.0, 0.0, 1.0]), lo, hi),
            2.0
        );
        assert_eq!(
            box_test([1.0, 1.0, -2.0], inv([-0.0, 0.0, 1.0]), lo, hi),
            2.0
        );
        assert_eq!(
            box_test([1.0, 0.0, 5.0], inv([0.0, -0.0, -1.0]), lo, hi),
            4.0
        );
        // Grazing a corner diagonally.
        assert!(box_test([-1.0, -1.0, 0.5], inv([1.0, 1.0, 0.0]), lo, hi) < f32::INFINITY);
        // Negative directions.
        assert_eq!(
            box_test([3.0, 0.5, 0.5], inv([-1.0, 0.0, 0.0]), lo, hi),
            2.0
        );
    }

    #[test]
    fn triangle_hits_and_misses() {
        let (v0, v1, v2) = ([0.0, 0.0, -2.0], [1.0, 0.0, -2.0], [0.0, 1.0, -2.0]);
        let (t, u, v) = tri_test([0.25, 0.5, 0.0], [0.0, 0.0, -1.0], v0, v1, v2);
        assert_eq!((t, u, v), (2.0, 0.25, 0.5));
        assert_eq!(
            tri_test([0.8, 0.8, 0.0], [0.0, 0.0, -1.0], v0, v1, v2).0,
            f32::INFINITY
        );
        // Behind the origin, parallel, and NaN input.
        assert_eq!(
            tri_test([0.25, 0.5, -3.0], [0.0, 0.0, -1.0], v0, v1, v2).0,
            f32::INFINITY
        );
        assert_eq!(
            tri_test([0.25, 0.5, 0.0], [1.0, 0.0, 0.0], v0, v1, v2),
            (f32::INFINITY, 0.0, 0.0)
        );
        assert_eq!(
            tri_test([f32::NAN, 0.5, 0.0], [0.0, 0.0, -1.0], v0, v1, v2).0,
            f32::INFINITY
        );
    }
}
