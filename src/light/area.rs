use super::{LightSample, PhotonEmission};
use crate::geometry::Shape;
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::{Distribution1D, cosine_hemisphere};
use std::f32::consts::PI;

/// A diffuse (Lambertian) emitter made of one or more shapes with constant radiance.
/// One-sided lights emit on the side their normals face.
#[derive(Clone, Debug)]
pub struct AreaLight {
    pub shapes: Vec<Shape>,
    pub radiance: Rgb,
    pub two_sided: bool,
    area: f32,
    by_area: Distribution1D,
}

impl AreaLight {
    /// `None` if the shapes have no area.
    pub fn new(shapes: Vec<Shape>, radiance: Rgb, two_sided: bool) -> Option<Self> {
        let areas: Vec<f64> = shapes.iter().map(|s| f64::from(s.area())).collect();
        let by_area = Distribution1D::new(&areas)?;
        Some(Self {
            area: by_area.total() as f32,
            shapes,
            radiance,
            two_sided,
            by_area,
        })
    }

    pub fn area(&self) -> f32 {
        self.area
    }

    /// Φ = π A L for one side.
    pub fn power(&self) -> Rgb {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance * (PI * self.area * sides)
    }

    /// Radiance leaving a point with normal `n` in direction `w`.
    pub fn emitted(&self, n: Vec3, w: Vec3) -> Rgb {
        if self.two_sided || n.dot(w) > 0.0 {
            self.radiance
        } else {
            Rgb::ZERO
        }
    }

    /// Uniform point on the area (density 1/A), cosine-weighted direction (density cos θ/π) on
    /// the emitting side, or on a side chosen at random for two-sided lights: every photon
    /// carries flux L·cos θ / (cos θ/π · 1/A) = π A L, times two for two-sided lights.
    pub fn emit(&self, u_pick: f32, u_pos: Vec2, u_dir: Vec2) -> Option<PhotonEmission> {
        let (i, rest) = self.by_area.sample(u_pick);
        let s = self.shapes[i].sample_area(u_pos);
        let (normal, sides) = if self.two_sided {
            (if rest < 0.5 { s.n } else { -s.n }, 2.0)
        } else {
            (s.n, 1.0)
        };
        let local = cosine_hemisphere(u_dir);
        if local.z <= 0.0 {
            return None;
        }
        Some(PhotonEmission {
            origin: s.p,
            dir: Frame::from_normal(normal).to_world(local),
            normal: s.n,
            flux: self.radiance * (std::f32::consts::PI * self.area * sides),
        })
    }

    /// Uniform point on the light's area, then converted to a solid-angle density at `p`.
    pub fn sample_li(&self, p: Vec3, u_pick: f32, u: Vec2) -> Option<LightSample> {
        let (i, _) = self.by_area.sample(u_pick);
        let s = self.shapes[i].sample_area(u);
        let d = s.p - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let wi = d / dist2.sqrt();
        let radiance = self.emitted(s.n, -wi);
        if radiance == Rgb::ZERO {
            return None;
        }
        let pdf = self.pdf_li(p, s.p, s.n);
        (pdf > 0.0 && pdf.is_finite()).then_some(LightSample {
            wi,
            radiance,
            pdf,
            point: s.p,
            normal: s.n,
            is_delta: false,
        })
    }

    /// Solid-angle density with which [`AreaLight::sample_li`] picks the point `q` (normal `n`)
    /// as seen from `p`: the area density 1/A converted by distance² / |cos θ_light|.
    pub fn pdf_li(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        let d = q - p;
        let dist2 = d.length_squared();
        let cos = (n.dot(d) / dist2.sqrt()).abs();
        if cos == 0.0 {
            return 0.0;
        }
        dist2 / (cos * self.area)
    }
}
