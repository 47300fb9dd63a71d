//! Bounding volume hierarchy in the memory layout of `trax_runtime::abi` (`bvh_nodes`):
//! `abi::BvhNode` nodes, root at index 0, siblings adjacent, triangles reordered into leaf order;
//! optional parent pointers and treelets.
//!
//! [`Bvh::build`] runs the binned SAH builder ([`binned`]), then, if asked, groups nodes and
//! triangles into treelets ([`treelet`]). [`sweep`] is a full-sweep SAH reference builder used
//! to judge the binned builder's quality.

mod aabb;
pub mod binned;
pub mod sweep;
pub mod treelet;
pub mod wide;

pub use aabb::Aabb;
pub use treelet::{TreeletLayout, TreeletOptions, Treelets};

use crate::scene::Vec3;

/// Triangle slot that holds padding (treelet alignment), not a scene triangle.
pub const PAD: u32 = u32::MAX;

/// Cost of one traversal step relative to one triangle test (simtrax uses 1 and 1).
pub const C_TRAV: f32 = 1.0;
/// Cost of one triangle intersection test.
pub const C_ISEC: f32 = 1.0;

/// One node, with the fields of its memory layout ([`Node::to_abi`]).
///
/// Interior: `b == 0`, children at `a` and `a + 1`. Leaf: `b` triangles from slot `a`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Node {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
    /// First child (interior) or first triangle slot (leaf).
    pub a: u32,
    /// 0 for an interior node, else the triangle count.
    pub b: u32,
}

impl Node {
    /// Whether this node is a leaf.
    pub fn is_leaf(&self) -> bool {
        self.b != 0
    }

    /// The node's box.
    pub fn aabb(&self) -> Aabb {
        Aabb {
            min: self.min,
            max: self.max,
        }
    }

    /// The node as stored in memory ([`trax_runtime::abi::BvhNode`]).
    pub fn to_abi(&self) -> trax_runtime::abi::BvhNode {
        trax_runtime::abi::BvhNode {
            min: self.min,
            max: self.max,
            a: self.a,
            b: self.b,
        }
    }
}

/// Build settings.
#[derive(Clone, Debug, PartialEq)]
pub struct BvhOptions {
    /// Largest leaf: a node with more triangles is always split.
    pub max_leaf: u32,
    /// Most SAH bins per axis in the binned builder (large nodes use this many).
    pub bins: u32,
    /// Depth past which the builder switches from SAH to median splits (bounds the depth).
    pub sah_depth: u32,
    /// Treelets to form, if any. The image builder sets this itself from
    /// `RenderOptions::treelets` (and rejects it set).
    pub treelets: Option<TreeletOptions>,
}

impl Default for BvhOptions {
    fn default() -> Self {
        BvhOptions {
            max_leaf: 4,
            bins: 256,
            sah_depth: 48,
            treelets: None,
        }
    }
}

/// Errors from building a BVH.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BvhError {
    /// No triangles.
    #[error("cannot build a BVH over zero triangles")]
    Empty,
    /// A vertex is NaN or infinite.
    #[error("triangle {0} has a non-finite vertex")]
    NonFinite(usize),
    /// More triangles than fit in memory.
    #[error("{0} triangles do not fit in the 32-bit address space")]
    TooLarge(usize),
    /// A setting is out of range.
    #[error("invalid BVH option: {0}")]
    BadOption(String),
}

/// A built BVH.
#[derive(Clone, Debug)]
pub struct Bvh {
    /// Nodes; root at 0. Padding nodes (treelet alignment) are all zero.
    pub nodes: Vec<Node>,
    /// For each triangle slot, the scene triangle stored there, or [`PAD`].
    pub tri_order: Vec<u32>,
    /// Treelets, when requested.
    pub treelets: Option<Treelets>,
}

/// Summary figures of a BVH.
#[derive(Clone, Debug, PartialEq)]
pub struct BvhStats {
    /// Nodes in the array (including treelet padding).
    pub nodes: usize,
    /// Nodes reachable from the root (the tree itself, without treelet padding).
    pub tree_nodes: usize,
    /// Leaf nodes reachable from the root.
    pub leaves: usize,
    /// Longest root-to-leaf path (root alone = depth 1).
    pub depth: usize,
    /// SAH cost with [`C_TRAV`] and [`C_ISEC`].
    pub sah_cost: f32,
    /// Largest leaf.
    pub max_leaf: u32,
}

impl Bvh {
    /// Builds a BVH over `triangles` with the binned SAH builder, then forms treelets if
    /// `opts.treelets` is set.
    pub fn build(triangles: &[[Vec3; 3]], opts: &BvhOptions) -> Result<Bvh, BvhError> {
        check_input(triangles, opts)?;
        let mut bvh = binned::build(triangles, opts);
        if let Some(t) = &opts.treelets {
            treelet::apply(&mut bvh, t, opts.max_leaf)?;
        }
        Ok(bvh)
    }

    /// Parent index of every node (root and padding: `0xFFFF_FFFF`).
    pub fn parents(&self) -> Vec<u32> {
        let mut p = vec![u32::MAX; self.nodes.len()];
        for i in self.reachable() {
            let n = self.nodes[i as usize];
            if !n.is_leaf() {
                p[n.a as usize] = i;
                p[n.a as usize + 1] = i;
            }
        }
        p
    }

