use super::{BsdfSample, Lobes};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use std::f32::consts::FRAC_1_PI;

/// Ideal diffuse reflector, f = ρ/π, two-sided.
#[derive(Clone, Copy, Debug)]
pub struct Lambertian {
    pub albedo: Rgb,
}

impl Lambertian {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z > 0.0 && wi.z > 0.0 {
            self.albedo * FRAC_1_PI
        } else {
            Rgb::ZERO
        }
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z > 0.0 {
            cosine_hemisphere_pdf(wi.z)
        } else {
            0.0
        }
    }

    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(wi.z);
        (pdf > 0.0).then_some(BsdfSample {
            wi,
            // (ρ/π)·cos θ / (cos θ/π) = ρ
            weight: self.albedo,
            pdf,
            lobe: Lobes::DIFFUSE_REFLECTION,
            eta: 1.0,
        })
    }
}
