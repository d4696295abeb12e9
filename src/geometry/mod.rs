//! Shapes the renderer intersects: triangles, analytic spheres and disks, and the surface
//! records they produce. Quads and boxes become triangles when a scene is built.

mod disk;
mod sphere;
mod triangle;

pub use disk::Disk;
pub use sphere::Sphere;
pub use triangle::{ShearedRay, Triangle, transposed, watertight_hit};

use crate::math::{Ray, Vec2, Vec3};
use glam::Affine3A;

/// The scale factor of a similarity transform, or an error if `m` shears or scales unevenly.
fn uniform_scale(m: &Affine3A) -> Result<f32, &'static str> {
    let c = [m.matrix3.x_axis, m.matrix3.y_axis, m.matrix3.z_axis].map(Vec3::from);
    let s = c[0].length();
    let tol = 1e-4 * s;
    let similar = (c[1].length() - s).abs() < tol
        && (c[2].length() - s).abs() < tol
        && c[0].dot(c[1]).abs() < tol * s
        && c[0].dot(c[2]).abs() < tol * s
        && c[1].dot(c[2]).abs() < tol * s;
    if s > 0.0 && s.is_finite() && similar {
        Ok(s)
    } else {
        Err("spheres and disks accept only rotation, translation and uniform scale")
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn union(self, o: Self) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }
}

/// Where a ray met a shape: distance and the shape's own surface parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    pub t: f32,
    /// Barycentrics (b1, b2) for triangles; unused elsewhere.
    pub uv: Vec2,
}

/// The local geometry at a point on a shape.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    pub p: Vec3,
    /// Geometric normal: the shape's outward (or front-face) normal, unit length.
    pub n: Vec3,
    /// A bound on each coordinate's distance from the true surface, for the origins of rays
    /// leaving it ([`crate::math::offset_origin`]).
    pub error: Vec3,
}

/// The closed set of shapes (pbrt-v4 style: an enum with exhaustive matches).
#[derive(Clone, Copy, Debug)]
pub enum Shape {
    Triangle(Triangle),
    Sphere(Sphere),
    Disk(Disk),
}

impl Shape {
    pub fn bounds(&self) -> Bounds {
        match self {
            Shape::Triangle(s) => s.bounds(),
            Shape::Sphere(s) => s.bounds(),
            Shape::Disk(s) => s.bounds(),
        }
    }

    /// Nearest intersection with `t` in (`t_min`, `t_max`).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        match self {
            Shape::Triangle(s) => s.intersect(ray, t_min, t_max),
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
            Shape::Disk(s) => s.intersect(ray, t_min, t_max),
        }
    }

    /// Surface point and geometric normal for a hit found by [`Shape::intersect`].
    pub fn surface(&self, ray: &Ray, hit: &ShapeHit) -> SurfacePoint {
        match self {
            Shape::Triangle(s) => s.surface(hit),
            Shape::Sphere(s) => s.surface(ray.at(hit.t)),
            Shape::Disk(s) => s.surface(ray.at(hit.t)),
        }
    }

    /// The shape's own texture parametrisation at a hit: barycentrics (b1, b2) on triangles,
    /// (φ / 2π, θ / π) about +z on spheres, polar (r / R, φ / 2π) on disks.
    pub fn uv(&self, hit: &ShapeHit, p: Vec3) -> Vec2 {
        use std::f32::consts::{PI, TAU};
        match self {
            Shape::Triangle(_) => hit.uv,
            Shape::Sphere(s) => {
                let d = (p - s.center) / s.radius;
                let phi = d.y.atan2(d.x).rem_euclid(TAU);
                Vec2::new(phi / TAU, d.z.clamp(-1.0, 1.0).acos() / PI)
            }
            Shape::Disk(d) => {
                let f = crate::math::Frame::from_normal(d.normal);
                let q = p - d.center;
                let (x, y) = (q.dot(f.s), q.dot(f.t));
                Vec2::new(
                    (x * x + y * y).sqrt() / d.radius,
                    y.atan2(x).rem_euclid(TAU) / TAU,
                )
            }
        }
    }

    pub fn area(&self) -> f32 {
        match self {
            Shape::Triangle(s) => s.area(),
            Shape::Sphere(s) => s.area(),
            Shape::Disk(s) => s.area(),
        }
    }

    /// The shape under an object-to-world transform. Spheres and disks stay analytic, so they
    /// accept only similarity transforms (rotation, translation, uniform scale); anything else
    /// is refused with the reason.
    pub fn transformed(&self, m: &Affine3A) -> Result<Shape, &'static str> {
        match self {
            Shape::Triangle(t) => {
                let [a, b, c] = t.vertices().map(|p| m.transform_point3(p));
                Ok(Shape::Triangle(Triangle::new(a, b, c)))
            }
            Shape::Sphere(s) => Ok(Shape::Sphere(Sphere {
                center: m.transform_point3(s.center),
                radius: s.radius * uniform_scale(m)?,
            })),
            Shape::Disk(d) => Ok(Shape::Disk(Disk {
                center: m.transform_point3(d.center),
                normal: m.transform_vector3(d.normal).normalize(),
                radius: d.radius * uniform_scale(m)?,
            })),
        }
    }

    /// A point uniformly distributed by area on the shape (density 1 / area).
    pub fn sample_area(&self, u: Vec2) -> SurfacePoint {
        match self {
            Shape::Triangle(s) => s.sample_area(u),
            Shape::Sphere(s) => s.sample_area(u),
            Shape::Disk(s) => s.sample_area(u),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn similarity_transforms_keep_spheres_and_disks_analytic() {
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::splat(2.0),
            Quat::from_rotation_y(0.7),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let s = Shape::Sphere(Sphere {
            center: Vec3::X,
            radius: 0.5,
        });
        match s.transformed(&m) {
            Ok(Shape::Sphere(t)) => {
                assert!((t.radius - 1.0).abs() < 1e-6);
                assert!((t.center - m.transform_point3(Vec3::X)).length() < 1e-6);
            }
            other => panic!("{other:?}"),
        }
        let d = Shape::Disk(Disk {
            center: Vec3::ZERO,
            normal: Vec3::Z,
            radius: 1.0,
        });
        let Ok(Shape::Disk(t)) = d.transformed(&m) else {
            panic!("disk")
        };
        assert!((t.area() - 4.0 * d.area()).abs() < 1e-4);
        assert!((t.normal - Quat::from_rotation_y(0.7) * Vec3::Z).length() < 1e-5);
        let shear = Affine3A::from_scale(Vec3::new(1.0, 2.0, 1.0));
        assert!(s.transformed(&shear).is_err());
        // Triangles accept any affine map.
        let tri = Shape::Triangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y));
        assert!((tri.transformed(&shear).expect("affine").area() - 1.0).abs() < 1e-6);
    }
}
