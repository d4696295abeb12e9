//! The ray–node test of the four-wide BVH: which of a node's four child boxes a ray enters
//! before its far distance, and at what distance.
//!
//! Each box is tested by the slab method (Kay and Kajiya 1986; Williams et al. 2005), the four
//! children side by side in one `Vec4` per plane. The far distance is scaled by 1 + 2γ₃ so
//! that rounding can only make the test conservative (Ize, "Robust BVH Ray Traversal", JCGT
//! 2013); the exact primitive tests decide. A box counts from distance 0, whatever the scene's
//! unit, and only direction components below 10⁻²⁰ are replaced, so no ray is bent off a face
//! it runs along.

use super::wide::Node;
use glam::{Vec3A, Vec4};

/// A direction component smaller than this in magnitude is taken as this, with its sign (+
/// for ±0): the ray then moves at most 10⁻²⁰ of its length off its line, and the products of
/// the slab test stay finite (no 0 · ∞) for any coordinate below 10¹⁵.
const TINY_COMPONENT: f32 = 1e-20;

/// 1 + 2γ₃ with γₙ = nε / (1 − nε) and ε = 2⁻²⁴ (pbrt-v4, §6.8.2): a bound on the relative
/// rounding error of a slab distance computed in three rounded operations.
const FAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// A ray as the node test reads it: its origin and inverse direction splatted over the four
/// children, and per axis which of a node's planes it enters a slab by.
pub(super) struct NodeRay {
    origin: [Vec4; 3],
    inv_direction: [Vec4; 3],
    /// Per axis, the index in [`Node::planes`] of the plane the ray enters the slab by (the
    /// upper one when the direction is negative) and of the one it leaves by.
    entry: [usize; 3],
    exit: [usize; 3],
}

impl NodeRay {
    pub fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let fix = |d: f32| {
            if d.abs() >= TINY_COMPONENT {
                d
            } else if d < 0.0 {
                -TINY_COMPONENT
            } else {
                TINY_COMPONENT
            }
        };
        let direction = Vec3A::new(fix(direction.x), fix(direction.y), fix(direction.z));
        let inv = direction.recip();
        let negative = [direction.x < 0.0, direction.y < 0.0, direction.z < 0.0];
        let entry = [0, 1, 2].map(|axis| axis + 3 * usize::from(negative[axis]));
        Self {
            origin: [
                Vec4::splat(origin.x),
                Vec4::splat(origin.y),
                Vec4::splat(origin.z),
            ],
            inv_direction: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            entry,
            exit: entry.map(|plane| (plane + 3) % 6),
        }
    }

    /// The distances at which the ray enters each of `node`'s four children (clamped to 0),
    /// and as four bits which of them it enters at a distance in [0, `t_max`].
    #[inline(always)]
    pub fn enters(&self, node: &Node, t_max: f32) -> (Vec4, u32) {
        let distance = |plane: usize, axis: usize| {
            (node.planes[plane] - self.origin[axis]) * self.inv_direction[axis]
        };
        let near = distance(self.entry[0], 0)
            .max(distance(self.entry[1], 1))
            .max(distance(self.entry[2], 2))
            .max(Vec4::ZERO);
        let far = distance(self.exit[0], 0)
            .min(distance(self.exit[1], 1))
            .min(distance(self.exit[2], 2))
            * FAR_SCALE;
        (near, near.cmple(far.min(Vec4::splat(t_max))).bitmask())
    }
}
