//! Treelets (thesis §3.1.1 and chapter 5): the node array is cut into groups of at most a byte
//! budget (L1 capacity by default), each stored contiguously; triangles are grouped
//! separately into triangle treelets of the same budget, in leaf order. With `align_bytes`
//! set (STRaTA+), every node treelet starts on a multiple of that many bytes from its array's
//! start and every triangle treelet in the first 36-byte slot of such a block, holding what
//! fits in the budget from the block's start (padding nodes are zero, padding triangle slots
//! are [`PAD`]).
//!
//! Node treelets grow greedily from a root (the BVH root, or a sibling pair that did not fit
//! in its parent's treelet): the candidate sibling pair with the largest surface area joins
//! next, siblings always together, until the budget is full; pairs left over become roots of
//! later treelets, in breadth-first order. A root whose whole subtree fits in the budget is
//! not grown alone but packed, whole, into a shared treelet with other such subtrees (next
//! fit), so the many small subtrees near the leaves do not each open a nearly empty
//! treelet. Node treelet ids are `0..node_count`; triangle treelet ids follow them.

use std::collections::{BinaryHeap, VecDeque};
use std::ops::Range;

use super::{Bvh, BvhError, Node, PAD};

/// Arrays must stay below this many bytes (the 32-bit address space below the stacks).
const LIMIT: u64 = trax_runtime::abi::STACK_TOP as u64;

/// Bytes per node and per triangle as stored.
const NODE_BYTES: u32 = std::mem::size_of::<trax_runtime::abi::BvhNode>() as u32;
const TRI_BYTES: u32 = std::mem::size_of::<trax_runtime::abi::Triangle>() as u32;

/// Treelet settings.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TreeletOptions {
    /// Largest treelet in bytes (node and triangle treelets alike).
    pub budget_bytes: u32,
    /// Start every treelet on a multiple of this many bytes (a power of two, e.g. a DRAM
    /// row); 0 packs treelets back to back.
    pub align_bytes: u32,
}

impl Default for TreeletOptions {
    /// 32 KiB treelets (the default L1 capacity), not aligned.
    fn default() -> Self {
        TreeletOptions {
            budget_bytes: 32 * 1024,
            align_bytes: 0,
        }
    }
}

/// When the image builder forms treelets, and with which options (a chip config's
/// `[treelets]`, resolved by the pipeline).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TreeletLayout {
    /// Form treelets for every program that reads the BVH; when false, only for a program
    /// that reads `treelet_ids` or `tri_treelet_ids` (the others see the BVH in build
    /// order).
    pub always: bool,
    /// Budget and alignment.
    pub options: TreeletOptions,
}

impl Default for TreeletLayout {
    /// Treelets only for programs that read `treelet_ids`, with the default options.
    fn default() -> Self {
        TreeletLayout {
            always: false,
            options: TreeletOptions::default(),
        }
    }
}

impl TreeletLayout {
    /// The treelets to form for a program that references the header fields `referenced`
    /// (formed for one that reads `treelet_ids` or `tri_treelet_ids`).
    pub fn for_program(&self, referenced: &[&str]) -> Option<TreeletOptions> {
        let reads = referenced.contains(&"treelet_ids") || referenced.contains(&"tri_treelet_ids");
        (self.always || reads).then(|| self.options.clone())
    }
}

/// The treelets of a BVH.
#[derive(Clone, Debug, PartialEq)]
pub struct Treelets {
    /// Node treelet id of every node (`u32::MAX` for padding nodes).
    pub node_treelet: Vec<u32>,
    /// Node index range of each node treelet (id = position).
    pub node_ranges: Vec<Range<u32>>,
    /// Triangle slot range of each triangle treelet (id = node treelet count + position).
    pub tri_ranges: Vec<Range<u32>>,
    /// The options used.
    pub options: TreeletOptions,
}

impl Treelets {
    /// Total number of treelets (node and triangle).
    pub fn count(&self) -> usize {
        self.node_ranges.len() + self.tri_ranges.len()
    }
}

/// A max-heap entry: a sibling pair keyed by its summed surface area.
#[derive(PartialEq)]
struct Cand {
    area: f32,
    pair: u32,
}
impl Eq for Cand {}
impl PartialOrd for Cand {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cand {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        // Ties broken by index so the result is deterministic.
        self.area
            .total_cmp(&o.area)
            .then_with(|| o.pair.cmp(&self.pair))
    }
}

