//! Treelets: budget, contiguity, alignment, and that the BVH stays valid after reordering.

use trax_assembler::bvh::{Bvh, BvhError, BvhOptions, TreeletOptions, PAD};
use trax_assembler::scene::{cornell_box, procedural, Vec3};

/// Bytes of a BVH node and of a triangle in memory.
const NODE: u32 = std::mem::size_of::<trax_runtime::abi::BvhNode>() as u32;
const TRI: u32 = std::mem::size_of::<trax_runtime::abi::Triangle>() as u32;

fn build(tris: &[[Vec3; 3]], budget: u32, align: u32) -> Bvh {
    let opts = BvhOptions {
        treelets: Some(TreeletOptions {
            budget_bytes: budget,
            align_bytes: align,
        }),
        ..BvhOptions::default()
    };
    let b = Bvh::build(tris, &opts).unwrap();
    b.check(tris, opts.max_leaf).unwrap();
    b
}

/// Checks budget, contiguity, coverage and alignment of node and triangle treelets.
fn check_treelets(b: &Bvh, budget: u32, align: u32) {
    let t = b.treelets.as_ref().unwrap();
    assert_eq!(t.node_treelet.len(), b.nodes.len());
    assert_eq!(
        t.node_ranges[0].start, 0,
        "the root treelet holds node 0 first"
    );
    let mut prev_end = 0;
    let reachable: std::collections::HashSet<u32> = b.reachable().into_iter().collect();
    for (id, r) in t.node_ranges.iter().enumerate() {
        assert!(r.start >= prev_end, "treelets in order, disjoint");
        assert!(r.end > r.start, "treelet {id} empty");
        assert!(
            (r.end - r.start) * NODE <= budget,
            "node treelet {id} over budget"
        );
        if align > 0 {
            assert_eq!(r.start * NODE % align, 0, "treelet {id} not aligned");
        }
        // Contiguous: every node in the range belongs to this treelet and is real.
        for i in r.clone() {
            assert_eq!(t.node_treelet[i as usize], id as u32);
            assert!(
                reachable.contains(&i),
                "node {i} in treelet {id} is unreachable"
            );
        }
        // Gaps are padding only.
        for i in prev_end..r.start {
            assert_eq!(t.node_treelet[i as usize], u32::MAX);
            assert!(!reachable.contains(&i));
        }
        prev_end = r.end;
    }
    assert_eq!(prev_end as usize, b.nodes.len());
    // Siblings share a treelet.
    for &i in &reachable {
        let n = b.nodes[i as usize];
        if !n.is_leaf() {
            assert_eq!(
                t.node_treelet[n.a as usize],
                t.node_treelet[n.a as usize + 1]
            );
        }
    }
    // Triangle treelets: within budget, contiguous, aligned, each leaf inside one.
    let mut prev = 0;
    for (k, r) in t.tri_ranges.iter().enumerate() {
        assert!(r.start >= prev);
        assert!(
            (r.end - r.start) * TRI <= budget,
            "triangle treelet {k} over budget"
        );
        if align > 0 {
            // It starts in the first slot of an aligned block and stays within the budget
            // from the block's start.
            let (start, end) = (u64::from(r.start * TRI), u64::from(r.end * TRI));
            let block = start / u64::from(align) * u64::from(align);
            assert!(
                start - block < u64::from(TRI),
                "triangle treelet {k} does not start in its block's first slot"
            );
            assert!(
                end <= block + u64::from(budget),
                "triangle treelet {k} runs past its block's budget"
            );
        }
        for s in prev..r.start {
            assert_eq!(b.tri_order[s as usize], PAD);
        }
        prev = r.end;
    }
    assert_eq!(prev as usize, b.tri_order.len());
    for &i in &reachable {
        let n = b.nodes[i as usize];
        if n.is_leaf() {
            let inside = t
                .tri_ranges
                .iter()
                .filter(|r| r.start <= n.a && n.a + n.b <= r.end)
                .count();
            assert_eq!(inside, 1, "leaf {i} split across triangle treelets");
        }
    }
}

