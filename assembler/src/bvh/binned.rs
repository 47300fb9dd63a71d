//! Binned SAH builder (one thread).
//!
//! Each node of `n` triangles bins their centroids into `n` equal slots per axis (at least
//! 16, at most `bins`), evaluates the SAH at every bin boundary of all three axes, and splits
//! at the cheapest one; a node with at most `max_leaf` triangles becomes a leaf when that is
//! no more expensive. Subtrees of at most 128 triangles are instead built with exact
//! full-sweep splits over lists sorted once per subtree (cheaper than binning at that size,
//! and better splits). Robustness:
//! a node whose centroids coincide on every axis, or that has no split with both sides
//! non-empty, is split at the middle of its range; past `sah_depth` splits are object
//! medians, so depth stays bounded; bin indices are clamped so huge or tiny extents never
//! index out of range or produce NaN. Child boxes are exact unions of their triangles'
//! boxes, hence always inside the parent's.

use super::aabb::{fmax, fmin};
use super::{Aabb, Bvh, BvhOptions, Node, C_TRAV};
use crate::scene::Vec3;

/// A triangle's box and index, moved around during partitioning (32 bytes: cache-friendly).
/// Lanes 0..3 are the box; lane 3 of `lo` carries the triangle index's bits, lane 3 of `hi`
/// is unused. Four lanes let the bin updates compile to packed min/max.
#[derive(Clone, Copy)]
struct Prim {
    lo: [f32; 4],
    hi: [f32; 4],
}

impl Prim {
    /// Twice the centroid (saves a multiply; only ever compared with itself).
    #[inline(always)]
    fn c(&self, axis: usize) -> f32 {
        self.lo[axis] + self.hi[axis]
    }
    #[inline(always)]
    fn aabb(&self) -> Aabb {
        Aabb {
            min: [self.lo[0], self.lo[1], self.lo[2]],
            max: [self.hi[0], self.hi[1], self.hi[2]],
        }
    }
    #[inline(always)]
    fn idx(&self) -> u32 {
        self.lo[3].to_bits()
    }
}

/// One bin's bounds, in the same four-lane form as [`Prim`] (lane 3 is junk).
#[derive(Clone, Copy)]
struct Bin {
    lo: [f32; 4],
    hi: [f32; 4],
}

impl Bin {
    const EMPTY: Bin = Bin {
        lo: [f32::INFINITY; 4],
        hi: [f32::NEG_INFINITY; 4],
    };

    #[inline(always)]
    fn add(&mut self, p: &Prim) {
        for l in 0..4 {
            self.lo[l] = fmin(self.lo[l], p.lo[l]);
            self.hi[l] = fmax(self.hi[l], p.hi[l]);
        }
    }

    #[inline(always)]
    fn merge(&mut self, o: &Bin) {
        for l in 0..4 {
            self.lo[l] = fmin(self.lo[l], o.lo[l]);
            self.hi[l] = fmax(self.hi[l], o.hi[l]);
        }
    }

    #[inline(always)]
    fn aabb(&self) -> Aabb {
        Aabb {
            min: [self.lo[0], self.lo[1], self.lo[2]],
            max: [self.hi[0], self.hi[1], self.hi[2]],
        }
    }

    /// Surface area of a non-empty bin times `k²` (the extents are multiplied by the
    /// node's [`Aabb::area_scale`] `k` first, so no scale overflows or underflows). Callers
    /// only use it once something was added; an empty bin's value is meaningless but never
    /// NaN-trapping.
    #[inline(always)]
    fn area(&self, k: f32) -> f32 {
        let d = [0, 1, 2].map(|i| (self.hi[i] - self.lo[i]) * k);
        2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    }
}

/// A chosen split: the left part's size and, when the binning already knows them, each
/// side's (bounds, centroid bounds).
struct Split {
    mid: usize,
    children: Option<[(Aabb, Aabb); 2]>,
}

impl Split {
    fn at(mid: usize) -> Split {
        Split {
            mid,
            children: None,
        }
    }
}

struct Task {
    node: u32,
    start: usize,
    end: usize,
    bounds: Aabb,
    /// Bounds of the doubled centroids.
    cbounds: Aabb,
    depth: u32,
}