fn round_up(x: u32, to: u32) -> u32 {
    if to <= 1 {
        x
    } else {
        x.div_ceil(to) * to
    }
}

/// Forms treelets and reorders `bvh.nodes` and `bvh.tri_order` so each treelet is contiguous.
pub fn apply(bvh: &mut Bvh, opts: &TreeletOptions, max_leaf: u32) -> Result<(), BvhError> {
    // An aligned triangle treelet may start up to 35 bytes into its block.
    let slack = if opts.align_bytes == 0 {
        0
    } else {
        TRI_BYTES - 1
    };
    let min_budget = (3 * NODE_BYTES).max(max_leaf * TRI_BYTES + slack);
    if opts.budget_bytes < min_budget {
        return Err(BvhError::BadOption(format!(
            "treelet budget {} bytes is below the minimum {min_budget} (three nodes, one full leaf{})",
            opts.budget_bytes,
            if slack > 0 { " from any slot of an aligned block" } else { "" }
        )));
    }
    if opts.align_bytes != 0
        && (!opts.align_bytes.is_power_of_two()
            || opts.align_bytes < 64
            || opts.align_bytes > opts.budget_bytes)
    {
        return Err(BvhError::BadOption(format!(
            "treelet alignment must be 0 or a power of two from 64 to the budget ({}), got {}",
            opts.budget_bytes, opts.align_bytes
        )));
    }
    let cap = (opts.budget_bytes / NODE_BYTES) as usize;
    let old = &bvh.nodes;
    // Areas relative to the root's size (an exact power-of-two scaling: the same order as
    // plain areas, without overflow for huge scenes or underflow for tiny ones).
    let ks = old[0].aabb().area_scale();
    let area = |i: u32| {
        old[i as usize].aabb().area_scaled(ks) + old[i as usize + 1].aabb().area_scaled(ks)
    };

    // Subtree sizes in nodes (children always follow their parent in the array).
    let mut size = vec![1u32; old.len()];
    for i in (0..old.len()).rev() {
        let n = old[i];
        if !n.is_leaf() {
            size[i] = 1 + size[n.a as usize] + size[n.a as usize + 1];
        }
    }
    let subtree = |first: u32, is_pair: bool| -> u32 {
        if is_pair {
            size[first as usize] + size[first as usize + 1]
        } else {
            size[first as usize]
        }
    };

    // 1. Group nodes: each treelet is a list of old node indices, pairs kept adjacent. A root
    //    whose whole subtree fits is packed with other small subtrees (next fit) instead of
    //    opening a mostly empty treelet of its own.
    let mut groups: Vec<Vec<u32>> = Vec::new();
    let mut packing: Option<usize> = None; // index of the open packing group
    let mut roots: VecDeque<(u32, bool)> = VecDeque::from([(0u32, false)]); // (first, is_pair)
    while let Some((first, is_pair)) = roots.pop_front() {
        let members: &[u32] = if is_pair {
            &[first, first + 1]
        } else {
            &[first]
        };
        let whole = subtree(first, is_pair) as usize;
        if whole <= cap {
            let g = match packing {
                Some(k) if groups[k].len() + whole <= cap => k,
                _ => {
                    groups.push(Vec::with_capacity(cap.min(old.len())));
                    packing = Some(groups.len() - 1);
                    groups.len() - 1
                }
            };
            // Depth-first, pairs adjacent.
            let mut stack: Vec<u32> = Vec::new();
            for &m in members {
                groups[g].push(m);
                if !old[m as usize].is_leaf() {
                    stack.push(old[m as usize].a);
                }
            }
            stack.reverse();
            while let Some(pair) = stack.pop() {
                for m in [pair + 1, pair] {
                    if !old[m as usize].is_leaf() {
                        stack.push(old[m as usize].a);
                    }
                }
                groups[g].extend([pair, pair + 1]);
            }
            continue;
        }
        let mut g: Vec<u32> = Vec::new();
        let mut heap = BinaryHeap::new();
        for &m in members {
            g.push(m);
            let n = old[m as usize];
            if !n.is_leaf() {
                heap.push(Cand {
                    area: area(n.a),
                    pair: n.a,
                });
            }
        }
        while let Some(c) = heap.pop() {
            if g.len() + 2 > cap {
                roots.push_back((c.pair, true));
                continue;
            }
            for m in [c.pair, c.pair + 1] {
                g.push(m);
                let n = old[m as usize];
                if !n.is_leaf() {
                    heap.push(Cand {
                        area: area(n.a),
                        pair: n.a,
                    });
                }
            }
        }
        groups.push(g);
    }

    // 2. Lay the groups out, padding each start to the alignment.
    let align_nodes = (opts.align_bytes / NODE_BYTES).max(1);
    let mut new_of = vec![u32::MAX; old.len()];
    let mut layout: Vec<u32> = Vec::with_capacity(old.len()); // old index or u32::MAX (pad)
    let mut node_ranges = Vec::with_capacity(groups.len());
    for g in &groups {
        let start = round_up(layout.len() as u32, align_nodes);
        if start as u64 * NODE_BYTES as u64 >= LIMIT {
            return Err(BvhError::TooLarge(bvh.tri_order.len()));
        }
        layout.resize(start as usize, u32::MAX);
        for &o in g {
            new_of[o as usize] = layout.len() as u32;
            layout.push(o);
        }
        node_ranges.push(start..layout.len() as u32);
    }

    // 3. Triangles follow the new leaf order, grouped greedily without splitting a leaf.
    // An aligned triangle treelet starts in the first 36-byte slot of its aligned block
    // (36-byte slots meet a power-of-two boundary only every lcm(36, align) bytes, so
    // starting exactly on one would pad up to 4.5x) and holds what fits in the budget
    // counted from the block's start, so it covers no more blocks than a node treelet.
    let align = u64::from(opts.align_bytes);
    let budget = u64::from(opts.budget_bytes);
    let tri = u64::from(TRI_BYTES);
    // First slot of the treelet that follows slot `len`, and how many slots it holds.
    let next_start = |len: u32| -> u64 {
        if align == 0 {
            u64::from(len)
        } else {
            ((u64::from(len) * tri).div_ceil(align) * align).div_ceil(tri)
        }
    };
    let capacity = |start: u32| -> u32 {
        let at = u64::from(start) * tri;
        match at.checked_div(align) {
            None => (budget / tri) as u32,
            Some(blocks) => ((blocks * align + budget - at) / tri) as u32,
        }
    };
    let mut tri_order: Vec<u32> = Vec::with_capacity(bvh.tri_order.len());
    let mut tri_ranges: Vec<Range<u32>> = Vec::new();
    let mut cur_start = 0u32;
    let mut tri_cap = capacity(0);
    let mut nodes: Vec<Node> = Vec::with_capacity(layout.len());
    let mut node_treelet = Vec::with_capacity(layout.len());
    for (t, r) in node_ranges.iter().enumerate() {
        while (nodes.len() as u32) < r.start {
            nodes.push(Node::default());
            node_treelet.push(u32::MAX);
        }
        for &o in &layout[r.start as usize..r.end as usize] {
            let mut n = old[o as usize];
            if n.is_leaf() {
                let len = tri_order.len() as u32;
                if len - cur_start + n.b > tri_cap && len > cur_start {
                    tri_ranges.push(cur_start..len);
                    let start = next_start(len);
                    if start * tri >= LIMIT {
                        return Err(BvhError::TooLarge(bvh.tri_order.len()));
                    }
                    cur_start = start as u32;
                    tri_cap = capacity(cur_start);
                    tri_order.resize(cur_start as usize, PAD);
                }
                let first = tri_order.len() as u32;
                tri_order.extend_from_slice(&bvh.tri_order[n.a as usize..(n.a + n.b) as usize]);
                n.a = first;
            } else {
                n.a = new_of[n.a as usize];
            }
            nodes.push(n);
            node_treelet.push(t as u32);
        }
    }
    if tri_order.len() as u32 > cur_start {
        tri_ranges.push(cur_start..tri_order.len() as u32);
    }
    bvh.nodes = nodes;
    bvh.tri_order = tri_order;
    bvh.treelets = Some(Treelets {
        node_treelet,
        node_ranges,
        tri_ranges,
        options: opts.clone(),
    });
    Ok(())
}
