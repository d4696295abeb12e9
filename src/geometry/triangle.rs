use super::{Bounds, ShapeHit, SurfacePoint};
use crate::math::{Ray, Vec2, Vec3};
use crate::sampling::uniform_triangle;

/// A triangle stored as one vertex and two edges, ready for Möller–Trumbore.
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    pub p0: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
}

impl Triangle {
    /// Barycentric coordinates (b1, b2) of a point of the triangle's plane: p = p0 + b1 e1 + b2 e2.
    pub fn barycentrics(&self, p: Vec3) -> crate::math::Vec2 {
        let d = p - self.p0;
        let (d11, d12, d22) = (
            self.e1.dot(self.e1),
            self.e1.dot(self.e2),
            self.e2.dot(self.e2),
        );
        let (d1, d2) = (d.dot(self.e1), d.dot(self.e2));
        let det = d11 * d22 - d12 * d12;
        if det == 0.0 {
            return crate::math::Vec2::ZERO;
        }
        crate::math::Vec2::new((d22 * d1 - d12 * d2) / det, (d11 * d2 - d12 * d1) / det)
    }

    pub fn new(p0: Vec3, p1: Vec3, p2: Vec3) -> Self {
        Self {
            p0,
            e1: p1 - p0,
            e2: p2 - p0,
        }
    }

    pub fn vertices(&self) -> [Vec3; 3] {
        [self.p0, self.p0 + self.e1, self.p0 + self.e2]
    }

    pub fn bounds(&self) -> Bounds {
        let [a, b, c] = self.vertices();
        Bounds {
            min: a.min(b).min(c),
            max: a.max(b).max(c),
        }
    }

    /// Möller & Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection" (1997).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let pvec = ray.dir.cross(self.e2);
        let det = self.e1.dot(pvec);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv_det = 1.0 / det;
        let tvec = ray.origin - self.p0;
        let b1 = tvec.dot(pvec) * inv_det;
        if !(0.0..=1.0).contains(&b1) {
            return None;
        }
        let qvec = tvec.cross(self.e1);
        let b2 = ray.dir.dot(qvec) * inv_det;
        if b2 < 0.0 || b1 + b2 > 1.0 {
            return None;
        }
        let t = self.e2.dot(qvec) * inv_det;
        (t > t_min && t < t_max).then_some(ShapeHit {
            t,
            uv: Vec2::new(b1, b2),
        })
    }

    /// Geometric normal following the winding (p0, p1, p2), counter-clockwise seen from the front.
    pub fn normal(&self) -> Vec3 {
        self.e1.cross(self.e2).normalize()
    }

    pub fn surface(&self, hit: &ShapeHit) -> SurfacePoint {
        SurfacePoint {
            // From barycentrics rather than the ray: the point then lies on the triangle's plane.
            p: self.p0 + hit.uv.x * self.e1 + hit.uv.y * self.e2,
            n: self.normal(),
        }
    }

    /// Half the edges' cross product's length, in f64: its squared components overflow f32
    /// for edges past about 1e10, well inside the coordinates a scene may have.
    pub fn area(&self) -> f32 {
        let (a, b) = (self.e1.as_dvec3(), self.e2.as_dvec3());
        (0.5 * a.cross(b).length()) as f32
    }

    pub fn sample_area(&self, u: Vec2) -> SurfacePoint {
        let b = uniform_triangle(u);
        SurfacePoint {
            p: self.p0 + b.y * self.e1 + b.z * self.e2,
            n: self.normal(),
        }
    }
}
