//! Rough glass: GGX microfacet reflection and refraction (Walter et al. 2007, "Microfacet
//! Models for Refraction through Rough Surfaces"), sampled through the visible normals (Heitz
//! 2018) and choosing reflection or refraction by the Fresnel reflectance of the microfacet.
//! The local `z` axis is the outward normal; `ior` is inside over outside.

use super::microfacet::Ggx;
use super::{BsdfSample, Lobes, TransportMode, fresnel_dielectric};
use crate::math::{Rgb, Vec2, Vec3, reflect};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    pub ior: f32,
    pub ggx: Ggx,
    /// Multiplies transmitted light (1 for clear glass).
    pub transmittance: Rgb,
    /// The Beer–Lambert transmittance of the segment a path travelled inside the volume to
    /// reach this hit, scaling both lobes (1 unless set by
    /// [`super::Material::attenuated`]); the density is not scaled.
    pub segment: Rgb,
}

/// The microfacet normal (upper hemisphere) that takes `wo` to `wi`, with the relative index
/// η' = η_transmitted / η_incident of the crossing (1 for reflection); `None` if the pair is
/// degenerate or the microfacet faces away from either direction.
fn half_vector(wo: Vec3, wi: Vec3, ior: f32) -> Option<(Vec3, f32, bool)> {
    let (co, ci) = (wo.z, wi.z);
    if co == 0.0 || ci == 0.0 {
        return None;
    }
    let reflect = co * ci > 0.0;
    let etap = if reflect {
        1.0
    } else if co > 0.0 {
        ior
    } else {
        1.0 / ior
    };
    let m = wi * etap + wo;
    if m.length_squared() == 0.0 {
        return None;
    }
    let m = m.normalize();
    let m = if m.z < 0.0 { -m } else { m };
    // Both directions must see the front of the microfacet from their own side.
    if m.dot(wi) * ci < 0.0 || m.dot(wo) * co < 0.0 {
        return None;
    }
    Some((m, etap, reflect))
}

/// Refract `w` through a surface of normal `n` (upper side = outside) with relative index `ior`
/// (inside / outside); `None` under total internal reflection.
fn refract(w: Vec3, n: Vec3, ior: f32) -> Option<Vec3> {
    let (mut cos_i, mut eta, mut n) = (w.dot(n), ior, n);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-w / eta + (cos_i / eta - cos_t) * n)
}

impl RoughDielectric {
    /// Clear rough glass of index `ior` (inside over outside) whose refraction is scaled by
    /// `transmittance`.
    pub fn new(ior: f32, ggx: Ggx, transmittance: Rgb) -> Self {
        Self {
            ior,
            ggx,
            transmittance,
            segment: Rgb::ONE,
        }
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        let Some((m, etap, is_reflection)) = half_vector(wo, wi, self.ior) else {
            return Rgb::ZERO;
        };
        let f = fresnel_dielectric(wo.dot(m), self.ior);
        let dg = self.ggx.d(m) * self.ggx.g(wo, wi);
        if is_reflection {
            return self.segment * (dg * f / (4.0 * (wo.z * wi.z).abs()));
        }
        let denom = wi.dot(m) + wo.dot(m) / etap;
        let mut value =
            dg * (1.0 - f) * (wi.dot(m) * wo.dot(m) / (denom * denom * wi.z * wo.z)).abs();
        if mode == TransportMode::Radiance {
            value /= etap * etap;
        }
        self.transmittance * self.segment * value
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((m, etap, is_reflection)) = half_vector(wo, wi, self.ior) else {
            return 0.0;
        };
        let f = fresnel_dielectric(wo.dot(m), self.ior);
        let d_visible = self.ggx.visible_pdf(wo, m);
        if is_reflection {
            d_visible / (4.0 * wo.dot(m).abs()) * f
        } else {
            let denom = wi.dot(m) + wo.dot(m) / etap;
            d_visible * wi.dot(m).abs() / (denom * denom) * (1.0 - f)
        }
    }

    pub fn sample(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let m = self.ggx.sample_visible(wo, u);
        let f = fresnel_dielectric(wo.dot(m), self.ior);
        let (wi, lobe) = if u_lobe < f {
            (reflect(wo, m), Lobes::GLOSSY_REFLECTION)
        } else {
            (refract(wo, m, self.ior)?, Lobes::GLOSSY_TRANSMISSION)
        };
        let wi = wi.normalize();
        // A reflection must stay on `wo`'s side and a refraction cross; anything else would be
        // counted under the other lobe's density.
        if (wi.z * wo.z > 0.0) != (lobe == Lobes::GLOSSY_REFLECTION) {
            return None;
        }
        // Weight from eval and pdf, so the three always agree.
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(wo, wi, mode) * (wi.z.abs() / pdf);
        weight.is_finite().then_some(BsdfSample {
            wi,
            weight,
            pdf,
            lobe,
            eta: match lobe {
                Lobes::GLOSSY_TRANSMISSION if wo.z > 0.0 => self.ior,
                Lobes::GLOSSY_TRANSMISSION => 1.0 / self.ior,
                _ => 1.0,
            },
        })
    }
}