/// Nodes with at most this many triangles evaluate every split (a full sweep), which is
/// cheap at that size and recovers the quality binning loses on small nodes.
const EXACT_BELOW: usize = 128;
// Small subtrees index their triangles with `u8`.
const _: () = assert!(EXACT_BELOW <= 256);

/// Bounds of a range and of its doubled centroids.
fn range_bounds(prims: &[Prim]) -> (Aabb, Aabb) {
    let mut b = Aabb::EMPTY;
    let mut c = Aabb::EMPTY;
    for p in prims {
        b = b.union(&p.aabb());
        c.grow([p.c(0), p.c(1), p.c(2)]);
    }
    (b, c)
}

/// Builds the tree: nodes in depth-first order with sibling pairs allocated together.
pub fn build(triangles: &[[Vec3; 3]], opts: &BvhOptions) -> Bvh {
    let mut prims: Vec<Prim> = triangles
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let b = Aabb::of_triangle(t);
            Prim {
                lo: [b.min[0], b.min[1], b.min[2], f32::from_bits(i as u32)],
                hi: [b.max[0], b.max[1], b.max[2], 0.0],
            }
        })
        .collect();
    let nb = opts.bins as usize;
    let max_leaf = opts.max_leaf as usize;
    let mut nodes: Vec<Node> = Vec::with_capacity(2 * triangles.len());
    nodes.push(Node::default());
    let (bounds, cbounds) = range_bounds(&prims);
    let mut stack = vec![Task {
        node: 0,
        start: 0,
        end: prims.len(),
        bounds,
        cbounds,
        depth: 1,
    }];
    let mut bins = vec![Bin::EMPTY; 6 * nb];
    let mut counts = vec![0u32; 6 * nb];
    let mut right_area = vec![0.0f32; 3 * nb];
    let mut small = Small::new(max_leaf, opts.sah_depth);
    while let Some(t) = stack.pop() {
        let n = t.end - t.start;
        let leaf = |nodes: &mut Vec<Node>| {
            nodes[t.node as usize] = Node {
                min: t.bounds.min,
                max: t.bounds.max,
                a: t.start as u32,
                b: n as u32,
            };
        };
        if n == 1 {
            leaf(&mut nodes);
            continue;
        }
        let range = &mut prims[t.start..t.end];
        if n <= EXACT_BELOW {
            small.build(range, &t, &mut nodes);
            continue;
        }
        let ext = [0, 1, 2].map(|i| t.cbounds.max[i] - t.cbounds.min[i]);
        let widest = (0..3)
            .max_by(|&a, &b| ext[a].total_cmp(&ext[b]))
            .unwrap_or(0);
        // The split, or None for a leaf.
        let split: Option<Split> = if ext[widest] <= 0.0 {
            // All centroids coincide: no spatial split exists.
            (n > max_leaf).then(|| Split::at(n / 2))
        } else if t.depth >= opts.sah_depth {
            let mid = n / 2;
            range.select_nth_unstable_by(mid, |a, b| a.c(widest).total_cmp(&b.c(widest)));
            Some(Split::at(mid))
        } else {
            sah_split(
                range,
                &t,
                ext,
                nb,
                max_leaf,
                (&mut bins, &mut counts),
                &mut right_area,
            )
        };
        let Some(split) = split else {
            leaf(&mut nodes);
            continue;
        };
        let mid = split.mid;
        let [(lb, lc), (rb, rc)] = split
            .children
            .unwrap_or_else(|| [range_bounds(&range[..mid]), range_bounds(&range[mid..])]);
        let a = nodes.len() as u32;
        nodes.push(Node::default());
        nodes.push(Node::default());
        nodes[t.node as usize] = Node {
            min: t.bounds.min,
            max: t.bounds.max,
            a,
            b: 0,
        };
        stack.push(Task {
            node: a + 1,
            start: t.start + mid,
            end: t.end,
            bounds: rb,
            cbounds: rc,
            depth: t.depth + 1,
        });
        stack.push(Task {
            node: a,
            start: t.start,
            end: t.start + mid,
            bounds: lb,
            cbounds: lc,
            depth: t.depth + 1,
        });
    }
    Bvh {
        nodes,
        tri_order: prims.iter().map(Prim::idx).collect(),
        treelets: None,
    }
}

