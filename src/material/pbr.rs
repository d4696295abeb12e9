//! The glTF 2.0 metallic-roughness material, as the specification's Appendix B defines it:
//!
//! f = (1 − m)·[(1 − F_d)·base/π + F_d·D·V] + m·[F_m·D·V]
//!
//! with D the GGX distribution of α = roughness², V = G₂ / (4 |n·l| |n·v|) with the
//! height-correlated Smith G₂, F_d = 0.04 + 0.96 (1 − |v·h|)⁵ (a dielectric of IOR 1.5) and
//! F_m = base + (1 − base)(1 − |v·h|)⁵. Schlick's formula is linear in F0, so the two specular
//! terms are one GGX lobe with F0 = mix(0.04, base, m). Two-sided. A roughness under √0.001
//! makes the specular lobe a delta (a polished coat over the diffuse base).

use super::conductor::schlick;
use super::microfacet::Ggx;
use super::{BsdfSample, Lobes, Part};
use crate::math::{Rgb, Vec2, Vec3, luminance, reflect};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use std::f32::consts::FRAC_1_PI;

/// Reflectance of the dielectric coat at normal incidence (IOR 1.5).
const DIELECTRIC_F0: f32 = 0.04;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pbr {
    pub base_color: Rgb,
    pub metallic: f32,
    /// Perceptual roughness, as glTF's factor.
    pub roughness: f32,
    /// `KHR_materials_specular`'s factor: scales the dielectric coat's Fresnel (F0 and F90);
    /// 1 without the extension, 0 for no coat.
    pub specular: f32,
    /// GGX of α = roughness² (isotropic).
    pub ggx: Ggx,
}

/// Which of the two lobes a call uses.
#[derive(Clone, Copy)]
struct Use {
    diffuse: bool,
    specular: bool,
}

impl Pbr {
    /// From the glTF factors: perceptual roughness (α = roughness²).
    pub fn new(base_color: Rgb, metallic: f32, roughness: f32) -> Self {
        let r = roughness.clamp(0.0, 1.0);
        Self {
            base_color,
            metallic: metallic.clamp(0.0, 1.0),
            roughness: r,
            specular: 1.0,
            ggx: Ggx::isotropic(r * r),
        }
    }

    /// With its specular factor s (`KHR_materials_specular`), the coat of the glTF model.
    pub fn with_specular(self, specular: f32) -> Self {
        Self {
            specular: specular.clamp(0.0, 1.0),
            ..self
        }
    }

