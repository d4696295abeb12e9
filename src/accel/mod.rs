//! Bounding volume hierarchy over anything with bounds.
//!
//! A binary tree from our binned SAH build ([`binned_sah`]), improved by `obvhs`' reinsertion
//! optimizer (Meister & Bittner 2022) and collapsed into our four-wide BVH ([`wide`]): four
//! children's boxes per node in full precision, tested side by side by our node test
//! ([`node_test`]), whose answers do not depend on the scene's unit. Chosen by measurement over
//! `obvhs`' compressed 8-wide BVH, which it replaced: on the 102k-triangle benchmark, one core,
//! 4.9 M camera, 3.6 M bounce and 5.8 M shadow rays/s against 3.5 M, 3.4 M and 5.1 M. It knows
//! only boxes and primitive indices; what a primitive is stays with the caller's intersection
//! closure.

use crate::geometry::Bounds;
use crate::math::Ray;
use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;

mod binned_sah;
#[cfg(feature = "embree")]
pub mod embree;
mod node_test;
mod wide;

use node_test::NodeRay;
use wide::WideBvh;

/// Which ray caster holds a scene's triangles: our BVH (a four-wide BVH over our own SAH
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

/// A built BVH. Primitive ids seen by the intersection closures are positions in
/// [`Bvh::order`], so the caller stores its primitives in that order.
pub struct Bvh {
    /// `None` over no primitives.
    tree: Option<WideBvh>,
}

/// How far each primitive's box is grown, over the largest coordinate of the scene's bounds.
const BOX_PADDING: f32 = 1.0 / 131_072.0;

/// The primitives' boxes, each grown by [`BOX_PADDING`] of the scene's largest coordinate.
/// The node test rounds, so a ray through a box's corner or along its face can be judged to
/// pass by: a ray aimed exactly at a triangle's vertex, where the triangle's box is tight,
/// then missed it and every neighbour sharing the vertex, and escaped a closed mesh. The node
/// test widens its far distance by the rounding bound of the slab method (Ize, "Robust BVH Ray
/// Traversal", JCGT 2013); growing the boxes by a few dozen ulps of the scene also covers the
/// rounding of the boxes themselves. The exact triangle test decides.
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
            return (Self { tree: None }, Vec::new());
        }
        let boxes = padded_boxes(bounds);
        let mut binary = binned_sah::build(&boxes, binned_sah::MEDIAN_DEPTH);
        ReinsertionOptimizer::default().run(&mut binary, REINSERTION_BATCH_RATIO, None);
        let (tree, order) = WideBvh::collapse(&binary);
        (Self { tree: Some(tree) }, order)
    }

    /// Closest hit: `intersect(id, t_max)` returns the hit distance of primitive `id` below
    /// `t_max`, or infinity. Returns the id and distance of the nearest hit.
    #[inline]
    pub fn closest_hit<F>(&self, ray: &Ray, t_max: f32, intersect: F) -> Option<(u32, f32)>
    where
        F: FnMut(u32, f32) -> f32,
    {
        let tree = self.tree.as_ref()?;
        let r = NodeRay::new(Vec3A::from(ray.origin), Vec3A::from(ray.dir));
        tree.closest_hit(&r, t_max, intersect)
    }

    /// Whether any primitive is hit closer than `t_max`.
    #[inline]
    pub fn any_hit<F>(&self, ray: &Ray, t_max: f32, intersect: F) -> bool
    where
        F: FnMut(u32, f32) -> f32,
    {
        let Some(tree) = &self.tree else {
            return false;
        };
        let r = NodeRay::new(Vec3A::from(ray.origin), Vec3A::from(ray.dir));
        tree.any_hit(&r, t_max, intersect)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    /// Boxes spread over 17 orders of magnitude, where each binned split peels off a few and
    /// the tree is as deep as the build allows: a ray down through each box's middle finds
    /// that box first, and one beside them all (past the boxes' padding, 2⁻¹⁷ of the largest
    /// coordinate) finds none.
    #[test]
    fn a_skewed_deep_tree_finds_every_box() {
        let n = 50_000;
        let boxes: Vec<Bounds> = (0..n)
            .map(|i| {
                let at = Vec3::new(1.0008f32.powi(i), 0.0, 0.0);
                Bounds {
                    min: at,
                    max: at + Vec3::splat(0.05),
                }
            })
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert!(seen.iter().copied().eq(0..n as u32), "every primitive once");
        let box_of = |id: u32| boxes[order[id as usize] as usize];
        for i in (0..n as usize).step_by(97) {
            let middle = (boxes[i].min + boxes[i].max) * 0.5;
            let ray = Ray::new(middle + Vec3::Y, -Vec3::Y);
            let hit = bvh.closest_hit(&ray, f32::INFINITY, |id, _| {
                let b = box_of(id);
                if (b.min.x..=b.max.x).contains(&middle.x) {
                    1.0 - b.max.y
                } else {
                    f32::INFINITY
                }
            });
            let (id, _) = hit.expect("the box below the ray");
            assert!((box_of(id).min.x..=box_of(id).max.x).contains(&middle.x));
        }
        let beside = Ray::new(Vec3::new(-1e14, 1.0, 0.0), -Vec3::Y);
        assert!(
            bvh.closest_hit(&beside, f32::INFINITY, |_, _| 0.5)
                .is_none()
        );
    }
}