/// Bins `range`, picks the cheapest SAH split, partitions the range in place and returns the
/// size of the left part; `None` when a leaf is at least as cheap (and allowed).
fn sah_split(
    range: &mut [Prim],
    t: &Task,
    ext: [f32; 3],
    nb: usize,
    max_leaf: usize,
    (bins, counts): (&mut [Bin], &mut [u32]),
    right_area: &mut [f32],
) -> Option<Split> {
    let n = range.len();
    // Many bins where they matter (large nodes near the root, where a few huge triangles
    // such as enclosing walls must be separated precisely), few where they would be noise.
    let nb = n.max(16).min(nb);
    // Large nodes alternate between two bin sets, so that runs of neighbouring triangles
    // falling in one bin do not serialise on that bin's memory; merged afterwards.
    let sets = if n >= 2 * nb { 2 } else { 1 };
    bins[..sets * 3 * nb].fill(Bin::EMPTY);
    counts[..sets * 3 * nb].fill(0);
    // A finite, non-negative scale; `as usize` saturates (NaN -> 0), then clamp.
    let scale = ext.map(|e| {
        let s = nb as f32 / e;
        if e > 0.0 && s.is_finite() {
            s * 0.999_99
        } else {
            0.0
        }
    });
    let g = Grid {
        cmin: t.cbounds.min,
        scale,
        last: nb - 1,
    };
    let bin_of = |p: &Prim, axis: usize| g.bin(p, axis);
    {
        // Per-axis slices of exactly `nb` bins let the compiler drop bounds checks.
        let (set_a, set_b) = bins[..2 * 3 * nb].split_at_mut(3 * nb);
        let (cnt_a, cnt_b) = counts[..2 * 3 * nb].split_at_mut(3 * nb);
        if sets == 2 {
            let mut pairs = range.chunks_exact(2);
            for pair in &mut pairs {
                g.add(&pair[0], set_a, cnt_a);
                g.add(&pair[1], set_b, cnt_b);
            }
            for p in pairs.remainder() {
                g.add(p, set_a, cnt_a);
            }
            for (a, b) in set_a.iter_mut().zip(set_b.iter()) {
                a.merge(b);
            }
            for (a, b) in cnt_a.iter_mut().zip(cnt_b.iter()) {
                *a += b;
            }
        } else {
            for p in range.iter() {
                g.add(p, set_a, cnt_a);
            }
        }
    }
    // All three axes in one pass, so their dependency chains overlap. An axis that was not
    // binned (scale 0) has every triangle in bin 0, so it never offers a split.
    let bx = [&bins[..nb], &bins[nb..2 * nb], &bins[2 * nb..3 * nb]];
    let cx = [&counts[..nb], &counts[nb..2 * nb], &counts[2 * nb..3 * nb]];
    let right_area = &mut right_area[..3 * nb];
    // Areas relative to the node's size (exact power-of-two scaling), see `Aabb::area_scale`.
    let ks = t.bounds.area_scale();
    let mut acc = [Bin::EMPTY; 3];
    for k in (1..nb).rev() {
        for axis in 0..3 {
            acc[axis].merge(&bx[axis][k]);
            right_area[3 * k + axis] = acc[axis].area(ks);
        }
    }
    let mut acc = [Bin::EMPTY; 3];
    let mut nl = [0u32; 3];
    let mut axis_best = [(f32::INFINITY, 0usize); 3]; // (cost, last left bin)
    for k in 0..nb - 1 {
        for axis in 0..3 {
            acc[axis].merge(&bx[axis][k]);
            nl[axis] += cx[axis][k];
            let nr = n as u32 - nl[axis];
            if nl[axis] == 0 || nr == 0 {
                continue;
            }
            let cost =
                acc[axis].area(ks) * nl[axis] as f32 + right_area[3 * (k + 1) + axis] * nr as f32;
            if cost < axis_best[axis].0 {
                axis_best[axis] = (cost, k);
            }
        }
    }
    // Cheapest overall; ties go to the lower axis, then the lower bin.
    let mut best = (f32::INFINITY, 0usize, 0usize); // (cost, axis, last left bin)
    for (axis, &(cost, k)) in axis_best.iter().enumerate() {
        if cost < best.0 {
            best = (cost, axis, k);
        }
    }
    let area = t.bounds.area_scaled(ks);
    let leaf_cost = n as f32 * area;
    if !best.0.is_finite() {
        // No split with both sides non-empty (e.g. extents too small to bin).
        return (n > max_leaf).then(|| Split::at(median(range, ext)));
    }
    if n <= max_leaf && leaf_cost <= C_TRAV * area + best.0 {
        return None;
    }
    let (axis, k) = (best.1, best.2);
    let split_bins = &bins[axis * nb..axis * nb + nb];
    let (mut lb, mut rb) = (Bin::EMPTY, Bin::EMPTY);
    split_bins[..=k].iter().for_each(|b| lb.merge(b));
    split_bins[k + 1..].iter().for_each(|b| rb.merge(b));
    let (lb, rb) = (lb.aabb(), rb.aabb());
    // In-place partition (bin <= k goes left), gathering each side's centroid bounds; one
    // copy of the loop per axis so the axis is a constant inside it.
    let (i, lc, rc) = match axis {
        0 => partition(range, |p| bin_of(p, 0) <= k),
        1 => partition(range, |p| bin_of(p, 1) <= k),
        _ => partition(range, |p| bin_of(p, 2) <= k),
    };
    Some(Split {
        mid: i,
        children: Some([(lb, lc), (rb, rc)]),
    })
}

