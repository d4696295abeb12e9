//! The ray–node test of the wide BVH's traversal: which of a compressed node's eight child
//! boxes a ray enters before its far distance.
//!
//! The boxes are quantised to 8 bits per plane over the node's own grid (Ylitie, Karras and
//! Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", 2017),
//! and each is tested by the slab method (Kay and Kajiya 1986; Williams et al. 2005) with the
//! ray moved into the node's grid rather than the planes out of it. The far distance is scaled
//! by 1 + 2γ₃ so that rounding can only make the test conservative (Ize, "Robust BVH Ray
//! Traversal", JCGT 2013); the exact primitive tests decide.
//!
//! This is ours rather than `obvhs`' `CwBvhNode::intersect_ray` because that test depends on
//! the scene's unit: it skips every box a ray leaves within 10⁻⁴ scene units of its origin,
//! so a Cornell box built 5.5 cm wide rendered 1% dark and one 5.5 mm wide 11% dark, and it
//! replaces direction components below 1.2 · 10⁻⁷ by that, which bends rays aimed along a
//! face. Here a box counts from distance 0, and only components below 10⁻²⁰ are replaced.

use glam::{Vec3A, Vec4};
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};

/// A direction component smaller than this in magnitude is taken as this, with its sign (+
/// for ±0): the ray then moves at most 10⁻²⁰ of its length off its line, and the products of
/// the slab test stay finite (no 0 · ∞) for any coordinate below 10¹⁵.
const TINY_COMPONENT: f32 = 1e-20;

/// 1 + 2γ₃ with γₙ = nε / (1 − nε) and ε = 2⁻²⁴ (pbrt-v4, §6.8.2): a bound on the relative
/// rounding error of a slab distance computed in three rounded operations.
const FAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// A ray as the node test reads it.
pub(super) struct NodeRay {
    origin: Vec3A,
    /// The direction the node test and the traversal order use (tiny components replaced).
    direction: Vec3A,
    inv_direction: Vec3A,
    /// Per axis, whether the direction is negative: the ray then enters a slab by its upper
    /// plane.
    negative: [bool; 3],
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
        Self {
            origin,
            direction,
            inv_direction: direction.recip(),
            negative: [direction.x < 0.0, direction.y < 0.0, direction.z < 0.0],
        }
    }

    /// The direction whose octant orders the traversal; its signs are the ones the slab test
    /// uses.
    pub fn direction(&self) -> Vec3A {
        self.direction
    }
}

/// Children `4 * HALF` to `4 * HALF + 3`'s planes.
#[inline(always)]
fn four<const HALF: usize>(planes: &[u8; 8]) -> Vec4 {
    Vec4::new(
        f32::from(planes[4 * HALF]),
        f32::from(planes[4 * HALF + 1]),
        f32::from(planes[4 * HALF + 2]),
        f32::from(planes[4 * HALF + 3]),
    )
}

/// One axis of a node as a ray crosses it: the planes it enters and leaves the children's
/// slabs by, and the distance map from grid steps, `t = plane · step + offset`.
struct Slabs<'a> {
    entry: &'a [u8; 8],
    exit: &'a [u8; 8],
    step: Vec4,
    offset: Vec4,
}

impl<'a> Slabs<'a> {
    #[inline(always)]
    fn new(lower: &'a [u8; 8], upper: &'a [u8; 8], negative: bool, step: f32, offset: f32) -> Self {
        let (entry, exit) = if negative {
            (upper, lower)
        } else {
            (lower, upper)
        };
        Self {
            entry,
            exit,
            step: Vec4::splat(step),
            offset: Vec4::splat(offset),
        }
    }

    #[inline(always)]
    fn entry<const HALF: usize>(&self) -> Vec4 {
        four::<HALF>(self.entry) * self.step + self.offset
    }

    #[inline(always)]
    fn exit<const HALF: usize>(&self) -> Vec4 {
        four::<HALF>(self.exit) * self.step + self.offset
    }
}

/// Which of children `4 * HALF` to `4 * HALF + 3` the ray enters at a distance in
/// [0, `t_max`], as four bits.
#[inline(always)]
fn entered<const HALF: usize>(slabs: &[Slabs; 3], t_max: f32) -> u32 {
    let [x, y, z] = slabs;
    let near = x
        .entry::<HALF>()
        .max(y.entry::<HALF>())
        .max(z.entry::<HALF>())
        .max(Vec4::ZERO);
    let far = x.exit::<HALF>().min(y.exit::<HALF>()).min(z.exit::<HALF>()) * FAR_SCALE;
    near.cmple(far.min(Vec4::splat(t_max))).bitmask()
}

/// The node's hit mask, in `obvhs`' encoding (its traversal reads it): for each child box
/// the ray enters at a distance in [0, `t_max`], the child's bits put in place by
/// [`CwBvhNode::get_child_and_index_bits`] for the ray's octant `oct_inv4`.
#[inline(always)]
pub(super) fn hit_children(node: &CwBvhNode, ray: &NodeRay, t_max: f32, oct_inv4: u32) -> u32 {
    // Distance per grid step along each axis, and distance to the grid's origin planes.
    let step = node.compute_extent() * ray.inv_direction;
    let offset = (Vec3A::from(node.p) - ray.origin) * ray.inv_direction;
    let slabs = [
        Slabs::new(
            &node.child_min_x,
            &node.child_max_x,
            ray.negative[0],
            step.x,
            offset.x,
        ),
        Slabs::new(
            &node.child_min_y,
            &node.child_max_y,
            ray.negative[1],
            step.y,
            offset.y,
        ),
        Slabs::new(
            &node.child_min_z,
            &node.child_max_z,
            ray.negative[2],
            step.z,
            offset.z,
        ),
    ];
    let mut entered = entered::<0>(&slabs, t_max) | entered::<1>(&slabs, t_max) << 4;
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut hit_mask = 0;
    while entered != 0 {
        let child = entered.trailing_zeros() as usize;
        entered &= entered - 1;
        hit_mask |= extract_byte64(child_bits8, child) << extract_byte64(bit_index8, child);
    }
    hit_mask
}
