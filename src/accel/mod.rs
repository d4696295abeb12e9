//! Bounding volume hierarchy over anything with bounds.
//!
//! A thin layer over `obvhs`' compressed 8-wide BVH (Ylitie et al., "Efficient Incoherent Ray
//! Traversal on GPUs Through Compressed Wide BVHs", 2017), chosen by measurement: the fastest
//! pure-Rust BVH we measured (5.1 M camera and 1.7 M bounce rays/s on one core, against 2.1 M
//! and 0.7 M for `parry3d` and `bvh`). Its nodes and traversal order are obvhs'; the ray–node
//! test is ours ([`node_test`]), so that the answers do not depend on the scene's unit. It
//! knows only boxes and primitive indices; what a primitive is stays with the caller's
//! intersection closure.

use crate::geometry::Bounds;
use crate::math::{Ray, Vec3};
use glam::{UVec2, Vec3A};
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::{aabb::Aabb, cwbvh::CwBvh};

mod binned_sah;
#[cfg(feature = "embree")]
pub mod embree;
mod node_test;

use node_test::{NodeRay, hit_children};

/// Which ray caster holds a scene's triangles: our BVH (obvhs' wide BVH over our own SAH
/// build), or Intel Embree when the `embree` cargo feature is compiled in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RayEngine {
    /// The best compiled in: Embree with the `embree` feature, else our BVH.
    #[default]
    Best,
    Bvh,
    Embree,
}

impl RayEngine {
    /// Whether this build has Embree (the `embree` cargo feature).
    pub const EMBREE_COMPILED: bool = cfg!(feature = "embree");

    /// The engine `Best` stands for in this build; the others as they are.
    pub fn resolved(self) -> Self {
        match self {
            Self::Best if Self::EMBREE_COMPILED => Self::Embree,
            Self::Best => Self::Bvh,
            other => other,
        }
    }

    /// Every engine this build can run: our BVH, and Embree with the feature.
    pub fn compiled() -> Vec<Self> {
        let mut engines = vec![Self::Bvh];
        if Self::EMBREE_COMPILED {
            engines.push(Self::Embree);
        }
        engines
    }

    /// The name the CLI and benchmarks print.
    pub fn name(self) -> &'static str {
        match self.resolved() {
            Self::Embree => "embree",
            _ => "bvh",
        }
    }
}

/// The share of nodes that each of `obvhs`' reinsertion sweeps (Meister & Bittner 2022) moves
/// to a cheaper place in the tree: its "medium" preset.
const REINSERTION_BATCH_RATIO: f32 = 0.05;

/// Primitives per leaf of the wide BVH, at most; `obvhs` takes 1 to 3.
const MAX_LEAF_PRIMITIVES: u32 = 3;

/// The deepest wide BVH the traversal can walk: obvhs keeps pending node groups on a stack of
/// 32 entries, at most one per level, and a push onto a full stack overwrites its top entry
/// (a deeper tree would lose nodes without a word).
const MAX_WIDE_DEPTH: usize = 31;

/// A built BVH. Primitive ids seen by the intersection closures are positions in
/// [`Bvh::order`], so the caller stores its primitives in that order.
pub struct Bvh {
    inner: CwBvh,
    empty: bool,
}

/// How far each primitive's box is grown, over the largest coordinate of the scene's bounds.
const BOX_PADDING: f32 = 1.0 / 131_072.0;

/// The primitives' boxes, each grown by [`BOX_PADDING`] of the scene's largest coordinate.
/// The node test rounds, so a ray through a box's corner or along its face can be judged to
/// pass by: a ray aimed exactly at a triangle's vertex, where the triangle's box is tight,
/// then missed it and every neighbour sharing the vertex, and escaped a closed mesh. The node
/// test widens its far distance by the rounding bound of the slab method (Ize, "Robust BVH Ray
/// Traversal", JCGT 2013), but its distances to the quantised planes add two rounded terms,
/// whose cancellation that bound does not cover; growing the boxes by a few dozen ulps of the
/// scene does. The exact triangle test decides.
fn padded_boxes(bounds: &[Bounds]) -> Vec<Aabb> {
    let total = bounds.iter().fold(Bounds::EMPTY, |a, b| a.union(*b));
    let largest = total.min.abs().max(total.max.abs()).max_element();
    let pad = if largest.is_finite() {
        Vec3A::splat(largest * BOX_PADDING)
    } else {
        Vec3A::ZERO
    };
    bounds
        .iter()
        .map(|b| Aabb::new(Vec3A::from(b.min) - pad, Vec3A::from(b.max) + pad))
        .collect()
}

impl Bvh {
    /// Build over the given boxes. Returns the BVH and the permutation: position `i` of the
    /// BVH's primitive order holds input primitive `order[i]`.
    pub fn build(bounds: &[Bounds]) -> (Self, Vec<u32>) {
        if bounds.is_empty() {
            let bvh = Self {
                inner: CwBvh::default(),
                empty: true,
            };
            return (bvh, Vec::new());
        }
        Self::build_within(bounds, MAX_WIDE_DEPTH)
    }

