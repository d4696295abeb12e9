//! A top-down binned SAH build of a binary BVH (Wald 2007, "On fast construction of SAH-based
//! bounding volume hierarchies"), in `obvhs`' `Bvh2` layout so that its reinsertion optimizer
//! and wide-BVH conversion take it from there.
//!
//! Why our own build rather than `obvhs`' PLOC: PLOC merges neighbours that choose each other,
//! and when many candidate merges cost the same (coincident triangles, or equal triangles
//! evenly spaced in a row) its tie-breaking lets only one pair merge per sweep, so the build
//! becomes quadratic: 40k coincident triangles took 28 s. A top-down build splits every node,
//! whatever the costs; equal centroids fall back to a split at the middle of the list, and past
//! a depth limit every split is a median split, so the cost is O(n log n) for any input.

use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::node::Bvh2Node;

/// Bins per axis: Wald's 16 to 32 give nearly the quality of a full sweep.
const BINS: usize = 16;

/// Past this depth only median splits are made, which bounds the depth (and the build's
/// cost) at `MEDIAN_DEPTH + log2(n)` whatever the SAH would choose.
pub const MEDIAN_DEPTH: usize = 48;

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

impl Bin {
    const EMPTY: Self = Self {
        bounds: Aabb::INVALID,
        count: 0,
    };
}

/// A binary BVH over `boxes` with one primitive per leaf, split by the SAH down to depth
/// `median_depth` and at the median below it (0: a balanced tree).
pub fn build(boxes: &[Aabb], median_depth: usize) -> Bvh2 {
    let n = boxes.len();
    let centroids: Vec<_> = boxes.iter().map(Aabb::center).collect();
    let mut indices: Vec<u32> = (0..n as u32).collect();
    let mut nodes = vec![Bvh2Node::default(); 2 * n - 1];
    // (node, first, end, depth): the node that holds indices[first..end].
    let mut stack = vec![(0usize, 0usize, n, 0usize)];
    let mut next_node = 1;
    let mut max_depth = 0;
    while let Some((node, first, end, depth)) = stack.pop() {
        max_depth = max_depth.max(depth);
        let range = &mut indices[first..end];
        let bounds = range
            .iter()
            .fold(Aabb::INVALID, |b, &i| b.union(&boxes[i as usize]));
        if range.len() == 1 {
            nodes[node] = Bvh2Node::new(bounds, 1, first as u32);
            continue;
        }
        let middle = first + split(range, boxes, &centroids, depth >= median_depth);
        // Siblings sit side by side, the left at an odd index, as `Bvh2` requires.
        let left = next_node;
        next_node += 2;
        nodes[node] = Bvh2Node::new(bounds, 0, left as u32);
        stack.push((left + 1, middle, end, depth + 1));
        stack.push((left, first, middle, depth + 1));
    }
    Bvh2 {
        nodes,
        primitive_indices: indices,
        max_depth: obvhs::bvh2::DEFAULT_MAX_STACK_DEPTH.max(max_depth + 1),
        ..Bvh2::default()
    }
}

/// Reorder `range` so that its first `k` primitives form the left child; returns `k`, which is
/// always in `1..range.len()`.
fn split(range: &mut [u32], boxes: &[Aabb], centroids: &[glam::Vec3A], median: bool) -> usize {
    let centre_bounds = range.iter().fold(Aabb::INVALID, |mut b, &i| {
        b.extend(centroids[i as usize]);
        b
    });
    let extent = centre_bounds.diagonal();
    let half = range.len() / 2;
    if median || extent.max_element() <= 0.0 {
        // All centroids equal (or the depth limit): any halving is as good as another.
        if extent.max_element() > 0.0 {
            let axis = extent.max_position();
            range.select_nth_unstable_by(half, |&a, &b| {
                centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
            });
        }
        return half;
    }
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let bin_of = bin_index(centre_bounds.min[axis], extent[axis]);
        let mut bins = [Bin::EMPTY; BINS];
        for &i in range.iter() {
            let b = &mut bins[bin_of(centroids[i as usize][axis])];
            b.bounds = b.bounds.union(&boxes[i as usize]);
            b.count += 1;
        }
        // Right-to-left sweep: the cost of everything right of each boundary.
        let mut right_cost = [0.0f32; BINS];
        let mut acc = Bin::EMPTY;
        for k in (1..BINS).rev() {
            acc.bounds = acc.bounds.union(&bins[k].bounds);
            acc.count += bins[k].count;
            right_cost[k] = cost(&acc);
        }
        let mut acc = Bin::EMPTY;
        for k in 1..BINS {
            acc.bounds = acc.bounds.union(&bins[k - 1].bounds);
            acc.count += bins[k - 1].count;
            if acc.count == 0 || acc.count as usize == range.len() {
                continue;
            }
            let c = cost(&acc) + right_cost[k];
            if best.is_none_or(|(b, _, _)| c < b) {
                best = Some((c, axis, k));
            }
        }
    }
    let Some((_, axis, k)) = best else {
        // Every primitive fell in one bin on every axis (extents near float precision).
        return half;
    };
    let bin_of = bin_index(centre_bounds.min[axis], extent[axis]);
    let mut left = 0;
    for j in 0..range.len() {
        if bin_of(centroids[range[j] as usize][axis]) < k {
            range.swap(left, j);
            left += 1;
        }
    }
    left
}