    /// The dielectric coat's Fresnel at cosine `c`: s · Schlick(0.04).
    fn dielectric_fresnel(&self, c: f32) -> f32 {
        let c = c.clamp(0.0, 1.0);
        self.specular * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * (1.0 - c).powi(5))
    }

    /// The specular lobe's Fresnel: the dielectric coat's and the metal's (Schlick from the
    /// base colour), blended by `metallic`.
    fn fresnel(&self, c: f32) -> Rgb {
        Rgb::splat(self.dielectric_fresnel(c)) * (1.0 - self.metallic)
            + schlick(self.base_color, c) * self.metallic
    }

    fn specular_lobe(&self) -> Lobes {
        if self.ggx.is_delta() {
            Lobes::SPECULAR_REFLECTION
        } else {
            Lobes::GLOSSY_REFLECTION
        }
    }

    fn has_diffuse(&self) -> bool {
        self.metallic < 1.0
    }

    /// A dielectric whose coat is switched off (`KHR_materials_specular` 0) is diffuse only.
    fn has_specular(&self) -> bool {
        self.metallic > 0.0 || self.specular > 0.0
    }

    pub fn lobes(&self) -> Lobes {
        let specular = if self.has_specular() {
            self.specular_lobe()
        } else {
            Lobes::NONE
        };
        if self.has_diffuse() {
            Lobes::DIFFUSE_REFLECTION | specular
        } else {
            specular
        }
    }

    fn uses(&self, part: Part) -> Use {
        Use {
            diffuse: self.has_diffuse() && part.includes(Lobes::DIFFUSE_REFLECTION, 1.0),
            specular: self.has_specular()
                && part.includes(self.specular_lobe(), self.ggx.narrowest_alpha()),
        }
    }

    pub fn part_lobes(&self, part: Part) -> Lobes {
        let u = self.uses(part);
        let d = if u.diffuse {
            Lobes::DIFFUSE_REFLECTION
        } else {
            Lobes::NONE
        };
        if u.specular {
            d | self.specular_lobe()
        } else {
            d
        }
    }

    pub fn has(&self, part: Part) -> bool {
        let u = self.uses(part);
        u.diffuse || u.specular
    }

    /// Probability of sampling the specular lobe when both are in use: in proportion to the
    /// lobes' albedos at `wo`.
    fn specular_probability(&self, wo: Vec3, u: Use) -> f32 {
        match (u.diffuse, u.specular) {
            (false, _) => 1.0,
            (true, false) => 0.0,
            (true, true) => {
                let a = self.albedo_split(wo);
                let (d, s) = (luminance(a.0), luminance(a.1));
                if d + s > 0.0 {
                    (s / (d + s)).clamp(0.1, 0.9)
                } else {
                    0.5
                }
            }
        }
    }

    /// Approximate albedos of the diffuse and specular lobes seen from `wo`.
    fn albedo_split(&self, wo: Vec3) -> (Rgb, Rgb) {
        let c = wo.z.abs();
        let f_d = self.dielectric_fresnel(c);
        let diffuse = if self.has_diffuse() {
            self.base_color * ((1.0 - self.metallic) * (1.0 - f_d))
        } else {
            Rgb::ZERO
        };
        (diffuse, self.fresnel(c))
    }

    /// Reflectance of the specular lobe toward the mirror direction of `wo` (its weight when
    /// polished).
    pub fn coat_reflectance(&self, wo: Vec3) -> Rgb {
        self.fresnel(wo.z)
    }

    pub fn albedo(&self, wo: Vec3, part: Part) -> Rgb {
        let u = self.uses(part);
        let (d, s) = self.albedo_split(wo);
        d * f32::from(u8::from(u.diffuse)) + s * f32::from(u8::from(u.specular))
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, part: Part) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::ZERO;
        }
        let u = self.uses(part);
        let h = (wo + wi).normalize();
        let v_dot_h = wo.dot(h).clamp(0.0, 1.0);
        let mut f = Rgb::ZERO;
        if u.diffuse {
            let f_d = self.dielectric_fresnel(v_dot_h);
            f += self.base_color * ((1.0 - self.metallic) * (1.0 - f_d) * FRAC_1_PI);
        }
        if u.specular && !self.ggx.is_delta() {
            let dg = self.ggx.d(h) * self.ggx.g(wo, wi) / (4.0 * wo.z * wi.z);
            f += self.fresnel(v_dot_h) * dg;
        }
        f
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, part: Part) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let u = self.uses(part);
        let p_spec = self.specular_probability(wo, u);
        let mut pdf = 0.0;
        if u.diffuse {
            pdf += (1.0 - p_spec) * cosine_hemisphere_pdf(wi.z);
        }
        if u.specular && !self.ggx.is_delta() {
            let h = (wo + wi).normalize();
            pdf += p_spec * self.ggx.visible_pdf(wo, h) / (4.0 * wo.dot(h));
        }
        pdf
    }

    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2, part: Part) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let uses = self.uses(part);
        let p_spec = self.specular_probability(wo, uses);
        let specular = u_lobe < p_spec;
        if specular && self.ggx.is_delta() {
            return Some(BsdfSample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: self.fresnel(wo.z) / p_spec,
                pdf: p_spec,
                lobe: Lobes::SPECULAR_REFLECTION,
                eta: 1.0,
            });
        }
        let (wi, lobe) = if specular {
            (
                reflect(wo, self.ggx.sample_visible(wo, u)),
                Lobes::GLOSSY_REFLECTION,
            )
        } else {
            (cosine_hemisphere(u), Lobes::DIFFUSE_REFLECTION)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi, part);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(wo, wi, part) * (wi.z / pdf);
        weight.is_finite().then_some(BsdfSample {
            wi,
            weight,
            pdf,
            lobe,
            eta: 1.0,
        })
    }
}
