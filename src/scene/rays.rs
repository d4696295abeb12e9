//! The scene's ray caster over its shapes, with the engine chosen at build ([`RayEngine`]):
//! every shape in our BVH, or the triangles in Embree and the analytic shapes (spheres, disks)
//! beside them. The shapes are stored in the order this module returns, so a primitive's
//! index is the same to both engines' answers.
//!
//! Every query takes an `accept` test that may refuse a hit the shape reports (a cut-out
//! surface's alpha test); traversal then goes on as if the shape were not there. Shapes
//! whose hits may be refused stay in our BVH under Embree too (Embree is told nothing of
//! them), so one rule serves both engines.

use crate::accel::{Bvh, RayEngine};
use crate::error::{Error, Result};
use crate::geometry::{Bounds, Shape, ShapeHit, ShearedRay, transposed, watertight_hit};
use crate::math::Ray;
use glam::Vec3A;

/// Shapes beside Embree up to this many are tested one by one rather than through a BVH of
/// their own: a sphere test is cheaper than a wide node.
#[cfg(feature = "embree")]
const BESIDE_LOOP_MAX: usize = 8;

pub(super) struct RayCaster {
    engine: RayEngine,
    /// All shapes, or with Embree only those beside it (`shapes[..first_triangle]`): the
    /// analytic ones and the triangles whose hits may be refused.
    bvh: Bvh,
    /// The shapes in the BVH, in its order, as the ray–triangle test reads them.
    packed: Vec<PackedShape>,
    #[cfg(feature = "embree")]
    triangles: Option<crate::accel::embree::TriangleBvh>,
    /// With Embree: shapes before this index are beside it, the rest are its triangles.
    #[cfg(feature = "embree")]
    first_triangle: usize,
    bounds: Bounds,
}

impl RayCaster {
    /// Build over `shapes`; `refusable[i]` says whether a query's `accept` test may refuse
    /// hits on shape `i`. Returns the caster and the order to store the shapes in: position
    /// `i` holds input shape `order[i]`.
    pub fn build(
        shapes: &[Shape],
        refusable: &[bool],
        engine: RayEngine,
    ) -> Result<(Self, Vec<u32>)> {
        let bounds: Vec<Bounds> = shapes.iter().map(Shape::bounds).collect();
        let total = bounds.iter().fold(Bounds::EMPTY, |a, b| a.union(*b));
        match engine.resolved() {
            RayEngine::Embree => Self::build_embree(shapes, refusable, &bounds, total),
            _ => {
                let (bvh, order) = Bvh::build(&bounds);
                let caster = Self {
                    engine: RayEngine::Bvh,
                    packed: order
                        .iter()
                        .map(|&i| PackedShape::new(&shapes[i as usize]))
                        .collect(),
                    bvh,
                    #[cfg(feature = "embree")]
                    triangles: None,
                    #[cfg(feature = "embree")]
                    first_triangle: shapes.len(),
                    bounds: total,
                };
                Ok((caster, order))
            }
        }
    }

    #[cfg(not(feature = "embree"))]
    fn build_embree(_: &[Shape], _: &[bool], _: &[Bounds], _: Bounds) -> Result<(Self, Vec<u32>)> {
        Err(Error::InvalidScene(
            "the Embree ray engine is not in this build (cargo feature `embree`)".into(),
        ))
    }

    #[cfg(feature = "embree")]
    fn build_embree(
        shapes: &[Shape],
        refusable: &[bool],
        bounds: &[Bounds],
        total: Bounds,
    ) -> Result<(Self, Vec<u32>)> {
        let to_embree = |i: usize| {
            matches!(shapes[i], Shape::Triangle(_)) && !refusable.get(i).copied().unwrap_or(false)
        };
        let beside: Vec<u32> = (0..shapes.len() as u32)
            .filter(|&i| !to_embree(i as usize))
            .collect();
        let beside_bounds: Vec<Bounds> = beside.iter().map(|&i| bounds[i as usize]).collect();
        let (bvh, beside_order) = Bvh::build(&beside_bounds);
        let mut order: Vec<u32> = beside_order.iter().map(|&k| beside[k as usize]).collect();
        let mut vertices = Vec::with_capacity(shapes.len() - beside.len());
        for (i, s) in shapes.iter().enumerate() {
            if let Shape::Triangle(t) = s
                && to_embree(i)
            {
                order.push(i as u32);
                vertices.push(t.vertices());
            }
        }
        let triangles = crate::accel::embree::TriangleBvh::build(&vertices)
            .map_err(|e| Error::InvalidScene(e.to_string()))?;
        let caster = Self {
            engine: RayEngine::Embree,
            packed: beside_order
                .iter()
                .map(|&k| PackedShape::new(&shapes[beside[k as usize] as usize]))
                .collect(),
            bvh,
            triangles: Some(triangles),
            first_triangle: beside.len(),
            bounds: total,
        };
        Ok((caster, order))
    }