/// The bin of a centroid coordinate, for centroids spanning `[min, min + extent]`.
fn bin_index(min: f32, extent: f32) -> impl Fn(f32) -> usize {
    let scale = BINS as f32 / extent;
    move |c| (((c - min) * scale) as usize).min(BINS - 1)
}

/// The surface-area cost of a candidate child: half its area times its primitives.
fn cost(bin: &Bin) -> f32 {
    if bin.count == 0 {
        0.0
    } else {
        bin.bounds.half_area() * bin.count as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    fn unit_box(at: Vec3A) -> Aabb {
        Aabb::new(at, at + Vec3A::splat(0.05))
    }

    /// Every primitive in exactly one leaf, every node's box around its children's, and the
    /// depth within the bound that keeps the build O(n log n).
    fn check(boxes: &[Aabb]) -> usize {
        let bvh = build(boxes, MEDIAN_DEPTH);
        let mut seen = vec![false; boxes.len()];
        let mut stack = vec![(0usize, 0usize)];
        let mut deepest = 0;
        while let Some((i, depth)) = stack.pop() {
            deepest = deepest.max(depth);
            let node = &bvh.nodes[i];
            if node.prim_count > 0 {
                let prim = bvh.primitive_indices[node.first_index as usize] as usize;
                assert!(!seen[prim], "primitive {prim} in two leaves");
                seen[prim] = true;
                assert_eq!(*node.aabb(), boxes[prim]);
                continue;
            }
            let left = node.first_index as usize;
            assert_eq!(left % 2, 1, "a left child must sit at an odd index");
            for child in [left, left + 1] {
                let c = bvh.nodes[child].aabb();
                assert!(node.aabb().min.cmple(c.min).all() && node.aabb().max.cmpge(c.max).all());
                stack.push((child, depth + 1));
            }
        }
        assert!(seen.iter().all(|&s| s), "a primitive is missing");
        assert!(bvh.max_depth > deepest);
        deepest
    }

    #[test]
    fn degenerate_layouts_build_shallow_complete_trees() {
        let n = 20_000;
        let log2 = (n as f64).log2().ceil() as usize;
        let coincident = vec![unit_box(Vec3A::ZERO); n];
        // Equal centroids: halving at each level gives a balanced tree.
        assert_eq!(check(&coincident), log2);
        let row: Vec<_> = (0..n)
            .map(|i| unit_box(Vec3A::new(i as f32 * 0.1, 0.0, 0.0)))
            .collect();
        assert!(check(&row) <= 2 * log2);
        // Exponentially spaced boxes: the SAH peels one box per level; the median fallback
        // past MEDIAN_DEPTH bounds the depth.
        let skewed: Vec<_> = (0..n)
            .map(|i| unit_box(Vec3A::new(1.001f32.powi(i as i32), 0.0, 0.0)))
            .collect();
        assert!(check(&skewed) <= MEDIAN_DEPTH + log2 + 1);
    }

    #[test]
    fn the_sah_separates_two_clusters_at_the_root() {
        let mut boxes: Vec<_> = (0..100)
            .map(|i| unit_box(Vec3A::new(i as f32 * 0.01, 0.0, 0.0)))
            .collect();
        boxes.extend((0..100).map(|i| unit_box(Vec3A::new(50.0 + i as f32 * 0.01, 0.0, 0.0))));
        check(&boxes);
        let bvh = build(&boxes, MEDIAN_DEPTH);
        let left = bvh.nodes[bvh.nodes[0].first_index as usize].aabb();
        assert!(left.max.x < 2.0 || left.min.x > 40.0, "{left:?}");
    }
}
