use super::{LightSample, PhotonEmission};
use crate::math::Vec2;
use crate::math::{Rgb, Vec3};
use crate::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};
use crate::spectrum::{Lambda, Spectrum};
use std::f32::consts::PI;

/// Isotropic point light of radiant intensity `intensity` (W/sr; its RGB colour per channel).
#[derive(Clone, Copy, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Spectrum,
}

impl PointLight {
    pub fn power(&self) -> Rgb {
        4.0 * PI * self.intensity.rgb()
    }

    /// Uniform direction over the sphere: flux I / (1/4π) = 4π I, the whole power.
    pub fn emit(&self, u: Vec2, lambda: &Lambda) -> PhotonEmission {
        PhotonEmission {
            origin: self.position,
            dir: uniform_sphere(u),
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            flux: lambda.spectrum(&self.intensity) / UNIFORM_SPHERE_PDF,
        }
    }

    pub fn sample_li(&self, p: Vec3, lambda: &Lambda) -> Option<LightSample> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        Some(LightSample {
            wi: d / dist2.sqrt(),
            radiance: lambda.spectrum(&self.intensity) / dist2,
            pdf: 1.0,
            point: self.position,
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            is_delta: true,
        })
    }
}
