//! The four-wide BVH the traversal walks: a binary BVH collapsed so that each node holds four
//! children's boxes in full precision, side by side for one SIMD slab test ([`node_test`]),
//! as Embree's BVH4 does (Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray
//! Tracing", 2014). A child is an inner node or a leaf of up to [`MAX_LEAF`] primitives, which
//! sit side by side in the order the tree gives the caller.
//!
//! [`node_test`]: super::node_test

use super::node_test::NodeRay;
use glam::Vec4;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::node::Bvh2Node;
use smallvec::SmallVec;

/// Most primitives in a leaf: a child whose subtree holds no more is not opened once its
/// node's four slots are taken. Fewer nodes keep a large mesh's tree in cache.
const MAX_LEAF: usize = 4;

/// Pending children the traversal holds without allocating: a node visited leaves at most
/// three pending (four at the last level of an any-hit query), so this covers trees 21 deep;
/// deeper ones (the binary build bounds them, `binned_sah::MEDIAN_DEPTH`) spill to the heap.
const STACK: usize = 64;

/// A node fills two cache lines exactly.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
pub(super) struct Node {
    /// The four children's boxes: lower x, y, z, then upper x, y, z, one child per lane. An
    /// unused slot has lower +∞ and upper −∞, which no ray enters.
    pub planes: [Vec4; 6],
    /// Per child: an inner node's index, or a leaf's first primitive position.
    children: [u32; 4],
    /// Per child: 0 for an inner node, else the leaf's primitive count.
    leaf_sizes: [u8; 4],
}

impl Node {
    const UNUSED: Self = Self {
        planes: [
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
        ],
        children: [0; 4],
        leaf_sizes: [0; 4],
    };

    fn set_box(&mut self, slot: usize, b: &Aabb) {
        for axis in 0..3 {
            self.planes[axis][slot] = b.min[axis];
            self.planes[axis + 3][slot] = b.max[axis];
        }
    }
}

/// A four-wide BVH.
pub(super) struct WideBvh {
    nodes: Vec<Node>,
}

impl WideBvh {
    /// Collapse `binary`, whose leaves hold one primitive each: every node gathers four
    /// children by opening the inner child of largest surface area (the SAH's greedy order),
    /// and a gathered child of at most [`MAX_LEAF`] primitives becomes a leaf. Returns the
    /// tree and the order of its primitives: position `i` holds input primitive `order[i]`.
    pub fn collapse(binary: &Bvh2) -> (Self, Vec<u32>) {
        let b = &binary.nodes;
        let sizes = subtree_sizes(b);
        let mut nodes = Vec::with_capacity(b.len() / 4 + 1);
        let mut order = Vec::with_capacity(binary.primitive_indices.len());
        // (binary node, the slot its wide node goes in)
        let mut pending = vec![(0usize, None::<(usize, usize)>)];
        while let Some((root, parent)) = pending.pop() {
            let index = nodes.len();
            if let Some((p, slot)) = parent {
                let wide: &mut Node = &mut nodes[p];
                wide.children[slot] = index as u32;
            }
            let mut gathered = [root; 4];
            let mut count = 1;
            while count < 4 {
                let largest = gathered[..count]
                    .iter()
                    .enumerate()
                    .filter(|&(_, &n)| !b[n].is_leaf())
                    .max_by(|x, y| {
                        b[*x.1]
                            .aabb
                            .half_area()
                            .total_cmp(&b[*y.1].aabb.half_area())
                    })
                    .map(|(slot, _)| slot);
                let Some(slot) = largest else { break };
                let first = b[gathered[slot]].first_index as usize;
                gathered[slot] = first;
                gathered[count] = first + 1;
                count += 1;
            }
            let mut node = Node::UNUSED;
            for (slot, &child) in gathered[..count].iter().enumerate() {
                node.set_box(slot, &b[child].aabb);
                if sizes[child] as usize <= MAX_LEAF {
                    node.children[slot] = order.len() as u32;
                    node.leaf_sizes[slot] = sizes[child] as u8;
                    push_primitives(binary, child, &mut order);
                } else {
                    pending.push((child, Some((index, slot))));
                }
            }
            nodes.push(node);
        }
        (Self { nodes }, order)
    }