    /// [`Bvh::build`] with the tree held to `max_depth` wide nodes: an SAH tree deeper than
    /// that (boxes spread over many orders of magnitude, where each split peels off a few) is
    /// built again with median splits, a balanced tree of about log₈ n levels.
    fn build_within(bounds: &[Bounds], max_depth: usize) -> (Self, Vec<u32>) {
        let boxes = padded_boxes(bounds);
        let mut binary = binned_sah::build(&boxes, binned_sah::MEDIAN_DEPTH);
        ReinsertionOptimizer::default().run(&mut binary, REINSERTION_BATCH_RATIO, None);
        let mut inner = bvh2_to_cwbvh(&binary, MAX_LEAF_PRIMITIVES, true, false);
        if wide_depth(&inner) > max_depth {
            inner = bvh2_to_cwbvh(
                &binned_sah::build(&boxes, 0),
                MAX_LEAF_PRIMITIVES,
                true,
                false,
            );
        }
        let order = inner.primitive_indices.clone();
        (
            Self {
                inner,
                empty: false,
            },
            order,
        )
    }

    /// Closest hit: `intersect(id, t_max)` returns the hit distance of primitive `id` below
    /// `t_max`, or infinity. Returns the id and distance of the nearest hit.
    ///
    /// The traversal is `obvhs`' own loop (its `traverse!` macro) written out here rather than
    /// called through `CwBvh::ray_traverse`, so that `intersect` is inlined into it: through
    /// the function it stayed a call per primitive tested.
    #[inline]
    pub fn closest_hit<F>(&self, ray: &Ray, t_max: f32, mut intersect: F) -> Option<(u32, f32)>
    where
        F: FnMut(u32, f32) -> f32,
    {
        if self.empty {
            return None;
        }
        let r = NodeRay::new(Vec3A::from(ray.origin), Vec3A::from(ray.dir));
        let mut t_max = t_max;
        let mut state = self.inner.new_traversal(r.direction());
        let mut node;
        let mut nearest = None;
        obvhs::traverse!(
            self.inner,
            node,
            state,
            hit_children(node, &r, t_max, state.oct_inv4),
            {
                let t = intersect(state.primitive_id, t_max);
                if t < t_max {
                    nearest = Some(state.primitive_id);
                    t_max = t;
                }
            }
        );
        nearest.map(|id| (id, t_max))
    }

    /// Whether any primitive is hit closer than `t_max`.
    #[inline]
    pub fn any_hit<F>(&self, ray: &Ray, t_max: f32, mut intersect: F) -> bool
    where
        F: FnMut(u32, f32) -> f32,
    {
        if self.empty {
            return false;
        }
        let r = NodeRay::new(Vec3A::from(ray.origin), Vec3A::from(ray.dir));
        let mut state = self.inner.new_traversal(r.direction());
        let mut node;
        let mut blocked = false;
        'traversal: {
            obvhs::traverse!(
                self.inner,
                node,
                state,
                hit_children(node, &r, t_max, state.oct_inv4),
                {
                    if intersect(state.primitive_id, t_max) < t_max {
                        blocked = true;
                        break 'traversal;
                    }
                }
            );
        }
        blocked
    }

    /// Number of nodes, for statistics.
    pub fn node_count(&self) -> usize {
        self.inner.nodes.len()
    }

    /// Bounds of everything in the BVH.
    pub fn bounds(&self) -> Bounds {
        let b = self.inner.total_aabb;
        Bounds {
            min: Vec3::from(b.min),
            max: Vec3::from(b.max),
        }
    }
}

/// Wide nodes on the longest root-to-leaf path of `bvh`.
fn wide_depth(bvh: &CwBvh) -> usize {
    let mut stack = vec![(0usize, 1usize)];
    let mut deepest = 0;
    while let Some((i, depth)) = stack.pop() {
        deepest = deepest.max(depth);
        let node = &bvh.nodes[i];
        for child in (0..8).filter(|&c| !node.is_leaf(c)) {
            stack.push((node.child_node_index(child) as usize, depth + 1));
        }
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(at: Vec3) -> Bounds {
        Bounds {
            min: at,
            max: at + Vec3::splat(0.05),
        }
    }

    /// Boxes spread over 17 orders of magnitude, where each binned split peels off a few:
    /// the SAH tree widens to 25 levels, within the traversal stack, and a tree held to fewer
    /// is rebuilt balanced, with every primitive in it once. (No further spread: obvhs'
    /// widening compares surface areas, and asserts in debug builds when they leave f32's
    /// range.)
    #[test]
    fn a_tree_too_deep_for_the_traversal_stack_is_rebuilt_balanced() {
        let n = 50_000;
        let boxes: Vec<Bounds> = (0..n)
            .map(|i| cube(Vec3::new(1.0008f32.powi(i), 0.0, 0.0)))
            .collect();
        let (sah, _) = Bvh::build(&boxes);
        let sah_depth = wide_depth(&sah.inner);
        assert!((16..=MAX_WIDE_DEPTH).contains(&sah_depth), "{sah_depth}");
        let (balanced, order) = Bvh::build_within(&boxes, 12);
        let depth = wide_depth(&balanced.inner);
        assert!(depth <= 8, "rebuilt {depth} wide nodes deep");
        let mut seen = order.clone();
        seen.sort_unstable();
        assert!(seen.iter().copied().eq(0..n as u32), "every primitive once");
    }
}
