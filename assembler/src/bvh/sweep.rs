//! Reference full-sweep SAH builder: at every node, sorts the triangles by centroid on each
//! axis and evaluates the SAH between every pair of neighbours (as simtrax's `BVH.cc` does).
//! O(n log² n): slow, used to judge the binned builder's quality, not for real scenes.

use super::{Aabb, Bvh, BvhError, BvhOptions, Node, C_TRAV};
use crate::scene::Vec3;

/// Builds a BVH with full-sweep SAH, the same leaf rule and cap as the binned builder.
pub fn build(triangles: &[[Vec3; 3]], opts: &BvhOptions) -> Result<Bvh, BvhError> {
    super::check_input(triangles, opts)?;
    let boxes: Vec<Aabb> = triangles.iter().map(Aabb::of_triangle).collect();
    let cent: Vec<Vec3> = boxes.iter().map(Aabb::center).collect();
    let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
    let mut nodes = vec![Node::default()];
    let max_leaf = opts.max_leaf as usize;
    let mut stack = vec![(0u32, 0usize, triangles.len())];
    let mut right_area = Vec::new();
    while let Some((node, start, end)) = stack.pop() {
        let n = end - start;
        let range = &mut order[start..end];
        let bounds = range
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.union(&boxes[i as usize]));
        let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, left size)
                                                          // Areas relative to the node's size (exact power-of-two scaling).
        let ks = bounds.area_scale();
        if n > 1 {
            #[allow(clippy::needless_range_loop)] // `axis` indexes each centroid, not `cent`
            for axis in 0..3 {
                range.sort_by(|&a, &b| cent[a as usize][axis].total_cmp(&cent[b as usize][axis]));
                right_area.clear();
                right_area.resize(n + 1, 0.0f32);
                let mut acc = Aabb::EMPTY;
                for k in (1..n).rev() {
                    acc = acc.union(&boxes[range[k] as usize]);
                    right_area[k] = acc.area_scaled(ks);
                }
                let mut acc = Aabb::EMPTY;
                for k in 1..n {
                    acc = acc.union(&boxes[range[k - 1] as usize]);
                    // Only split between distinct centroids, like a binned split could.
                    if cent[range[k - 1] as usize][axis] == cent[range[k] as usize][axis] {
                        continue;
                    }
                    let cost = acc.area_scaled(ks) * k as f32 + right_area[k] * (n - k) as f32;
                    if best.is_none_or(|b| cost < b.0) {
                        best = Some((cost, axis, k));
                    }
                }
            }
        }
        let area = bounds.area_scaled(ks);
        let split = match best {
            Some((cost, axis, k)) => {
                if n <= max_leaf && n as f32 * area <= C_TRAV * area + cost {
                    None
                } else {
                    range.sort_by(|&a, &b| {
                        cent[a as usize][axis].total_cmp(&cent[b as usize][axis])
                    });
                    Some(k)
                }
            }
            None => (n > max_leaf).then_some(n / 2),
        };
        match split {
            None => {
                nodes[node as usize] = Node {
                    min: bounds.min,
                    max: bounds.max,
                    a: start as u32,
                    b: n as u32,
                }
            }
            Some(k) => {
                let a = nodes.len() as u32;
                nodes.push(Node::default());
                nodes.push(Node::default());
                nodes[node as usize] = Node {
                    min: bounds.min,
                    max: bounds.max,
                    a,
                    b: 0,
                };
                stack.push((a + 1, start + k, end));
                stack.push((a, start, start + k));
            }
        }
    }
    Ok(Bvh {
        nodes,
        tri_order: order,
        treelets: None,
    })
}
