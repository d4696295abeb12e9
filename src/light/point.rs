use super::LightSample;
use crate::math::{Rgb, Vec3};
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
