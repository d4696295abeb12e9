//! Rough (or polished) metal: a GGX microfacet conductor (Walter et al. 2007, "Microfacet
//! Models for Refraction through Rough Surfaces"; Heitz 2018 for sampling), with the exact
//! Fresnel reflectance of a complex index of refraction, or Schlick's from an F0 colour.

use super::microfacet::Ggx;
use super::{BsdfSample, Lobes};
use crate::math::{Rgb, Vec2, Vec3, reflect};

/// Named metals: complex IOR (η, k) per linear Rec. 709 channel, the RGB values Mitsuba 3.9's
/// RGB variants derive from the measured spectra it ships as `Au`, `Ag`, `Cu` and `Al` (read
/// from its `roughconductor`), so that the validation references and Photon mean the same gold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metal {
    Gold,
    Silver,
    Copper,
    Aluminium,
}

impl Metal {
    pub const ALL: [Metal; 4] = [Metal::Gold, Metal::Silver, Metal::Copper, Metal::Aluminium];

    pub fn name(self) -> &'static str {
        match self {
            Metal::Gold => "gold",
            Metal::Silver => "silver",
            Metal::Copper => "copper",
            Metal::Aluminium => "aluminium",
        }
    }

    /// (η, k) per channel.
    pub fn ior(self) -> (Rgb, Rgb) {
        match self {
            Metal::Gold => (
                Rgb::new(0.143, 0.3753, 1.442),
                Rgb::new(3.983, 2.386, 1.603),
            ),
            Metal::Silver => (
                Rgb::new(0.1553, 0.1167, 0.1384),
                Rgb::new(4.828, 3.122, 2.147),
            ),
            Metal::Copper => (
                Rgb::new(0.201, 0.9237, 1.102),
                Rgb::new(3.913, 2.453, 2.142),
            ),
            Metal::Aluminium => (
                Rgb::new(1.658, 0.8804, 0.5212),
                Rgb::new(9.224, 6.27, 4.837),
            ),
        }
    }
}

/// How a conductor's reflectance depends on the angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Exact, from the complex index of refraction η + ik (relative to the outside medium).
    Complex { eta: Rgb, k: Rgb },
    /// Schlick's approximation from the reflectance at normal incidence.
    Schlick { f0: Rgb },
}

impl ConductorFresnel {
    /// Reflectance for light arriving with cosine `cos_i` (≥ 0) to the normal.
    pub fn eval(&self, cos_i: f32) -> Rgb {
        match *self {
            ConductorFresnel::Complex { eta, k } => Rgb::new(
                fresnel_conductor(cos_i, eta.x, k.x),
                fresnel_conductor(cos_i, eta.y, k.y),
                fresnel_conductor(cos_i, eta.z, k.z),
            ),
            ConductorFresnel::Schlick { f0 } => schlick(f0, cos_i),
        }
    }
}

/// Schlick's Fresnel: F0 + (1 − F0)(1 − cos)⁵.
pub(super) fn schlick(f0: Rgb, cos_i: f32) -> Rgb {
    let m = (1.0 - cos_i.clamp(0.0, 1.0)).powi(5);
    f0 + (Rgb::ONE - f0) * m
}

/// Unpolarised Fresnel reflectance of a conductor with complex index η + ik, for light arriving
/// with cosine `cos_i` (the exact formula, written in terms of a² + b² as in Lagarde's "Memo on
/// Fresnel equations", 2013).
pub fn fresnel_conductor(cos_i: f32, eta: f32, k: f32) -> f32 {
    let c = cos_i.clamp(0.0, 1.0);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let (eta2, k2) = (eta * eta, k * k);
    let t0 = eta2 - k2 - s2;
    let a2_plus_b2 = (t0 * t0 + 4.0 * eta2 * k2).sqrt();
    let a = (0.5 * (a2_plus_b2 + t0)).max(0.0).sqrt();
    let t1 = a2_plus_b2 + c2;
    let t2 = 2.0 * c * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = c2 * a2_plus_b2 + s2 * s2;
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    (0.5 * (rp + rs)).clamp(0.0, 1.0)
}

/// A microfacet metal, two-sided. α = 0 is a polished (delta) mirror with Fresnel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    pub ggx: Ggx,
    pub fresnel: ConductorFresnel,
}

impl Conductor {
    pub fn lobes(&self) -> Lobes {
        if self.ggx.is_delta() {
            Lobes::SPECULAR_REFLECTION
        } else {
            Lobes::GLOSSY_REFLECTION
        }
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.ggx.is_delta() {
            return Rgb::ZERO;
        }
        let h = (wo + wi).normalize();
        let d = self.ggx.d(h);
        let g = self.ggx.g(wo, wi);
        self.fresnel.eval(wo.dot(h)) * (d * g / (4.0 * wo.z * wi.z))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.ggx.is_delta() {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        self.ggx.visible_pdf(wo, h) / (4.0 * wo.dot(h))
    }

    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.ggx.is_delta() {
            return Some(BsdfSample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: self.fresnel.eval(wo.z),
                pdf: 1.0,
                lobe: Lobes::SPECULAR_REFLECTION,
                eta: 1.0,
            });
        }
        let h = self.ggx.sample_visible(wo, u);
        let wi = reflect(wo, h);
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.ggx.visible_pdf(wo, h) / (4.0 * wo.dot(h));
        // f·cos/pdf = F · G2 / G1(wo) with visible-normal sampling.
        let weight = self.fresnel.eval(wo.dot(h)) * (self.ggx.g(wo, wi) / self.ggx.g1(wo));
        (pdf > 0.0 && weight.is_finite()).then_some(BsdfSample {
            wi,
            weight,
            pdf,
            lobe: Lobes::GLOSSY_REFLECTION,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conductor_fresnel_matches_normal_incidence_and_grazing() {
        for metal in Metal::ALL {
            let (eta, k) = metal.ior();
            for c in 0..3 {
                let f0 =
                    ((eta[c] - 1.0).powi(2) + k[c] * k[c]) / ((eta[c] + 1.0).powi(2) + k[c] * k[c]);
                assert!((fresnel_conductor(1.0, eta[c], k[c]) - f0).abs() < 1e-5);
                assert!(fresnel_conductor(1e-4, eta[c], k[c]) > 0.99);
            }
        }
        // A dielectric (k = 0) gives the dielectric Fresnel.
        for cos in [1.0f32, 0.7, 0.3] {
            let d = super::super::fresnel_dielectric(cos, 1.5);
            assert!((fresnel_conductor(cos, 1.5, 0.0) - d).abs() < 1e-5, "{cos}");
        }
    }
}