    /// Indices of the nodes reachable from the root, in depth-first order.
    pub fn reachable(&self) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.nodes.len());
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            out.push(i);
            let n = self.nodes[i as usize];
            if !n.is_leaf() {
                stack.push(n.a + 1);
                stack.push(n.a);
            }
        }
        out
    }

    /// Depth, leaf count and SAH cost.
    pub fn stats(&self) -> BvhStats {
        let root_area = self.nodes[0].aabb().area_f64();
        let mut cost = 0.0f64;
        let mut leaves = 0;
        let mut depth = 0;
        let mut max_leaf = 0;
        let mut tree_nodes = 0;
        let mut stack = vec![(0u32, 1usize)];
        while let Some((i, d)) = stack.pop() {
            let n = self.nodes[i as usize];
            tree_nodes += 1;
            depth = depth.max(d);
            let rel = if root_area > 0.0 {
                n.aabb().area_f64() / root_area
            } else {
                1.0
            };
            if n.is_leaf() {
                leaves += 1;
                max_leaf = max_leaf.max(n.b);
                cost += rel * (C_ISEC * n.b as f32) as f64;
            } else {
                cost += rel * C_TRAV as f64;
                stack.push((n.a, d + 1));
                stack.push((n.a + 1, d + 1));
            }
        }
        BvhStats {
            nodes: self.nodes.len(),
            tree_nodes,
            leaves,
            depth,
            sah_cost: cost as f32,
            max_leaf,
        }
    }
}

fn check_input(triangles: &[[Vec3; 3]], opts: &BvhOptions) -> Result<(), BvhError> {
    if triangles.is_empty() {
        return Err(BvhError::Empty);
    }
    // Node array (< 2n nodes × 32 bytes) must stay addressable.
    if triangles.len() as u64 >= crate::scene::MAX_TRIANGLES {
        return Err(BvhError::TooLarge(triangles.len()));
    }
    if let Some(i) = triangles
        .iter()
        .position(|t| !t.iter().flatten().all(|c| c.is_finite()))
    {
        return Err(BvhError::NonFinite(i));
    }
    if opts.max_leaf == 0 || opts.max_leaf > 255 {
        return Err(BvhError::BadOption(format!(
            "max_leaf must be in 1..=255, got {}",
            opts.max_leaf
        )));
    }
    if !(2..=4096).contains(&opts.bins) {
        return Err(BvhError::BadOption(format!(
            "bins must be in 2..=4096, got {}",
            opts.bins
        )));
    }
    Ok(())
}

impl Bvh {
    /// Checks the structural invariants against the triangles it was built from: every
    /// scene triangle is referenced from exactly one leaf slot and each slot at most once;
    /// every reachable node is visited once; child boxes lie inside their parent's; every
    /// leaf box holds its triangles; leaves respect `max_leaf`; siblings are adjacent by
    /// construction (children at `a`, `a + 1`). Returns the first violation found.
    pub fn check(&self, triangles: &[[Vec3; 3]], max_leaf: u32) -> Result<(), String> {
        let mut node_seen = vec![false; self.nodes.len()];
        let mut slot_seen = vec![false; self.tri_order.len()];
        let mut tri_seen = vec![false; triangles.len()];
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            let n = self
                .nodes
                .get(i as usize)
                .ok_or(format!("node {i} out of range"))?;
            if std::mem::replace(&mut node_seen[i as usize], true) {
                return Err(format!("node {i} reached twice"));
            }
            if n.min.iter().chain(&n.max).any(|c| !c.is_finite()) {
                return Err(format!("node {i} has a non-finite bound"));
            }
            if n.is_leaf() {
                if n.b > max_leaf {
                    return Err(format!("leaf {i} has {} triangles > {max_leaf}", n.b));
                }
                for s in n.a..n.a + n.b {
                    let slot = s as usize;
                    if slot >= self.tri_order.len() {
                        return Err(format!("leaf {i} slot {s} out of range"));
                    }
                    if std::mem::replace(&mut slot_seen[slot], true) {
                        return Err(format!("slot {s} referenced twice"));
                    }
                    let t = self.tri_order[slot];
                    if t == PAD {
                        return Err(format!("leaf {i} references padding slot {s}"));
                    }
                    if std::mem::replace(&mut tri_seen[t as usize], true) {
                        return Err(format!("triangle {t} reached twice"));
                    }
                    if !n
                        .aabb()
                        .contains(&Aabb::of_triangle(&triangles[t as usize]))
                    {
                        return Err(format!("leaf {i} box does not hold triangle {t}"));
                    }
                }
            } else {
                for c in [n.a, n.a + 1] {
                    let child = self
                        .nodes
                        .get(c as usize)
                        .ok_or(format!("node {i} child {c} out of range"))?;
                    if !n.aabb().contains(&child.aabb()) {
                        return Err(format!("child {c} box is not inside parent {i}"));
                    }
                    stack.push(c);
                }
            }
        }
        if let Some(t) = tri_seen.iter().position(|s| !s) {
            return Err(format!("triangle {t} is not reachable"));
        }
        Ok(())
    }
}
