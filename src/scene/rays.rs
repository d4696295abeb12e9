//! The scene's ray caster over its shapes, with the engine chosen at build ([`RayEngine`]):
//! every shape in our BVH, or the triangles in Embree and the analytic shapes (spheres, disks)
//! beside them. The shapes are stored in the order this module returns, so a primitive's
//! index is the same to both engines' answers.

use crate::accel::{Bvh, RayEngine};
use crate::error::{Error, Result};
use crate::geometry::{Bounds, Shape, ShapeHit};
use crate::math::Ray;

/// Analytic shapes up to this many are tested one by one rather than through a BVH of their
/// own: a sphere test is cheaper than a wide node.
#[cfg(feature = "embree")]
const ANALYTIC_LOOP_MAX: usize = 8;

pub(super) struct RayCaster {
    engine: RayEngine,
    /// All shapes, or with Embree only the analytic ones (`shapes[..first_triangle]`).
    bvh: Bvh,
    #[cfg(feature = "embree")]
    triangles: Option<crate::accel::embree::TriangleBvh>,
    /// With Embree: shapes before this index are analytic, the rest are triangles.
    #[cfg(feature = "embree")]
    first_triangle: usize,
    bounds: Bounds,
}

impl RayCaster {
    /// Build over `shapes`. Returns the caster and the order to store the shapes in: position
    /// `i` holds input shape `order[i]`.
    pub fn build(shapes: &[Shape], engine: RayEngine) -> Result<(Self, Vec<u32>)> {
        let bounds: Vec<Bounds> = shapes.iter().map(Shape::bounds).collect();
        let total = bounds.iter().fold(Bounds::EMPTY, |a, b| a.union(*b));
        match engine.resolved() {
            RayEngine::Embree => Self::build_embree(shapes, &bounds, total),
            _ => {
                let (bvh, order) = Bvh::build(&bounds);
                let caster = Self {
                    engine: RayEngine::Bvh,
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
    fn build_embree(_: &[Shape], _: &[Bounds], _: Bounds) -> Result<(Self, Vec<u32>)> {
        Err(Error::InvalidScene(
            "the Embree ray engine is not in this build (cargo feature `embree`)".into(),
        ))
    }

    #[cfg(feature = "embree")]
    fn build_embree(
        shapes: &[Shape],
        bounds: &[Bounds],
        total: Bounds,
    ) -> Result<(Self, Vec<u32>)> {
        let is_triangle = |s: &Shape| matches!(s, Shape::Triangle(_));
        let analytic: Vec<u32> = (0..shapes.len() as u32)
            .filter(|&i| !is_triangle(&shapes[i as usize]))
            .collect();
        let analytic_bounds: Vec<Bounds> = analytic.iter().map(|&i| bounds[i as usize]).collect();
        let (bvh, analytic_order) = Bvh::build(&analytic_bounds);
        let mut order: Vec<u32> = analytic_order
            .iter()
            .map(|&k| analytic[k as usize])
            .collect();
        let mut vertices = Vec::with_capacity(shapes.len() - analytic.len());
        for (i, s) in shapes.iter().enumerate() {
            if let Shape::Triangle(t) = s {
                order.push(i as u32);
                vertices.push(t.vertices());
            }
        }
        let triangles = crate::accel::embree::TriangleBvh::build(&vertices)
            .map_err(|e| Error::InvalidScene(e.to_string()))?;
        let caster = Self {
            engine: RayEngine::Embree,
            bvh,
            triangles: Some(triangles),
            first_triangle: analytic.len(),
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

    /// Nearest hit below `t_max`: the primitive's index and its hit.
    #[inline]
    pub fn closest_hit(&self, shapes: &[Shape], ray: &Ray, t_max: f32) -> Option<(u32, ShapeHit)> {
        #[cfg(feature = "embree")]
        if let Some(triangles) = &self.triangles {
            let mut best = triangles
                .closest_hit(ray, t_max)
                .map(|(id, t, uv)| (self.first_triangle as u32 + id, ShapeHit { t, uv }));
            let limit = best.map_or(t_max, |b| b.1.t);
            if let Some(hit) = self.closest_analytic(shapes, ray, limit) {
                best = Some(hit);
            }
            return best;
        }
        self.closest_in_bvh(shapes, ray, t_max)
    }

    /// Whether anything is hit closer than `t_max`.
    #[inline]
    pub fn any_hit(&self, shapes: &[Shape], ray: &Ray, t_max: f32) -> bool {
        #[cfg(feature = "embree")]
        if let Some(triangles) = &self.triangles {
            let analytic = &shapes[..self.first_triangle];
            let blocked = if analytic.len() <= ANALYTIC_LOOP_MAX {
                analytic
                    .iter()
                    .any(|s| s.intersect(ray, 0.0, t_max).is_some())
            } else {
                self.any_in_bvh(shapes, ray, t_max)
            };
            return blocked || triangles.any_hit(ray, t_max);
        }
        self.any_in_bvh(shapes, ray, t_max)
    }

    #[cfg(feature = "embree")]
    fn closest_analytic(&self, shapes: &[Shape], ray: &Ray, t_max: f32) -> Option<(u32, ShapeHit)> {
        let analytic = &shapes[..self.first_triangle];
        if analytic.len() > ANALYTIC_LOOP_MAX {
            return self.closest_in_bvh(shapes, ray, t_max);
        }
        let mut best = None;
        let mut limit = t_max;
        for (i, s) in analytic.iter().enumerate() {
            if let Some(h) = s.intersect(ray, 0.0, limit) {
                limit = h.t;
                best = Some((i as u32, h));
            }
        }
        best
    }

    fn closest_in_bvh(&self, shapes: &[Shape], ray: &Ray, t_max: f32) -> Option<(u32, ShapeHit)> {
        let mut best = None;
        let (prim, _) = self.bvh.closest_hit(ray, t_max, |id, t_max| {
            match shapes[id as usize].intersect(ray, 0.0, t_max) {
                Some(h) => {
                    best = Some(h);
                    h.t
                }
                None => f32::INFINITY,
            }
        })?;
        best.map(|h| (prim, h))
    }

    fn any_in_bvh(&self, shapes: &[Shape], ray: &Ray, t_max: f32) -> bool {
        self.bvh.any_hit(ray, t_max, |id, t_max| {
            shapes[id as usize]
                .intersect(ray, 0.0, t_max)
                .map_or(f32::INFINITY, |h| h.t)
        })
    }
}
