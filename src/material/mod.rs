//! Materials: the closed set of BSDFs, one file each.
//!
//! All BSDF methods work in a local shading frame whose `z` axis is the surface normal on the
//! side the incoming ray came from for two-sided materials, and the *outward* normal for
//! dielectrics (which must know whether light is entering or leaving). `wo` and `wi` point away
//! from the surface.

mod dielectric;
mod lambertian;
mod mirror;

pub use dielectric::{Dielectric, fresnel_dielectric};
pub use lambertian::Lambertian;
pub use mirror::Mirror;

use crate::math::{Rgb, Vec2, Vec3};

/// Whether the path carries radiance (from the camera) or importance/flux (from the lights).
/// Refraction scales radiance by 1/η² but not flux (Veach 1997, ch. 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    Radiance,
    Importance,
}

/// A sampled direction with its weight.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled incident direction (local frame).
    pub wi: Vec3,
    /// f · |cos θi| / pdf: the factor the path throughput is multiplied by.
    pub weight: Rgb,
    /// Solid-angle density of `wi`; for specular lobes the discrete probability of the lobe.
    pub pdf: f32,
    /// Whether `wi` came from a Dirac delta lobe (mirror or glass).
    pub specular: bool,
}

#[derive(Clone, Copy, Debug)]
pub enum Material {
    Lambertian(Lambertian),
    Mirror(Mirror),
    Dielectric(Dielectric),
}

impl Material {
    /// True for purely specular materials: they have no non-delta component, so next-event
    /// estimation is pointless and photons are not stored on them.
    pub fn is_specular(&self) -> bool {
        match self {
            Material::Lambertian(_) => false,
            Material::Mirror(_) | Material::Dielectric(_) => true,
        }
    }

    /// Whether the shading frame should be flipped to the side of `wo` (two-sided materials).
    pub fn is_two_sided(&self) -> bool {
        !matches!(self, Material::Dielectric(_))
    }

    /// BSDF value for a pair of directions (zero for delta lobes).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match self {
            Material::Lambertian(m) => m.eval(wo, wi),
            Material::Mirror(_) | Material::Dielectric(_) => Rgb::ZERO,
        }
    }

    /// Solid-angle density with which [`Material::sample`] picks `wi` (zero for delta lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Material::Lambertian(m) => m.pdf(wo, wi),
            Material::Mirror(_) | Material::Dielectric(_) => 0.0,
        }
    }

    /// Sample an incident direction. `u_lobe` picks a lobe, `u` the direction within it.
    pub fn sample(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        match self {
            Material::Lambertian(m) => m.sample(wo, u),
            Material::Mirror(m) => m.sample(wo),
            Material::Dielectric(m) => m.sample(wo, u_lobe, mode),
        }
    }

    /// Hemispherical-directional reflectance (albedo) seen from `wo`, for Russian roulette and
    /// for the albedo AOV.
    pub fn albedo(&self, wo: Vec3) -> Rgb {
        match self {
            Material::Lambertian(m) => m.albedo,
            Material::Mirror(m) => m.reflectance,
            Material::Dielectric(m) => {
                let f = fresnel_dielectric(wo.z, m.ior);
                Rgb::splat(f) + (1.0 - f) * m.transmittance
            }
        }
    }
}
