//! BVH structure, quality and robustness.

use trax_assembler::bvh::{sweep, Bvh, BvhError, BvhOptions};
use trax_assembler::scene::{cornell_box, procedural, Vec3};

/// Deterministic pseudo-random numbers in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn build_and_check(tris: &[[Vec3; 3]], opts: &BvhOptions) -> Bvh {
    let bvh = Bvh::build(tris, opts).unwrap();
    bvh.check(tris, opts.max_leaf).unwrap();
    assert_eq!(bvh.tri_order.len(), tris.len());
    assert!(bvh.nodes.len() <= 2 * tris.len());
    bvh
}

#[test]
fn invariants_on_cornell_and_procedural() {
    let opts = BvhOptions::default();
    let c = cornell_box();
    let b = build_and_check(&c.triangles, &opts);
    let s = b.stats();
    assert!(s.depth >= 4 && s.depth <= 12, "{s:?}");
    let p = procedural(20_000).unwrap();
    let b = build_and_check(&p.triangles, &opts);
    let s = b.stats();
    assert!(s.depth < 40, "{s:?}");
    assert!(s.leaves >= p.len() / 4);
    for bins in [2, 7, 4096] {
        let o = BvhOptions {
            bins,
            ..BvhOptions::default()
        };
        build_and_check(&p.triangles, &o);
    }
    for max_leaf in [1, 2, 8] {
        let o = BvhOptions {
            max_leaf,
            ..BvhOptions::default()
        };
        let b = build_and_check(&p.triangles, &o);
        assert!(b.stats().max_leaf <= max_leaf);
    }
}

