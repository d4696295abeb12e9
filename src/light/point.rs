use super::{LightSample, PhotonEmission};
use crate::math::Vec2;
use crate::math::{Rgb, Vec3};
use crate::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};
use std::f32::consts::PI;

/// Isotropic point light of radiant intensity `intensity` (W/sr per channel).
#[derive(Clone, Copy, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Rgb,
}

impl PointLight {
    pub fn power(&self) -> Rgb {
        4.0 * PI * self.intensity
    }

    /// Uniform direction over the sphere: flux I / (1/4π) = 4π I, the whole power.
    pub fn emit(&self, u: Vec2) -> PhotonEmission {
        PhotonEmission {
            origin: self.position,
            dir: uniform_sphere(u),
            normal: Vec3::ZERO,
            flux: self.intensity / UNIFORM_SPHERE_PDF,
        }
    }

    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        Some(LightSample {
            wi: d / dist2.sqrt(),
            radiance: self.intensity / dist2,
            pdf: 1.0,
            point: self.position,
            normal: Vec3::ZERO,
            is_delta: true,
        })
    }
}
