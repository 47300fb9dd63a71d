//! Wide BVHs for ray-tracing units: the binary BVH collapsed to 2, 4 or 8 children per
//! node ([`WideBvh::collapse`]), stored plainly (exact `f32` child boxes) or compressed
//! ([`WideBvh::compress`]: child boxes quantized to 8 bits per plane against the node's
//! box with one power-of-two scale per axis, in the manner of Ylitie, Karras and Laine,
//! "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017).
//!
//! Collapsing keeps the binary tree's leaves (so its triangle tests) and only removes
//! interior levels: a wide node starts with its binary node's two children and repeatedly
//! opens the interior child of largest surface area until it has `width` children or only
//! leaves (the greedy rule of Wald et al.'s and Ylitie et al.'s collapse). A closest-hit
//! traversal of the wide tree therefore tests a subset of the same triangles with the same
//! test and finds the same nearest distance as the binary tree's; quantized boxes are
//! conservative (never smaller than the exact ones), so they cost extra box and triangle
//! tests, never a missed hit.
//!
//! Layout: nodes in breadth-first order, the interior children of a node adjacent from
//! [`WideNode::child_base`]; the triangle slots of a node's leaf children adjacent in
//! [`WideBvh::slots`] from [`WideNode::slot_base`] (so a compressed node addresses its
//! children and triangles with two bases and per-child small offsets).

use std::collections::VecDeque;

use super::{Aabb, Bvh, BvhError};

/// Most children a wide node holds.
pub const MAX_WIDTH: usize = 8;

/// Bytes of a plain wide node: per child its box (24 bytes) and one word (child node
/// index, or leaf slot offset and count), plus the two bases.
pub const PLAIN_NODE_BYTES: usize = MAX_WIDTH * (24 + 4) + 8;

/// Bytes of a compressed wide node: origin (12), three exponent bytes, child mask and
/// child count bytes (padded to 16), the two bases (8), per child a leaf-offset and a
/// count byte (16) and six quantized planes (48): 88 bytes (Ylitie et al.'s packs the
/// same fields into 80).
pub const COMPRESSED_NODE_BYTES: usize = 16 + 8 + 2 * MAX_WIDTH + 6 * MAX_WIDTH;

/// A child of a wide node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Child {
    /// An interior node (index into [`WideBvh::nodes`]).
    Node(u32),
    /// A leaf: `count` triangle slots from [`WideBvh::slots`]`[first..]`.
    Leaf {
        /// First entry in [`WideBvh::slots`].
        first: u32,
        /// Triangles.
        count: u32,
    },
}

/// A node of a wide BVH.
#[derive(Clone, Debug, PartialEq)]
pub struct WideNode {
    /// The children, each with its exact box.
    pub children: Vec<(Aabb, Child)>,
    /// Index of the first interior child (the others follow it).
    pub child_base: u32,
    /// First entry of [`WideBvh::slots`] of the leaf children (the others follow).
    pub slot_base: u32,
}

/// A wide BVH over the triangle slots of a binary [`Bvh`].
#[derive(Clone, Debug, PartialEq)]
pub struct WideBvh {
    /// Children per node at most (2..=[`MAX_WIDTH`]).
    pub width: usize,
    /// Nodes; root at 0.
    pub nodes: Vec<WideNode>,
    /// Triangle slots of the binary BVH (indices into [`Bvh::tri_order`]), in wide-leaf
    /// order.
    pub slots: Vec<u32>,
}

/// A compressed wide node: child boxes as 8-bit offsets from `origin` in units of
/// `2^exp[axis]`, conservative ([`QuantNode::child_box`] holds the exact box).
#[derive(Clone, Debug, PartialEq)]
pub struct QuantNode {
    /// The node box's minimum corner.
    pub origin: [f32; 3],
    /// Per axis, the scale's power of two.
    pub exp: [i8; 3],
    /// Per child, the quantized minimum and maximum planes.
    pub lo: Vec<[u8; 3]>,
    /// See `lo`.
    pub hi: Vec<[u8; 3]>,
}

impl QuantNode {
    /// The box child `i` decodes to (as a unit decodes it, in `f32`).
    pub fn child_box(&self, i: usize) -> Aabb {
        let d = |q: u8, a: usize| self.origin[a] + q as f32 * pow2(self.exp[a]);
        Aabb {
            min: [0, 1, 2].map(|a| d(self.lo[i][a], a)),
            max: [0, 1, 2].map(|a| d(self.hi[i][a], a)),
        }
    }
}

