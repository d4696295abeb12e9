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
use crate::geometry::{Bounds, Shape, ShapeHit};
use crate::math::{Ray, Vec2};
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
        let origin = Vec3A::from(ray.origin);
        let dir = Vec3A::from(ray.dir);
        let (prim, _) = self.bvh.closest_hit(ray, t_max, |id, t_max| {
            match self.packed[id as usize].intersect(shapes, id, ray, origin, dir, t_max) {
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
        let origin = Vec3A::from(ray.origin);
        let dir = Vec3A::from(ray.dir);
        self.bvh.any_hit(ray, t_max, |id, t_max| {
            self.packed[id as usize]
                .intersect(shapes, id, ray, origin, dir, t_max)
                .filter(|h| accept(id, h))
                .map_or(f32::INFINITY, |h| h.t)
        })
    }
}

/// A shape as the BVH's leaves test it: a triangle as its first vertex and edges in SIMD lanes
/// (the same Möller–Trumbore test as [`crate::geometry::Triangle::intersect`], operation for
/// operation, so the answers are the same to the bit); any other shape with zero edges, which
/// sends the test to [`Shape::intersect`].
#[derive(Clone, Copy, Debug)]
struct PackedShape {
    p0: Vec3A,
    e1: Vec3A,
    e2: Vec3A,
}

impl PackedShape {
    fn new(shape: &Shape) -> Self {
        match shape {
            Shape::Triangle(t) => Self {
                p0: Vec3A::from(t.p0),
                e1: Vec3A::from(t.e1),
                e2: Vec3A::from(t.e2),
            },
            Shape::Sphere(_) | Shape::Disk(_) => Self {
                p0: Vec3A::ZERO,
                e1: Vec3A::ZERO,
                e2: Vec3A::ZERO,
            },
        }
    }

    /// The hit of `ray` (`origin`, `dir` the same in SIMD lanes) on shape `id` with `t` in
    /// (0, `t_max`). A zero determinant (the ray in the triangle's plane, a degenerate
    /// triangle, a shape that is not a triangle) is left to [`Shape::intersect`].
    #[inline(always)]
    fn intersect(
        &self,
        shapes: &[Shape],
        id: u32,
        ray: &Ray,
        origin: Vec3A,
        dir: Vec3A,
        t_max: f32,
    ) -> Option<ShapeHit> {
        let pvec = dir.cross(self.e2);
        let det = self.e1.dot(pvec);
        if det == 0.0 || !det.is_finite() {
            return shapes[id as usize].intersect(ray, 0.0, t_max);
        }
        let inv_det = 1.0 / det;
        let tvec = origin - self.p0;
        let b1 = tvec.dot(pvec) * inv_det;
        if !(0.0..=1.0).contains(&b1) {
            return None;
        }
        let qvec = tvec.cross(self.e1);
        let b2 = dir.dot(qvec) * inv_det;
        if b2 < 0.0 || b1 + b2 > 1.0 {
            return None;
        }
        let t = self.e2.dot(qvec) * inv_det;
        (t > 0.0 && t < t_max).then_some(ShapeHit {
            t,
            uv: Vec2::new(b1, b2),
        })
    }
}
