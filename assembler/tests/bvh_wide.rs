//! Wide BVHs (issue 29's RT units): the collapse keeps every triangle slot once, respects
//! the width and the adjacency the compressed node addresses by, quantized boxes are
//! conservative, and closest-hit traversal of the 2-, 4- and 8-wide trees, plain and
//! compressed, finds the binary tree's nearest hit distance bit for bit on every ray.

use std::path::Path;

use trax_assembler::bvh::wide::{Child, WideBvh, MAX_WIDTH};
use trax_assembler::bvh::{Aabb, Bvh, BvhError, BvhOptions};
use trax_assembler::scene::{cornell_box, load_scene, procedural, LoadOptions, Vec3};

/// A small deterministic generator (xorshift).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot(a: Vec3, b: Vec3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

struct Ray {
    o: Vec3,
    d: Vec3,
    inv: Vec3,
}

/// Möller–Trumbore: the hit distance if in `(1e-4, t_max)`. Both traversals call this
/// one function, so equal candidate sets give bit-equal nearest distances.
fn tri_t(r: &Ray, t: &[Vec3; 3], t_max: f32) -> Option<f32> {
    let e1 = sub(t[1], t[0]);
    let e2 = sub(t[2], t[0]);
    let p = cross(r.d, e2);
    let det = dot(e1, p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(r.o, t[0]);
    let u = dot(s, p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = cross(s, e1);
    let v = dot(r.d, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let d = dot(e2, q) * inv;
    (d > 1e-4 && d < t_max).then_some(d)
}

/// Slab test widened by 1e-5 of the distance at both ends: it holds every distance
/// [`tri_t`] returns for a triangle in the box (whose own rounding is far below that), the
/// condition under which traversal order cannot change the nearest hit.
fn box_entry(r: &Ray, b: &Aabb, t_max: f32) -> Option<f32> {
    let (mut lo, mut hi) = (0.0f32, f32::INFINITY);
    for a in 0..3 {
        let t0 = (b.min[a] - r.o[a]) * r.inv[a];
        let t1 = (b.max[a] - r.o[a]) * r.inv[a];
        let (n, f) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
        lo = if n > lo { n } else { lo };
        hi = if f < hi { f } else { hi };
    }
    let (lo, hi) = (lo * (1.0 - 1e-5), hi * (1.0 + 1e-5));
    (lo <= hi && lo <= t_max).then_some(lo)
}

/// The binary tree's nearest hit: (slot, t).
fn binary_closest(bvh: &Bvh, tris: &[[Vec3; 3]], r: &Ray) -> Option<(u32, f32)> {
    let mut best = None;
    let mut t_max = f32::INFINITY;
    let mut stack = vec![0u32];
    while let Some(i) = stack.pop() {
        let n = bvh.nodes[i as usize];
        if box_entry(r, &n.aabb(), t_max).is_none() {
            continue;
        }
        if n.is_leaf() {
            for s in n.a..n.a + n.b {
                if let Some(t) = tri_t(r, &tris[bvh.tri_order[s as usize] as usize], t_max) {
                    t_max = t;
                    best = Some((s, t));
                }
            }
        } else {
            stack.push(n.a + 1);
            stack.push(n.a);
        }
    }
    best
}

fn rays(tris: &[[Vec3; 3]], n: usize, seed: u64) -> Vec<Ray> {
    let b = tris
        .iter()
        .fold(Aabb::EMPTY, |a, t| a.union(&Aabb::of_triangle(t)));
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            let o = [0, 1, 2].map(|a| b.min[a] + (b.max[a] - b.min[a]) * rng.next());
            let d = [0, 1, 2].map(|_| rng.next() * 2.0 - 1.0);
            Ray {
                o,
                d,
                inv: d.map(|c| 1.0 / c),
            }
        })
        .collect()
}

fn scenes() -> Vec<(&'static str, Vec<[Vec3; 3]>)> {
    let shared = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/scenes"));
    let sibenik = shared.join("sibenik/sibenik.obj");
    vec![
        ("cornell", cornell_box().triangles),
        ("procedural:3000", procedural(3000).unwrap().triangles),
        (
            "sibenik",
            load_scene(sibenik.to_str().unwrap(), &LoadOptions::default())
                .unwrap()
                .triangles,
        ),
    ]
}

/// Structure: every binary slot once, the width, children and leaf slots adjacent from
/// the node's bases, breadth-first order (children after their parent).
fn check_structure(bvh: &Bvh, w: &WideBvh) {
    let mut seen = vec![false; bvh.tri_order.len()];
    for &s in &w.slots {
        assert!(
            !std::mem::replace(&mut seen[s as usize], true),
            "slot {s} twice"
        );
    }
    let leaf_slots: usize = bvh
        .reachable()
        .iter()
        .map(|&i| bvh.nodes[i as usize])
        .filter(|n| n.is_leaf())
        .map(|n| n.b as usize)
        .sum();
    assert_eq!(
        w.slots.len(),
        leaf_slots,
        "every leaf slot of the binary tree"
    );
    let mut reached = vec![0u32; w.nodes.len()];
    for (i, n) in w.nodes.iter().enumerate() {
        assert!(!n.children.is_empty() && n.children.len() <= w.width);
        let (mut next_node, mut next_slot) = (n.child_base, n.slot_base);
        for (b, c) in &n.children {
            match *c {
                Child::Node(j) => {
                    assert_eq!(j, next_node, "node {i}: interior children adjacent");
                    assert!(j as usize > i, "breadth-first");
                    next_node += 1;
                    reached[j as usize] += 1;
                    let cb = w.nodes[j as usize]
                        .children
                        .iter()
                        .fold(Aabb::EMPTY, |a, (x, _)| a.union(x));
                    assert!(b.contains(&cb), "child box holds its children");
                }
                Child::Leaf { first, count } => {
                    assert_eq!(first, next_slot, "node {i}: leaf slots adjacent");
                    next_slot += count;
                }
            }
        }
    }
    assert!(reached[1..].iter().all(|&r| r == 1) && reached[0] == 0);
}

#[test]
fn collapsed_trees_hold_every_triangle_once_within_the_width() {
    for (name, tris) in scenes() {
        let bvh = Bvh::build(&tris, &BvhOptions::default()).unwrap();
        let interior = bvh
            .reachable()
            .iter()
            .filter(|&&i| !bvh.nodes[i as usize].is_leaf())
            .count();
        let mut prev = usize::MAX;
        for width in [2, 4, 8] {
            let w = WideBvh::collapse(&bvh, width).unwrap();
            check_structure(&bvh, &w);
            if width == 2 {
                // Width 2 is the binary tree itself, one wide node per interior node.
                assert_eq!(w.nodes.len(), interior, "{name}");
            }
            // Each doubling of the width removes levels: strictly fewer nodes.
            assert!(w.nodes.len() < prev, "{name} width {width}");
            prev = w.nodes.len();
            let full = w.nodes.iter().filter(|n| n.children.len() == width).count();
            eprintln!(
                "{name}: width {width}: {} nodes ({} full), plain {} KiB, compressed {} KiB",
                w.nodes.len(),
                full,
                w.plain_bytes() / 1024,
                w.compressed_bytes() / 1024
            );
        }
    }
}

#[test]
fn quantized_boxes_hold_the_exact_boxes_and_stay_tight() {
    for (name, tris) in scenes() {
        let bvh = Bvh::build(&tris, &BvhOptions::default()).unwrap();
        let w = WideBvh::collapse(&bvh, MAX_WIDTH).unwrap();
        let (mut loose, mut exact) = (0.0f64, 0.0f64);
        for (n, q) in w.nodes.iter().zip(w.compress()) {
            let node_box = n.children.iter().fold(Aabb::EMPTY, |a, (b, _)| a.union(b));
            for (i, (b, _)) in n.children.iter().enumerate() {
                let d = q.child_box(i);
                assert!(d.contains(b), "{name}: decoded {d:?} does not hold {b:?}");
                // Within one step of 1/255 of the node's extent (at most two after the
                // scale doubles for rounding) on each plane.
                for a in 0..3 {
                    let step = (node_box.max[a] - node_box.min[a]) / 255.0;
                    assert!(
                        b.min[a] - d.min[a] <= 4.0 * step + f32::EPSILON * b.min[a].abs()
                            && d.max[a] - b.max[a] <= 4.0 * step + f32::EPSILON * b.max[a].abs(),
                        "{name}: axis {a} of {d:?} loose around {b:?}"
                    );
                }
                loose += d.area_f64();
                exact += b.area_f64();
            }
        }
        eprintln!(
            "{name}: quantized child boxes' area {:.3}x exact",
            loose / exact
        );
    }
}

#[test]
fn wide_traversal_finds_the_binary_trees_nearest_hit() {
    for (name, tris) in scenes() {
        let bvh = Bvh::build(&tris, &BvhOptions::default()).unwrap();
        let rays = rays(&tris, 3000, 0x9e37_79b9_7f4a_7c15);
        let want: Vec<_> = rays
            .iter()
            .map(|r| binary_closest(&bvh, &tris, r))
            .collect();
        let hits = want.iter().filter(|h| h.is_some()).count();
        assert!(
            hits > rays.len() / 4,
            "{name}: the rays hit something ({hits})"
        );
        for width in [2, 4, 8] {
            let w = WideBvh::collapse(&bvh, width).unwrap();
            let q = w.compress();
            for compressed in [false, true] {
                let mut tests = 0u64;
                for (r, want) in rays.iter().zip(&want) {
                    let tri = |s: u32| &tris[bvh.tri_order[s as usize] as usize];
                    let (got, c) = w
                        .closest(
                            f32::INFINITY,
                            64,
                            |node, child, b, t_max| {
                                if compressed {
                                    box_entry(r, &q[node as usize].child_box(child), t_max)
                                } else {
                                    box_entry(r, b, t_max)
                                }
                            },
                            |s, t_max| tri_t(r, tri(s), t_max),
                        )
                        .expect("64 entries are enough");
                    tests += c.tri_tests as u64;
                    match (got, want) {
                        (None, None) => {}
                        (Some((gs, gt)), Some((ws, wt))) => {
                            assert_eq!(gt.to_bits(), wt.to_bits(), "{name} w{width} t");
                            // Another slot only on an exact tie of distances.
                            if gs != *ws {
                                let t2 = tri_t(r, tri(gs), f32::INFINITY).unwrap();
                                assert_eq!(t2.to_bits(), wt.to_bits(), "{name}: not a tie");
                            }
                        }
                        _ => panic!("{name} width {width}: {got:?} vs {want:?}"),
                    }
                }
                eprintln!(
                    "{name}: width {width} compressed {compressed}: {:.1} triangle tests/ray",
                    tests as f64 / rays.len() as f64
                );
            }
        }
    }
}

#[test]
fn a_single_triangle_is_one_leaf_and_a_small_stack_overflows() {
    let t = one_triangle();
    let bvh = Bvh::build(&t, &BvhOptions::default()).unwrap();
    let w = WideBvh::collapse(&bvh, 4).unwrap();
    assert_eq!(w.nodes.len(), 1);
    assert_eq!(w.nodes[0].children[0].1, Child::Leaf { first: 0, count: 1 });
    let r = Ray {
        o: [0.2, 0.2, -1.0],
        d: [0.0, 0.0, 1.0],
        inv: [f32::INFINITY, f32::INFINITY, 1.0],
    };
    let (hit, c) = w
        .closest(
            f32::INFINITY,
            4,
            |_, _, b, tm| box_entry(&r, b, tm),
            |s, tm| tri_t(&r, &t[bvh.tri_order[s as usize] as usize], tm),
        )
        .unwrap();
    assert_eq!(hit.map(|h| h.1), Some(1.0));
    assert_eq!((c.nodes, c.box_tests, c.tri_tests), (1, 1, 1));

    // Every box entered, a stack of one entry: the root's children overflow it, and the
    // traversal says so rather than answering.
    let tris = procedural(3000).unwrap().triangles;
    let bvh = Bvh::build(&tris, &BvhOptions::default()).unwrap();
    let w = WideBvh::collapse(&bvh, 8).unwrap();
    assert!(w
        .closest(f32::INFINITY, 1, |_, _, _, _| Some(0.0), |_, _| None)
        .is_none());
    assert!(w
        .closest(f32::INFINITY, 64, |_, _, _, _| Some(0.0), |_, _| None)
        .is_some());
}

fn one_triangle() -> Vec<[Vec3; 3]> {
    vec![[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]
}

#[test]
fn widths_outside_two_to_eight_are_refused() {
    let bvh = Bvh::build(&one_triangle(), &BvhOptions::default()).unwrap();
    for w in [0, 1, 9, 16] {
        assert!(matches!(
            WideBvh::collapse(&bvh, w),
            Err(BvhError::BadOption(m)) if m.contains("2..=8")
        ));
    }
}