/// `2^e` exactly (`e` within `f32`'s normal range).
fn pow2(e: i8) -> f32 {
    f32::from_bits(((e as i32 + 127) as u32) << 23)
}

/// Counts of one traversal ([`WideBvh::closest`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalCounts {
    /// Wide nodes whose children were tested.
    pub nodes: u32,
    /// Child box tests.
    pub box_tests: u32,
    /// Triangle tests.
    pub tri_tests: u32,
    /// Deepest the traversal stack got.
    pub max_stack: u32,
}

impl WideBvh {
    /// Collapses `bvh` to at most `width` (2..=8) children per node.
    pub fn collapse(bvh: &Bvh, width: usize) -> Result<WideBvh, BvhError> {
        if !(2..=MAX_WIDTH).contains(&width) {
            return Err(BvhError::BadOption(format!(
                "BVH width must be in 2..={MAX_WIDTH}, got {width}"
            )));
        }
        let root = bvh.nodes[0];
        let mut w = WideBvh {
            width,
            nodes: vec![],
            slots: vec![],
        };
        // Binary nodes of each wide node, in breadth-first order of the wide tree.
        let mut queue = VecDeque::from([if root.is_leaf() { None } else { Some(0u32) }]);
        w.nodes.push(placeholder());
        let mut next = 1u32;
        let mut at = 0usize;
        while let Some(bin) = queue.pop_front() {
            // The binary nodes this wide node's children stand for.
            let kids: Vec<u32> = match bin {
                None => vec![0],
                Some(b) => open(bvh, b, width),
            };
            let mut node = WideNode {
                children: Vec::with_capacity(kids.len()),
                child_base: next,
                slot_base: w.slots.len() as u32,
            };
            for k in kids {
                let n = bvh.nodes[k as usize];
                let child = if n.is_leaf() {
                    let first = w.slots.len() as u32;
                    w.slots.extend(n.a..n.a + n.b);
                    Child::Leaf { first, count: n.b }
                } else {
                    let i = next;
                    next += 1;
                    w.nodes.push(placeholder());
                    queue.push_back(Some(k));
                    Child::Node(i)
                };
                node.children.push((n.aabb(), child));
            }
            w.nodes[at] = node;
            at += 1;
        }
        Ok(w)
    }

    /// The compressed form of every node (same order as [`WideBvh::nodes`]).
    pub fn compress(&self) -> Vec<QuantNode> {
        self.nodes.iter().map(quantize).collect()
    }

    /// Bytes of the node array as stored plainly.
    pub fn plain_bytes(&self) -> usize {
        self.nodes.len() * PLAIN_NODE_BYTES
    }

    /// Bytes of the node array as stored compressed.
    pub fn compressed_bytes(&self) -> usize {
        self.nodes.len() * COMPRESSED_NODE_BYTES
    }

    /// Closest-hit traversal with the caller's tests: `box_entry(node, child, box, t_max)`
    /// gives the entry distance of a child's box if the ray enters it before `t_max`;
    /// `tri_hit(slot, t_max)` gives the distance of a hit on triangle slot `slot` nearer than
    /// `t_max`. Children are visited nearest first; a stack of at most `stack_limit` entries
    /// (`None` when exceeded: the caller reports the overflow). Returns the nearest hit
    /// (slot and distance) and the counts. With a box test whose interval holds every
    /// distance `tri_hit` can return for a triangle inside the box (conservative at both
    /// ends), the nearest distance is the one a binary traversal with the same tests finds;
    /// the slot differs only where two triangles tie at that distance.
    pub fn closest<B, T>(
        &self,
        mut t_max: f32,
        stack_limit: usize,
        mut box_entry: B,
        mut tri_hit: T,
    ) -> Option<(Option<(u32, f32)>, TraversalCounts)>
    where
        B: FnMut(u32, usize, &Aabb, f32) -> Option<f32>,
        T: FnMut(u32, f32) -> Option<f32>,
    {
        let mut counts = TraversalCounts::default();
        let mut best = None;
        let mut stack: Vec<(Child, f32)> = vec![(Child::Node(0), f32::NEG_INFINITY)];
        let mut order: Vec<(f32, Child)> = Vec::with_capacity(MAX_WIDTH);
        while let Some((item, entry)) = stack.pop() {
            // Entered at or before the nearest hit so far (a hit exactly at a box's entry
            // distance lies in the box).
            if entry > t_max {
                continue;
            }
            match item {
                Child::Leaf { first, count } => {
                    for &slot in &self.slots[first as usize..(first + count) as usize] {
                        counts.tri_tests += 1;
                        if let Some(t) = tri_hit(slot, t_max) {
                            t_max = t;
                            best = Some((slot, t));
                        }
                    }
                }
                Child::Node(i) => {
                    counts.nodes += 1;
                    order.clear();
                    for (c, (b, child)) in self.nodes[i as usize].children.iter().enumerate() {
                        counts.box_tests += 1;
                        if let Some(e) = box_entry(i, c, b, t_max) {
                            order.push((e, *child));
                        }
                    }
                    // Nearest on top of the stack; equal entries keep child order.
                    order.sort_by(|a, b| b.0.total_cmp(&a.0));
                    for &(e, c) in &order {
                        stack.push((c, e));
                    }
                    if stack.len() > stack_limit {
                        return None;
                    }
                    counts.max_stack = counts.max_stack.max(stack.len() as u32);
                }
            }
        }
        Some((best, counts))
    }
}

