//! Shapes the renderer intersects: triangles, analytic spheres and disks, and the surface
//! records they produce. Quads and boxes become triangles when a scene is built.

mod disk;
mod sphere;
mod triangle;

pub use disk::Disk;
pub use sphere::Sphere;
pub use triangle::Triangle;

use crate::math::{Ray, Vec2, Vec3};

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

    pub fn area(&self) -> f32 {
        match self {
            Shape::Triangle(s) => s.area(),
            Shape::Sphere(s) => s.area(),
            Shape::Disk(s) => s.area(),
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