    /// The engine in use (never `Best`).
    pub fn engine(&self) -> RayEngine {
        self.engine
    }

    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// Nearest accepted hit below `t_max`: the primitive's index and its hit.
    #[inline]
    pub fn closest_hit(
        &self,
        shapes: &[Shape],
        ray: &Ray,
        t_max: f32,
        accept: impl Fn(u32, &ShapeHit) -> bool,
    ) -> Option<(u32, ShapeHit)> {
        #[cfg(feature = "embree")]
        if let Some(triangles) = &self.triangles {
            let mut best = triangles
                .closest_hit(ray, t_max)
                .map(|(id, t, uv)| (self.first_triangle as u32 + id, ShapeHit { t, uv }));
            let limit = best.map_or(t_max, |b| b.1.t);
            if let Some(hit) = self.closest_beside(shapes, ray, limit, accept) {
                best = Some(hit);
            }
            return best;
        }
        self.closest_in_bvh(shapes, ray, t_max, accept)
    }

    /// Whether anything is hit (and accepted) closer than `t_max`.
    #[inline]
    pub fn any_hit(
        &self,
        shapes: &[Shape],
        ray: &Ray,
        t_max: f32,
        accept: impl Fn(u32, &ShapeHit) -> bool,
    ) -> bool {
        #[cfg(feature = "embree")]
        if let Some(triangles) = &self.triangles {
            let beside = &shapes[..self.first_triangle];
            let blocked = if beside.len() <= BESIDE_LOOP_MAX {
                beside.iter().enumerate().any(|(i, s)| {
                    s.intersect(ray, 0.0, t_max)
                        .is_some_and(|h| accept(i as u32, &h))
                })
            } else {
                self.any_in_bvh(shapes, ray, t_max, accept)
            };
            return blocked || triangles.any_hit(ray, t_max);
        }
        self.any_in_bvh(shapes, ray, t_max, accept)
    }

    #[cfg(feature = "embree")]
    fn closest_beside(
        &self,
        shapes: &[Shape],
        ray: &Ray,
        t_max: f32,
        accept: impl Fn(u32, &ShapeHit) -> bool,
    ) -> Option<(u32, ShapeHit)> {
        let beside = &shapes[..self.first_triangle];
        if beside.len() > BESIDE_LOOP_MAX {
            return self.closest_in_bvh(shapes, ray, t_max, accept);
        }
        let mut best = None;
        let mut limit = t_max;
        for (i, s) in beside.iter().enumerate() {
            if let Some(h) = s.intersect(ray, 0.0, limit)
                && accept(i as u32, &h)
            {
                limit = h.t;
                best = Some((i as u32, h));
            }
        }
        best
    }

    fn closest_in_bvh(
        &self,
        shapes: &[Shape],
        ray: &Ray,
        t_max: f32,
        accept: impl Fn(u32, &ShapeHit) -> bool,
    ) -> Option<(u32, ShapeHit)> {
        let mut best = None;
        let sheared = ShearedRay::new(ray);
        let (prim, _) = self.bvh.closest_hit(ray, t_max, |id, t_max| {
            match self.packed[id as usize].intersect(shapes, id, ray, &sheared, t_max) {
                Some(h) if accept(id, &h) => {
                    best = Some(h);
                    h.t
                }
                _ => f32::INFINITY,
            }
        })?;
        best.map(|h| (prim, h))
    }

    fn any_in_bvh(
        &self,
        shapes: &[Shape],
        ray: &Ray,
        t_max: f32,
        accept: impl Fn(u32, &ShapeHit) -> bool,
    ) -> bool {
        let sheared = ShearedRay::new(ray);
        self.bvh.any_hit(ray, t_max, |id, t_max| {
            self.packed[id as usize]
                .intersect(shapes, id, ray, &sheared, t_max)
                .filter(|h| accept(id, h))
                .map_or(f32::INFINITY, |h| h.t)
        })
    }
}

/// A shape as the BVH's leaves test it: a triangle as its vertices by coordinate, tested by
/// the same function as [`crate::geometry::Triangle::intersect`] (so the answers are the same
/// to the bit); any other shape with a NaN first vertex, which sends the test to
/// [`Shape::intersect`].
#[derive(Clone, Copy, Debug)]
struct PackedShape {
    vertices: [Vec3A; 3],
}

impl PackedShape {
    fn new(shape: &Shape) -> Self {
        match shape {
            Shape::Triangle(t) => Self {
                vertices: transposed(t.vertices()),
            },
            Shape::Sphere(_) | Shape::Disk(_) => Self {
                vertices: [Vec3A::NAN; 3],
            },
        }
    }

    /// The hit of `ray` (`sheared` made from it) on shape `id` with `t` in (0, `t_max`).
    #[inline(always)]
    fn intersect(
        &self,
        shapes: &[Shape],
        id: u32,
        ray: &Ray,
        sheared: &ShearedRay,
        t_max: f32,
    ) -> Option<ShapeHit> {
        if self.vertices[0].x.is_nan() {
            return shapes[id as usize].intersect(ray, 0.0, t_max);
        }
        watertight_hit(sheared, &self.vertices, 0.0, t_max)
    }
}
