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

fn scale(a: [f32; 3], k: f32) -> [f32; 3] {
    [a[0] * k, a[1] * k, a[2] * k]
}

fn max_abs(a: [f32; 3]) -> f32 {
    fops::fmax(a[0].abs(), fops::fmax(a[1].abs(), a[2].abs()))
}

/// The power of two `k` with `m * k` in `[1, 2)` for `m >= 0`, a normal f32: `m` is
/// clamped to at most 2^126 first (IEEE minNum, so huge, infinite and NaN `m` get 2^-126),
/// and zero and subnormal `m` get 2^127. The prelude's `math::pow2_scale`.
pub fn pow2_scale(m: f32) -> f32 {
    let m = fops::fmin(m, POW2_126);
    f32::from_bits(0x7F00_0000 - (m.to_bits() & 0x7F80_0000))
}

/// 2^126.
const POW2_126: f32 = 8.507_059e37;

/// `trax.tritest`: the Plücker-coordinate ray/triangle test of the thesis's triangle
/// pipeline (§3.2.3, after Shevtsov et al.): hit or miss from the signs of the ray's
/// permuted inner products with the three edges, and the one divide only for a hit.
/// Returns `(t, u, v)`: the hit distance (`+inf` on a miss, and for hits at `t <= 0`)
/// and the barycentric weights of `v1` and `v2` (both 0 on a miss).
///
/// With the vertices taken relative to the ray's origin (`a, b, c`), the ray passes
/// through the origin and its inner product with edge `p -> q` is the triple product
/// `d . (p x q)`: `w0` for edge `b -> c`, `w1` for `c -> a`, `w2` for `a -> b`. The ray
/// hits when all three have one sign (zero counts as either: edges and vertices are
/// inside) and their sum `d . n` is not 0; then `u = w1 / sum`, `v = w2 / sum` and
/// `t = a . (b x c) / sum`. An edge shared by two triangles gives exactly opposite
/// products in the two (`p x q` and `q x p` are exact negations), so a ray cannot pass
/// between them.
///
/// The vertex offsets are first multiplied by the power of two that brings the largest of
/// their coordinates to about 1 (an exponent adjustment in hardware), and `t` divided by
/// it at the end: the products of two and three lengths then neither overflow nor
/// underflow at any scene scale, and since the scaling is exact the result is bit for bit
/// the plain computation's wherever that one was in range.
pub fn tri_test(
    origin: [f32; 3],
    dir: [f32; 3],
    v0: [f32; 3],
    v1: [f32; 3],
    v2: [f32; 3],
) -> (f32, f32, f32) {
    let miss = (f32::INFINITY, 0.0, 0.0);
    let a = sub(v0, origin);
    let b = sub(v1, origin);
    let c = sub(v2, origin);
    let k = pow2_scale(fops::fmax(max_abs(a), fops::fmax(max_abs(b), max_abs(c))));
    let (a, b, c) = (scale(a, k), scale(b, k), scale(c, k));
    let bc = cross(b, c);
    let w0 = dot(dir, bc);
    let w1 = dot(dir, cross(c, a));
    let w2 = dot(dir, cross(a, b));
    let all_pos = w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0;
    let all_neg = w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0;
    let sum = w0 + w1 + w2;
    if !(all_pos || all_neg) || sum == 0.0 || sum.is_nan() {
        return miss;
    }
    // The pipeline's result is the hit; the divide follows only for one.
    let inv = 1.0 / sum;
    let t = dot(a, bc) * inv / k;
    if t > 0.0 {
        (t, w1 * inv, w2 * inv)
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
    fn triangle_test_is_the_same_at_every_scale() {
        let (v0, v1, v2) = ([0.0, 0.0, -2.0], [1.0, 0.0, -2.0], [0.0, 1.0, -2.0]);
        let o = [0.25, 0.5, 0.0];
        let d = [0.0, 0.0, -1.0];
        // Powers of two scale exactly: the same hit, t scaled, at every representable scale.
        for e in -60..=60 {
            let k = 2f32.powi(e);
            let sc = |a: [f32; 3]| a.map(|c| c * k);
            let (t, u, v) = tri_test(sc(o), d, sc(v0), sc(v1), sc(v2));
            assert_eq!((t, u, v), (2.0 * k, 0.25, 0.5), "scale 2^{e}");
        }
        // Decimal scales round the vertices; the hit stays within rounding.
        for e in -30..=30 {
            let k = 10f64.powi(e);
            let sc = |a: [f32; 3]| a.map(|c| (c as f64 * k) as f32);
            let (t, u, v) = tri_test(sc(o), d, sc(v0), sc(v1), sc(v2));
            assert!(((t as f64) / (2.0 * k) - 1.0).abs() < 1e-6, "1e{e}: t {t}");
            assert!((u - 0.25).abs() < 1e-6 && (v - 0.5).abs() < 1e-6, "1e{e}");
        }
    }

    #[test]
    fn pow2_scale_brings_magnitudes_to_one() {
        for m in [1.0f32, 1.5, 3.0, 1e-30, 7e30, f32::MIN_POSITIVE, f32::MAX] {
            let k = pow2_scale(m);
            assert!(k.is_normal() && (k.to_bits() & 0x7f_ffff) == 0, "{m}");
            assert!(
                (1.0..2.0).contains(&(m * k)) || m == f32::MAX,
                "{m}: {}",
                m * k
            );
        }
        assert_eq!(POW2_126, 2f32.powi(126));
        assert_eq!(pow2_scale(0.0), 2f32.powi(127));
        assert_eq!(pow2_scale(1e-45), 2f32.powi(127));
        assert_eq!(pow2_scale(f32::MIN_POSITIVE), 2f32.powi(126));
        assert_eq!(pow2_scale(f32::INFINITY), 2f32.powi(-126));
        assert_eq!(pow2_scale(f32::NAN), 2f32.powi(-126));
    }

    #[test]
    fn shared_edges_leave_no_gap() {
        // Two triangles sharing the edge (0,0,-2)-(1,1,-2); rays through points on and
        // next to it hit at least one of them.
        let (p, q) = ([0.0, 0.0, -2.0], [1.0, 1.0, -2.0]);
        let (r, s) = ([1.0, 0.0, -2.0], [0.0, 1.0, -2.0]);
        let d = [0.0, 0.0, -1.0];
        // Inside the square the two make up (its corners and border are its own edges).
        for i in 1..64 {
            let x = i as f32 / 64.0;
            for e in [-1e-7f32, 0.0, 1e-7] {
                let o = [x + e, x, 0.3];
                let h1 = tri_test(o, d, p, r, q).0;
                let h2 = tri_test(o, d, p, q, s).0;
                let t = h1.min(h2);
                assert!((t - 2.3).abs() < 1e-6, "{o:?}: {h1} {h2}");
            }
        }
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
