use super::{Bounds, ShapeHit, SurfacePoint};
use crate::math::{Frame, Ray, Vec2, Vec3, gamma};
use crate::sampling::uniform_disk_polar;
use std::f32::consts::PI;

/// A flat disk; `normal` is its front side (the side a one-sided emitter lights).
#[derive(Clone, Copy, Debug)]
pub struct Disk {
    pub center: Vec3,
    pub normal: Vec3,
    pub radius: f32,
}

impl Disk {
    pub fn bounds(&self) -> Bounds {
        // Extent of a disk along axis i is r·sqrt(1 − n_i²).
        let e = self.radius
            * (Vec3::ONE - self.normal * self.normal)
                .max(Vec3::ZERO)
                .sqrt();
        Bounds {
            min: self.center - e,
            max: self.center + e,
        }
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let denom = self.normal.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        let t = (self.center - ray.origin).dot(self.normal) / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let d = ray.at(t) - self.center;
        (d.length_squared() <= self.radius * self.radius).then_some(ShapeHit { t, uv: Vec2::ZERO })
    }

    pub fn surface(&self, p: Vec3) -> SurfacePoint {
        // Projected onto the plane: the error along the normal is then the rounding of the
        // projection (a difference, a dot product, a product and a difference: γ₇ of the
        // terms), not the hit distance's.
        let projected = p - (p - self.center).dot(self.normal) * self.normal;
        SurfacePoint {
            p: projected,
            n: self.normal,
            error: gamma(7) * (p.abs() + self.center.abs()),
        }
    }

    pub fn area(&self) -> f32 {
        PI * self.radius * self.radius
    }

    pub fn sample_area(&self, u: Vec2) -> SurfacePoint {
        let d = uniform_disk_polar(u, self.radius);
        let f = Frame::from_normal(self.normal);
        SurfacePoint {
            p: self.center + f.s * d.x + f.t * d.y,
            n: self.normal,
            // The frame is orthogonal to the normal within a few roundings, each scaled by
            // at most the radius; the products and sums round once each.
            error: gamma(7) * (self.center.abs() + Vec3::splat(self.radius)),
        }
    }
}