#[test]
fn single_triangle_is_a_root_leaf() {
    let t = [[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    let b = build_and_check(&t, &BvhOptions::default());
    assert_eq!(b.nodes.len(), 1);
    assert_eq!((b.nodes[0].a, b.nodes[0].b), (0, 1));
    assert_eq!(b.parents(), vec![u32::MAX]);
}

#[test]
fn degenerate_and_flat_triangles() {
    // Identical point triangles: no spatial split exists; the leaf cap still holds.
    let pts = vec![[[1.0, 2.0, 3.0]; 3]; 1000];
    let b = build_and_check(&pts, &BvhOptions::default());
    assert!(b.stats().depth <= 12, "{:?}", b.stats());
    // Collinear (zero-area) triangles along x, and all triangles in one plane.
    let mut lines = Vec::new();
    let mut plane = Vec::new();
    let mut r = Lcg(7);
    for i in 0..2000 {
        let x = i as f32 * 0.01;
        lines.push([[x, 0.0, 0.0], [x + 0.5, 0.0, 0.0], [x + 0.25, 0.0, 0.0]]);
        let (u, v) = (r.next() * 100.0, r.next() * 100.0);
        plane.push([[u, v, 5.0], [u + 1.0, v, 5.0], [u, v + 1.0, 5.0]]);
    }
    build_and_check(&lines, &BvhOptions::default());
    let b = build_and_check(&plane, &BvhOptions::default());
    assert!(b.stats().sah_cost.is_finite());
    // Mixed: many duplicates of one triangle plus a few others.
    let mut mixed = vec![[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 500];
    mixed.extend(plane.iter().take(50));
    build_and_check(&mixed, &BvhOptions::default());
}

#[test]
fn coordinates_from_1e_minus_6_to_1e6() {
    let mut r = Lcg(42);
    let mut tris = Vec::new();
    for i in 0..5000 {
        // Scales spread over 12 orders of magnitude; sizes proportional to position.
        let scale = 10f32.powf(-6.0 + 12.0 * (i as f32 / 5000.0));
        let p = [r.next() * scale, r.next() * scale, r.next() * scale];
        let s = scale * 1e-3;
        tris.push([p, [p[0] + s, p[1], p[2]], [p[0], p[1] + s, p[2] + s]]);
    }
    // Tiny triangles near the origin and huge ones far out.
    tris.push([[1e-6, 1e-6, 1e-6], [2e-6, 1e-6, 1e-6], [1e-6, 2e-6, 1e-6]]);
    tris.push([[-1e6, -1e6, -1e6], [1e6, -1e6, 1e6], [1e6, 1e6, -1e6]]);
    let b = build_and_check(&tris, &BvhOptions::default());
    let s = b.stats();
    assert!(s.sah_cost.is_finite(), "{s:?}");
    assert!(s.depth <= 64, "depth stays bounded: {s:?}");
}

/// The SAH compares areas within a node, so scaling a scene must not change its tree:
/// exactly for powers of two (areas are computed in each node's own power-of-two frame,
/// so they neither overflow beyond extents of about 1e19 nor underflow below 1e-19), and
/// up to the rounding of the scaled vertices for powers of ten. (With plain f32 areas,
/// which overflow beyond about 1e19, the builder fell back to median splits: three times
/// the SAH cost at 1e20 on this scene.)
#[test]
fn scaled_scenes_get_the_same_tree() {
    let tris = procedural(4_000).unwrap().triangles;
    let scaled = |s: f64| -> Vec<[Vec3; 3]> {
        tris.iter()
            .map(|t| t.map(|v| v.map(|c| (c as f64 * s) as f32)))
            .collect()
    };
    let opts = BvhOptions::default();
    let unit = build_and_check(&tris, &opts);
    let unit_cost = unit.stats().sah_cost;
    for e in [-100, -64, -20, 20, 64, 100] {
        let b = build_and_check(&scaled(2f64.powi(e)), &opts);
        let same = b.nodes.len() == unit.nodes.len()
            && b.tri_order == unit.tri_order
            && b.nodes
                .iter()
                .zip(&unit.nodes)
                .all(|(x, y)| (x.a, x.b) == (y.a, y.b));
        assert!(same, "2^{e}: a different tree");
        assert_eq!(b.stats().sah_cost, unit_cost, "2^{e}");
    }
    for e in [-25, -20, -10, 10, 20, 25] {
        let b = build_and_check(&scaled(10f64.powi(e)), &opts);
        let cost = b.stats().sah_cost;
        // One split chosen differently (rounding) changes the rest of a greedy build:
        // scenes scatter by a few percent (see `sah_close_to_full_sweep_reference`).
        assert!(
            (cost / unit_cost - 1.0).abs() < 0.05,
            "1e{e}: SAH cost {cost}, {unit_cost} at unit scale"
        );
    }
}

/// Binned SAH cost over full-sweep SAH cost.
fn sah_ratio(tris: &[[Vec3; 3]]) -> f32 {
    let opts = BvhOptions::default();
    let binned = Bvh::build(tris, &opts).unwrap().stats().sah_cost;
    let reference = sweep::build(tris, &opts).unwrap();
    reference.check(tris, opts.max_leaf).unwrap();
    binned / reference.stats().sah_cost
}

#[test]
fn sah_close_to_full_sweep_reference() {
    // Greedy top-down builds diverge chaotically once one split differs, so individual
    // scenes scatter by a few percent either way; measured: cornell 1.000, procedural:4000
    // 1.070, procedural:20000 1.004, 8k bunny triangles 1.001.
    let cornell = sah_ratio(&cornell_box().triangles);
    assert!(cornell < 1.02, "cornell: ratio {cornell}");
    let mut ratios = Vec::new();
    for n in [4_000, 20_000] {
        let r = sah_ratio(&procedural(n).unwrap().triangles);
        assert!(r < 1.08, "procedural:{n}: ratio {r}");
        ratios.push(r);
    }
    let mean = ratios.iter().sum::<f32>() / ratios.len() as f32;
    assert!(mean < 1.05, "procedural mean ratio {mean}");
}

#[test]
fn parents_point_back() {
    let p = procedural(2_000).unwrap();
    let b = build_and_check(&p.triangles, &BvhOptions::default());
    let parents = b.parents();
    assert_eq!(parents[0], u32::MAX);
    for (i, n) in b.nodes.iter().enumerate() {
        if !n.is_leaf() {
            assert_eq!(parents[n.a as usize], i as u32);
            assert_eq!(parents[n.a as usize + 1], i as u32);
        }
    }
    assert!(parents[1..].iter().all(|&x| x != u32::MAX));
}

#[test]
fn node_bytes_follow_the_abi() {
    let c = cornell_box();
    let b = Bvh::build(&c.triangles, &BvhOptions::default()).unwrap();
    let n = b.nodes[0];
    let bytes = trax_runtime::abi::Field::to_bytes(&n.to_abi());
    assert_eq!(bytes.len(), 32);
    assert_eq!(&bytes[0..4], &n.min[0].to_le_bytes());
    assert_eq!(&bytes[20..24], &n.max[2].to_le_bytes());
    assert_eq!(&bytes[24..28], &n.a.to_le_bytes());
    assert_eq!(
        &bytes[28..32],
        &0u32.to_le_bytes(),
        "root of 32 triangles is interior"
    );
    assert_eq!(n.a, 1, "root's children are nodes 1 and 2");
}

#[test]
fn bad_input_is_an_error() {
    let opts = BvhOptions::default();
    assert_eq!(Bvh::build(&[], &opts).unwrap_err(), BvhError::Empty);
    let t = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let bad = [t, [[0.0, f32::NAN, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    assert_eq!(Bvh::build(&bad, &opts).unwrap_err(), BvhError::NonFinite(1));
    let inf = [[[0.0, 0.0, f32::INFINITY], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    assert_eq!(Bvh::build(&inf, &opts).unwrap_err(), BvhError::NonFinite(0));
    for o in [
        BvhOptions {
            max_leaf: 0,
            ..BvhOptions::default()
        },
        BvhOptions {
            bins: 1,
            ..BvhOptions::default()
        },
    ] {
        assert!(matches!(Bvh::build(&[t], &o), Err(BvhError::BadOption(_))));
    }
}