    /// Closest hit: `intersect(id, t_max)` returns the hit distance of primitive `id` below
    /// `t_max`, or infinity. Children are visited nearest first, and a pending child is
    /// dropped once a hit closer than its entry is found.
    #[inline]
    pub fn closest_hit<F>(
        &self,
        ray: &NodeRay,
        mut t_max: f32,
        mut intersect: F,
    ) -> Option<(u32, f32)>
    where
        F: FnMut(u32, f32) -> f32,
    {
        let mut stack = SmallVec::<[(u32, f32); STACK]>::new();
        let mut node = 0u32;
        let mut nearest = None;
        loop {
            let n = &self.nodes[node as usize];
            let (near, mut mask) = ray.enters(n, t_max);
            let mut inner = [(0u32, 0f32); 4];
            let mut count = 0;
            while mask != 0 {
                let slot = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let child = n.children[slot];
                match n.leaf_sizes[slot] {
                    0 => {
                        inner[count] = (child, near[slot]);
                        count += 1;
                    }
                    size => {
                        for id in child..child + u32::from(size) {
                            let t = intersect(id, t_max);
                            if t < t_max {
                                nearest = Some(id);
                                t_max = t;
                            }
                        }
                    }
                }
            }
            // Farthest first onto the stack; the nearest is walked next.
            farthest_first(&mut inner[..count]);
            let next = match count {
                0 => loop {
                    let Some((candidate, entry)) = stack.pop() else {
                        return nearest.map(|id| (id, t_max));
                    };
                    if entry <= t_max {
                        break candidate;
                    }
                },
                _ => {
                    stack.extend_from_slice(&inner[..count - 1]);
                    inner[count - 1].0
                }
            };
            node = next;
        }
    }

    /// Whether `intersect` reports a hit closer than `t_max` for any primitive whose box the
    /// ray enters.
    #[inline]
    pub fn any_hit<F>(&self, ray: &NodeRay, t_max: f32, mut intersect: F) -> bool
    where
        F: FnMut(u32, f32) -> f32,
    {
        let mut stack = SmallVec::<[u32; STACK]>::new();
        let mut node = 0u32;
        loop {
            let n = &self.nodes[node as usize];
            let (_, mut mask) = ray.enters(n, t_max);
            while mask != 0 {
                let slot = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let child = n.children[slot];
                match n.leaf_sizes[slot] {
                    0 => stack.push(child),
                    size => {
                        if (child..child + u32::from(size)).any(|id| intersect(id, t_max) < t_max) {
                            return true;
                        }
                    }
                }
            }
            let Some(next) = stack.pop() else {
                return false;
            };
            node = next;
        }
    }
}

/// Sort (child, entry distance) pairs, at most four, by decreasing distance: an insertion
/// sort, which for so few beats the general sort's set-up.
#[inline(always)]
fn farthest_first(children: &mut [(u32, f32)]) {
    for i in 1..children.len() {
        let mut j = i;
        while j > 0 && children[j - 1].1 < children[j].1 {
            children.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// The number of primitives under each node of a binary BVH with one primitive per leaf.
fn subtree_sizes(b: &[Bvh2Node]) -> Vec<u32> {
    // Pre-order puts every node before its children; sum in reverse.
    let mut preorder = Vec::with_capacity(b.len());
    let mut stack = vec![0usize];
    while let Some(n) = stack.pop() {
        preorder.push(n);
        if !b[n].is_leaf() {
            let first = b[n].first_index as usize;
            stack.extend([first, first + 1]);
        }
    }
    let mut sizes = vec![0u32; b.len()];
    for &n in preorder.iter().rev() {
        sizes[n] = if b[n].is_leaf() {
            b[n].prim_count
        } else {
            let first = b[n].first_index as usize;
            sizes[first] + sizes[first + 1]
        };
    }
    sizes
}

/// Append the input indices of the primitives under binary node `root` to `order`.
fn push_primitives(binary: &Bvh2, root: usize, order: &mut Vec<u32>) {
    let mut stack = vec![root];
    while let Some(n) = stack.pop() {
        let node = &binary.nodes[n];
        let first = node.first_index as usize;
        if node.is_leaf() {
            order.extend_from_slice(
                &binary.primitive_indices[first..first + node.prim_count as usize],
            );
        } else {
            stack.extend([first + 1, first]);
        }
    }
}