/// The bin grid of one node: bin of a doubled centroid along an axis.
struct Grid {
    cmin: Vec3,
    scale: [f32; 3],
    last: usize,
}

impl Grid {
    /// Bin index; `as i32` saturates (NaN -> 0) and is cheaper than a conversion to usize.
    #[inline(always)]
    fn bin(&self, p: &Prim, axis: usize) -> usize {
        ((((p.c(axis) - self.cmin[axis]) * self.scale[axis]) as i32).max(0) as usize).min(self.last)
    }

    /// Adds a triangle to one bin per axis of a set of `3 * (last + 1)` bins.
    #[inline(always)]
    fn add(&self, p: &Prim, bins: &mut [Bin], counts: &mut [u32]) {
        let nb = self.last + 1;
        for axis in 0..3 {
            let k = axis * nb + self.bin(p, axis);
            bins[k].add(p);
            counts[k] += 1;
        }
    }
}

/// Moves the triangles for which `left` holds to the front; returns their count and the
/// centroid bounds of both sides.
#[inline(always)]
fn partition(range: &mut [Prim], left: impl Fn(&Prim) -> bool) -> (usize, Aabb, Aabb) {
    let (mut lc, mut rc) = (Aabb::EMPTY, Aabb::EMPTY);
    let (mut i, mut j) = (0usize, range.len());
    while i < j {
        let p = range[i];
        if left(&p) {
            lc.grow([p.c(0), p.c(1), p.c(2)]);
            i += 1;
        } else {
            rc.grow([p.c(0), p.c(1), p.c(2)]);
            j -= 1;
            range.swap(i, j);
        }
    }
    (i, lc, rc)
}

/// A split inside a small subtree: (axis of the list that is split, left size, the two
/// child boxes when the sweep already knows them).
type SmallSplit = (usize, usize, Option<(Aabb, Aabb)>);

/// Builds whole subtrees of at most [`EXACT_BELOW`] triangles with full-sweep SAH splits.
///
/// The triangles are copied to a local buffer and sorted once per axis (by doubled centroid,
/// then position); each split then stably partitions the three sorted lists instead of
/// sorting again, so a subtree costs three small sorts in all rather than three per node.
/// Splits fall only between distinct keys, so each candidate's sides, and hence the tree,
/// are those of sorting every node afresh.
struct Small {
    buf: [Prim; EXACT_BELOW],
    /// Doubled centroids of `buf`, per axis.
    keys: [[f32; EXACT_BELOW]; 3],
    /// Per axis, local positions in key order; a node owns the same slice of all three.
    lists: [[u8; EXACT_BELOW]; 3],
    left: [bool; EXACT_BELOW],
    /// Suffix boxes of the sweep, per position and axis.
    right: [[Bin; 3]; EXACT_BELOW],
    max_leaf: usize,
    sah_depth: u32,
}