#[test]
fn l1_sized_treelets_on_a_procedural_scene() {
    let p = procedural(30_000).unwrap();
    let b = build(&p.triangles, 32 * 1024, 0);
    check_treelets(&b, 32 * 1024, 0);
    let t = b.treelets.as_ref().unwrap();
    // Small subtrees are packed together: close to the minimum number of treelets.
    let min = b.nodes.len().div_ceil(1024);
    let got = t.node_ranges.len();
    assert!(
        got >= min && got <= min + min / 10 + 1,
        "{got} treelets, minimum {min}"
    );
    // Packed: no padding at all.
    assert!(b.tri_order.iter().all(|&s| s != PAD));
    // The root treelet is filled to the budget (the tree is much larger than one treelet).
    let r0 = &t.node_ranges[0];
    assert!((r0.end - r0.start) * 32 > 32 * 1024 - 64, "{r0:?}");
}

#[test]
fn dram_row_aligned_treelets() {
    let p = procedural(30_000).unwrap();
    for (budget, align) in [(16 * 1024, 2048), (4096, 4096), (8192, 1024), (32768, 2048)] {
        let b = build(&p.triangles, budget, align);
        check_treelets(&b, budget, align);
        // Padding stays modest when the budget holds several aligned slot groups.
        if budget >= 16 * 1024 {
            let pads = b.tri_order.iter().filter(|&&s| s == PAD).count();
            assert!(
                pads * 5 < p.len(),
                "{pads} padding slots for {} triangles",
                p.len()
            );
        }
    }
}

/// An aligned triangle treelet starts in the first 36-byte slot of its aligned block, so the
/// array holds at most one `round_up(budget, align)` span per treelet, and every treelet but
/// the last is full up to one leaf short of its slots. Before the fix treelets started on
/// multiples of lcm(36, align) bytes: 72 KiB apart for 16 KiB treelets on 8 KiB rows, 4.5x
/// the triangles' bytes.
#[test]
fn aligned_triangle_treelets_pad_to_the_next_block_only() {
    let p = procedural(30_000).unwrap();
    let max_leaf = BvhOptions::default().max_leaf;
    for (budget, align) in [(16384, 8192), (16384, 2048), (4096, 4096), (32768, 8192)] {
        let b = build(&p.triangles, budget, align);
        check_treelets(&b, budget, align);
        let t = b.treelets.as_ref().unwrap();
        let n = t.tri_ranges.len() as u64;
        // Slots a treelet can hold from any start in the block's first slot.
        let least_slots = u64::from((budget - (TRI - 1)) / TRI);
        let most_treelets = (p.len() as u64).div_ceil(least_slots - u64::from(max_leaf - 1));
        assert!(
            n <= most_treelets,
            "{n} triangle treelets > {most_treelets}"
        );
        let span = u64::from(budget.div_ceil(align) * align);
        let bytes = b.tri_order.len() as u64 * u64::from(TRI);
        assert!(
            bytes <= n * span,
            "budget {budget}, align {align}: {bytes} triangle bytes > {n} treelets x {span}"
        );
    }
}

#[test]
fn small_budgets_and_small_scenes() {
    let c = cornell_box();
    for budget in [160, 256, 1024, 1 << 20] {
        let b = build(&c.triangles, budget, 0);
        check_treelets(&b, budget, 0);
    }
    let b = build(&c.triangles, 1 << 20, 0);
    assert_eq!(b.treelets.as_ref().unwrap().node_ranges.len(), 1);
    let t = [[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    let b = build(&t, 4096, 64);
    check_treelets(&b, 4096, 64);
}

#[test]
fn same_sah_cost_before_and_after_treelets() {
    let p = procedural(5_000).unwrap();
    let plain = Bvh::build(&p.triangles, &BvhOptions::default()).unwrap();
    let tl = build(&p.triangles, 4096, 2048);
    let (a, b) = (plain.stats(), tl.stats());
    assert_eq!(a.leaves, b.leaves);
    assert_eq!(a.depth, b.depth);
    assert!((a.sah_cost - b.sah_cost).abs() <= 1e-3 * a.sah_cost);
}

#[test]
fn bad_treelet_options() {
    let c = cornell_box();
    for (budget, align) in [(64, 0), (4096, 100), (4096, 32), (4096, 8192)] {
        let opts = BvhOptions {
            treelets: Some(TreeletOptions {
                budget_bytes: budget,
                align_bytes: align,
            }),
            ..BvhOptions::default()
        };
        assert!(
            matches!(Bvh::build(&c.triangles, &opts), Err(BvhError::BadOption(_))),
            "budget {budget} align {align}"
        );
    }
}
