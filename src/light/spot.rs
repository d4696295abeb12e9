use super::{LightSample, PhotonEmission};
use crate::math::{Frame, Vec2};
use crate::math::{Rgb, Vec3};
use crate::sampling::{uniform_cone, uniform_cone_pdf};
use crate::spectrum::{Lambda, Spectrum};
use std::f32::consts::PI;

/// Spot light: intensity `intensity` (W/sr) along `direction`, full inside the cone of
/// half-angle `acos(cos_falloff_start)`, falling smoothly to zero at `acos(cos_cutoff)`.
#[derive(Clone, Copy, Debug)]
pub struct SpotLight {
    pub position: Vec3,
    pub direction: Vec3,
    pub intensity: Spectrum,
    pub cos_cutoff: f32,
    pub cos_falloff_start: f32,
}

fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    if edge0 == edge1 {
        return if x >= edge1 { 1.0 } else { 0.0 };
    }
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl SpotLight {
    /// Build from the cone's half-angle and the width of its soft edge, both in degrees.
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Spectrum,
        half_angle_deg: f32,
        falloff_deg: f32,
    ) -> Self {
        let cutoff = half_angle_deg.to_radians();
        let start = (half_angle_deg - falloff_deg).max(0.0).to_radians();
        Self {
            position,
            direction: direction.normalize(),
            intensity,
            cos_cutoff: cutoff.cos(),
            cos_falloff_start: start.cos(),
        }
    }

    /// Relative intensity in direction `w` (unit, pointing away from the light).
    pub fn falloff(&self, w: Vec3) -> f32 {
        smoothstep(
            self.cos_cutoff,
            self.cos_falloff_start,
            w.dot(self.direction),
        )
    }

    /// Φ = 2π I [(1 − cos θ_start) + (cos θ_start − cos θ_cutoff)/2]: the smoothstep ramp in
    /// cos θ integrates to exactly half its width, since smoothstep(x) + smoothstep(1−x) = 1.
    pub fn power(&self) -> Rgb {
        self.intensity.rgb()
            * (2.0
                * PI
                * ((1.0 - self.cos_falloff_start)
                    + 0.5 * (self.cos_falloff_start - self.cos_cutoff)))
    }

    /// Uniform direction inside the cutoff cone (the original project's cone sampling, with
    /// spread s = (1 − cos θ_cutoff)/2), flux I(ω)/pdf so the smooth edge is weighted in.
    pub fn emit(&self, u: Vec2, lambda: &Lambda) -> Option<PhotonEmission> {
        let local = uniform_cone(u, self.cos_cutoff);
        let dir = Frame::from_normal(self.direction).to_world(local);
        let k = self.falloff(dir);
        (k > 0.0).then(|| PhotonEmission {
            origin: self.position,
            dir,
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            flux: lambda.spectrum(&self.intensity) * (k / uniform_cone_pdf(self.cos_cutoff)),
        })
    }

    /// Density with which [`SpotLight::emit`] sends a photon in direction `w`: uniform
    /// in the cone.
    pub fn pdf_emit(&self, w: Vec3) -> f32 {
        if w.dot(self.direction) >= self.cos_cutoff {
            uniform_cone_pdf(self.cos_cutoff)
        } else {
            0.0
        }
    }

    pub fn sample_li(&self, p: Vec3, lambda: &Lambda) -> Option<LightSample> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let wi = d / dist2.sqrt();
        let k = self.falloff(-wi);
        (k > 0.0).then_some(LightSample {
            wi,
            radiance: lambda.spectrum(&self.intensity) * (k / dist2),
            pdf: 1.0,
            point: self.position,
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            is_delta: true,
        })
    }
}