impl Small {
    fn new(max_leaf: usize, sah_depth: u32) -> Small {
        let zero = Prim {
            lo: [0.0; 4],
            hi: [0.0; 4],
        };
        Small {
            buf: [zero; EXACT_BELOW],
            keys: [[0.0; EXACT_BELOW]; 3],
            lists: [[0; EXACT_BELOW]; 3],
            left: [false; EXACT_BELOW],
            right: [[Bin::EMPTY; 3]; EXACT_BELOW],
            max_leaf,
            sah_depth,
        }
    }

    /// Builds the subtree of task `t` (`range` is its triangles, at most [`EXACT_BELOW`]),
    /// appending its nodes depth-first and reordering `range` into leaf order.
    fn build(&mut self, range: &mut [Prim], t: &Task, nodes: &mut Vec<Node>) {
        let n = range.len();
        self.buf[..n].copy_from_slice(range);
        let mut keys = [0u64; EXACT_BELOW];
        for axis in 0..3 {
            let keys = &mut keys[..n];
            for (i, k) in keys.iter_mut().enumerate() {
                let c = self.buf[i].c(axis);
                self.keys[axis][i] = c;
                *k = pack_key(c, i);
            }
            sort_keys(keys);
            for (l, &k) in self.lists[axis].iter_mut().zip(keys.iter()) {
                *l = key_pos(k) as u8;
            }
        }
        self.node(0, n, t.node, t.bounds, t.depth, t.start as u32, nodes);
        for (dst, &l) in range.iter_mut().zip(self.lists[0][..n].iter()) {
            *dst = self.buf[l as usize];
        }
    }

    /// Doubled centroid of local triangle `l` on `axis`.
    #[inline(always)]
    fn key(&self, axis: usize, l: u8) -> f32 {
        self.keys[axis][l as usize]
    }

    /// Box of the triangles at list positions `s..e`.
    fn bounds(&self, s: usize, e: usize) -> Aabb {
        let mut b = Bin::EMPTY;
        for &l in &self.lists[0][s..e] {
            b.add(&self.buf[l as usize]);
        }
        b.aabb()
    }

    /// Builds the node at list positions `s..e` (slot `first + s` onwards).
    #[allow(clippy::too_many_arguments)]
    fn node(
        &mut self,
        s: usize,
        e: usize,
        node: u32,
        bounds: Aabb,
        depth: u32,
        first: u32,
        nodes: &mut Vec<Node>,
    ) {
        let n = e - s;
        let mid = self.choose(s, e, &bounds, depth);
        let Some((axis, k, boxes)) = mid else {
            nodes[node as usize] = Node {
                min: bounds.min,
                max: bounds.max,
                a: first + s as u32,
                b: n as u32,
            };
            return;
        };
        // Mark the sides from the chosen axis's order, then stably partition the others.
        let m = s + k;
        for (i, &l) in self.lists[axis][s..e].iter().enumerate() {
            self.left[l as usize] = i < k;
        }
        // Branch-free: each entry is written to both sides' buffers and only the cursor of
        // its own side advances (the other write is overwritten or past the end).
        for other in (0..3).filter(|&a| a != axis) {
            let (mut lt, mut rt) = ([0u8; EXACT_BELOW], [0u8; EXACT_BELOW]);
            let (mut i, mut j) = (0usize, 0usize);
            for &l in &self.lists[other][s..e] {
                let is_left = self.left[l as usize];
                lt[i.min(EXACT_BELOW - 1)] = l;
                rt[j.min(EXACT_BELOW - 1)] = l;
                i += is_left as usize;
                j += !is_left as usize;
            }
            self.lists[other][s..m].copy_from_slice(&lt[..k]);
            self.lists[other][m..e].copy_from_slice(&rt[..n - k]);
        }
        let (lb, rb) = boxes.unwrap_or_else(|| (self.bounds(s, m), self.bounds(m, e)));
        let a = nodes.len() as u32;
        nodes.push(Node::default());
        nodes.push(Node::default());
        nodes[node as usize] = Node {
            min: bounds.min,
            max: bounds.max,
            a,
            b: 0,
        };
        self.node(s, m, a, lb, depth + 1, first, nodes);
        self.node(m, e, a + 1, rb, depth + 1, first, nodes);
    }

