use super::{Bounds, ShapeHit, SurfacePoint};
use crate::math::{Ray, Vec2, Vec3, gamma};
use crate::sampling::uniform_sphere;
use std::f32::consts::PI;

/// An analytic sphere; its normal points outward.
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    pub fn bounds(&self) -> Bounds {
        Bounds {
            min: self.center - Vec3::splat(self.radius),
            max: self.center + Vec3::splat(self.radius),
        }
    }

    /// Ray–sphere intersection in the numerically careful form of Haines et al., "Precision
    /// Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, 2019): the discriminant is
    /// computed from the distance of the centre to the ray, not from b² − 4ac.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let f = ray.origin - self.center;
        let b = -f.dot(ray.dir);
        let r2 = self.radius * self.radius;
        let perp = f + b * ray.dir;
        let disc = r2 - perp.length_squared();
        if disc < 0.0 {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = b + b.signum() * disc.sqrt();
        let (t0, t1) = if q == 0.0 {
            (0.0, 0.0)
        } else {
            let a = c / q;
            (a.min(q), a.max(q))
        };
        let t = if t0 > t_min && t0 < t_max {
            t0
        } else if t1 > t_min && t1 < t_max {
            t1
        } else {
            return None;
        };
        Some(ShapeHit { t, uv: Vec2::ZERO })
    }

    pub fn surface(&self, p: Vec3) -> SurfacePoint {
        // Re-projected onto the sphere: the error along the normal is then the rounding of
        // this expression, not the hit distance's.
        self.point_toward((p - self.center).normalize())
    }

    /// The point c + r·n for a computed unit `n`, with the bound of its distance from the
    /// sphere: n's length is 1 within a few roundings, and the product and the sum round
    /// once each; γ₈ of the terms covers them (pbrt-v4 §6.8.5 bounds re-projected points the
    /// same way).
    fn point_toward(&self, n: Vec3) -> SurfacePoint {
        let radial = self.radius * n;
        SurfacePoint {
            p: self.center + radial,
            n,
            error: gamma(8) * (self.center.abs() + radial.abs()),
        }
    }

    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    pub fn sample_area(&self, u: Vec2) -> SurfacePoint {
        self.point_toward(uniform_sphere(u))
    }
}
