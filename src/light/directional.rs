use super::{LightSample, PhotonEmission};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::uniform_disk_polar;
use std::f32::consts::PI;

/// Light arriving from one direction (the sun): `irradiance` (W/m² per channel) on a surface
/// facing it. Its power is that irradiance over the disk the scene's bounding sphere casts,
/// Φ = E·πr² (pbrt-v4's convention), so the bounding sphere is set when the scene is built.
#[derive(Clone, Copy, Debug)]
pub struct DirectionalLight {
    /// Unit direction the light travels in.
    pub direction: Vec3,
    pub irradiance: Rgb,
    pub scene_center: Vec3,
    pub scene_radius: f32,
}

impl DirectionalLight {
    pub fn new(direction: Vec3, irradiance: Rgb) -> Self {
        Self {
            direction: direction.normalize_or(-Vec3::Z),
            irradiance,
            scene_center: Vec3::ZERO,
            scene_radius: 0.0,
        }
    }

    pub fn power(&self) -> Rgb {
        self.irradiance * PI * self.scene_radius * self.scene_radius
    }

    /// A photon from a uniform point of the disk of radius r facing the light, one radius
    /// outside the scene's sphere: flux E / (1/πr²) = the whole power.
    pub fn emit(&self, u: Vec2) -> Option<PhotonEmission> {
        if self.scene_radius <= 0.0 {
            return None;
        }
        let f = Frame::from_normal(self.direction);
        let d = uniform_disk_polar(u, self.scene_radius);
        Some(PhotonEmission {
            origin: self.scene_center - self.direction * self.scene_radius + f.s * d.x + f.t * d.y,
            dir: self.direction,
            normal: Vec3::ZERO,
            flux: self.power(),
        })
    }

    /// The direction toward the light; the shadow ray ends outside the scene's sphere.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let wi = -self.direction;
        Some(LightSample {
            wi,
            radiance: self.irradiance,
            pdf: 1.0,
            point: p + wi * (2.0 * self.scene_radius + (p - self.scene_center).length()),
            normal: Vec3::ZERO,
            is_delta: true,
        })
    }
}