fn placeholder() -> WideNode {
    WideNode {
        children: vec![],
        child_base: 0,
        slot_base: 0,
    }
}

/// The binary nodes standing for the children of wide node `b`: its two children, then
/// the interior one of largest surface area opened until there are `width` or only leaves.
/// Opened children keep their place, so the order stays the binary tree's left to right.
fn open(bvh: &Bvh, b: u32, width: usize) -> Vec<u32> {
    let n = bvh.nodes[b as usize];
    let mut kids = vec![n.a, n.a + 1];
    while kids.len() < width {
        let widest = kids
            .iter()
            .enumerate()
            .filter(|(_, &k)| !bvh.nodes[k as usize].is_leaf())
            .max_by(|(_, &x), (_, &y)| {
                let (ax, ay) = (
                    bvh.nodes[x as usize].aabb().area_f64(),
                    bvh.nodes[y as usize].aabb().area_f64(),
                );
                // Largest area; on equal areas the first.
                ax.total_cmp(&ay).then(y.cmp(&x))
            })
            .map(|(i, _)| i);
        let Some(i) = widest else { break };
        let c = bvh.nodes[kids[i] as usize].a;
        kids.splice(i..=i, [c, c + 1]);
    }
    kids
}

/// Quantizes a node's child boxes: per axis the smallest power of two `s` with the node's
/// extent within `255 s`, planes rounded outward, and any plane that `f32` decoding would
/// still place inside its exact box moved out by one step (or the scale doubled).
fn quantize(node: &WideNode) -> QuantNode {
    let all = node
        .children
        .iter()
        .fold(Aabb::EMPTY, |acc, (b, _)| acc.union(b));
    let origin = all.min;
    let mut exp = [0i8; 3];
    for a in 0..3 {
        let extent = all.max[a] as f64 - origin[a] as f64;
        let mut e = if extent > 0.0 {
            (extent / 255.0).log2().ceil().clamp(-126.0, 127.0) as i32
        } else {
            -126
        };
        // Doubles the scale until every child's planes decode outside its exact box.
        while e < 127 && !axis_fits(node, origin[a], a, e as i8) {
            e += 1;
        }
        exp[a] = e as i8;
    }
    let mut q = QuantNode {
        origin,
        exp,
        lo: vec![],
        hi: vec![],
    };
    for (b, _) in &node.children {
        let mut lo = [0u8; 3];
        let mut hi = [0u8; 3];
        for a in 0..3 {
            (lo[a], hi[a]) = planes(origin[a], exp[a], b.min[a], b.max[a]).unwrap_or((0, 255));
        }
        q.lo.push(lo);
        q.hi.push(hi);
    }
    q
}

fn axis_fits(node: &WideNode, origin: f32, a: usize, e: i8) -> bool {
    node.children
        .iter()
        .all(|(b, _)| planes(origin, e, b.min[a], b.max[a]).is_some())
}

/// The 8-bit planes of `[lo, hi]` against `origin` in steps of `2^e`, conservative as
/// decoded in `f32`; `None` if the box does not fit in 255 steps.
fn planes(origin: f32, e: i8, lo: f32, hi: f32) -> Option<(u8, u8)> {
    let s = pow2(e) as f64;
    let dec = |q: u32| origin + q as f32 * pow2(e);
    let mut ql = ((lo as f64 - origin as f64) / s).floor().max(0.0) as u32;
    while ql > 0 && dec(ql) > lo {
        ql -= 1;
    }
    let mut qh = ((hi as f64 - origin as f64) / s).ceil().max(0.0) as u32;
    while qh <= 255 && dec(qh) < hi {
        qh += 1;
    }
    (ql <= 255 && qh <= 255 && dec(ql) <= lo).then_some((ql as u8, qh as u8))
}