    /// The split of list positions `s..e` as (axis, left size), or `None` for a leaf; the
    /// same rules as the binned builder's loop, with every distinct split position a candidate.
    fn choose(&mut self, s: usize, e: usize, bounds: &Aabb, depth: u32) -> Option<SmallSplit> {
        let n = e - s;
        if n == 1 {
            return None;
        }
        let ext =
            [0, 1, 2].map(|a| self.key(a, self.lists[a][e - 1]) - self.key(a, self.lists[a][s]));
        let widest = (0..3)
            .max_by(|&a, &b| ext[a].total_cmp(&ext[b]))
            .unwrap_or(0);
        if ext[widest] <= 0.0 {
            // All centroids coincide: no spatial split exists.
            return (n > self.max_leaf).then_some((0, n / 2, None));
        }
        if depth >= self.sah_depth {
            return Some((widest, n / 2, None));
        }
        // All three axes in one pass, so their dependency chains overlap; suffix boxes are
        // kept so the chosen split's child boxes come for free.
        let Small {
            buf,
            keys,
            lists,
            right,
            ..
        } = self;
        let lists = [&lists[0][s..e], &lists[1][s..e], &lists[2][s..e]];
        let mut acc = [Bin::EMPTY; 3];
        for k in (1..n).rev() {
            for axis in 0..3 {
                acc[axis].add(&buf[lists[axis][k] as usize]);
                right[k][axis] = acc[axis];
            }
        }
        let ks = bounds.area_scale();
        let mut acc = [Bin::EMPTY; 3];
        let mut axis_best = [(f32::INFINITY, 0usize, Bin::EMPTY); 3]; // (cost, k, left box)
        for k in 1..n {
            for axis in 0..3 {
                let (prev, next) = (lists[axis][k - 1] as usize, lists[axis][k] as usize);
                acc[axis].add(&buf[prev]);
                if keys[axis][prev] == keys[axis][next] {
                    continue;
                }
                let cost = acc[axis].area(ks) * k as f32 + right[k][axis].area(ks) * (n - k) as f32;
                if cost < axis_best[axis].0 {
                    axis_best[axis] = (cost, k, acc[axis]);
                }
            }
        }
        // Cheapest overall; ties go to the lower axis, then the lower position.
        let mut best = (f32::INFINITY, 0usize, 0usize);
        for (axis, &(cost, k, _)) in axis_best.iter().enumerate() {
            if cost < best.0 {
                best = (cost, axis, k);
            }
        }
        let area = bounds.area_scaled(ks);
        if !best.0.is_finite() {
            return (n > self.max_leaf).then_some((0, n / 2, None));
        }
        if n <= self.max_leaf && n as f32 * area <= C_TRAV * area + best.0 {
            return None;
        }
        let (axis, k) = (best.1, best.2);
        let boxes = (axis_best[axis].2.aabb(), right[k][axis].aabb());
        Some((axis, k, Some(boxes)))
    }
}

/// Packs a key and a position so that integer order is `f32::total_cmp` order, then position.
#[inline(always)]
fn pack_key(key: f32, pos: usize) -> u64 {
    let b = key.to_bits();
    let ord = if b >> 31 == 1 { !b } else { b | 0x8000_0000 };
    ((ord as u64) << 32) | pos as u64
}

/// The position packed by [`pack_key`].
#[inline(always)]
fn key_pos(k: u64) -> usize {
    (k as u32) as usize
}

/// Sorts packed keys: insertion sort for the tiny arrays near the leaves (where a general
/// sort's set-up dominates), the standard sort otherwise.
fn sort_keys(keys: &mut [u64]) {
    if keys.len() > 8 {
        keys.sort_unstable();
        return;
    }
    for i in 1..keys.len() {
        let mut j = i;
        while j > 0 && keys[j] < keys[j - 1] {
            keys.swap(j, j - 1);
            j -= 1;
        }
    }
}

/// Object-median split on the widest centroid axis; returns the left size.
fn median(range: &mut [Prim], ext: [f32; 3]) -> usize {
    let axis = (0..3)
        .max_by(|&a, &b| ext[a].total_cmp(&ext[b]))
        .unwrap_or(0);
    let mid = range.len() / 2;
    range.select_nth_unstable_by(mid, |a, b| a.c(axis).total_cmp(&b.c(axis)));
    mid
}
