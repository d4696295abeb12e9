//! Materials: the closed set of BSDFs, one file each, behind one interface built on lobes.
//!
//! Every material reports its [`Lobes`] (diffuse, glossy, specular; reflection, transmission)
//! and answers `eval`, `pdf` and `sample` (returning a named [`BsdfSample`]). Integrators decide
//! by lobes and by [`Part`], never by material kind: adding a material touches its own file,
//! the `Material` enum below and the description mapping, and nothing in the integrators.
//!
//! All BSDF methods work in a local shading frame whose `z` axis is the surface normal on the
//! side the incoming ray came from for two-sided materials, and the *outward* normal for
//! dielectrics (which must know whether light is entering or leaving). `wo` and `wi` point away
//! from the surface.

mod conductor;
mod dielectric;
mod dispersion;
mod lambertian;
pub mod microfacet;
mod mirror;
mod pbr;
mod rough_dielectric;

pub use conductor::{Conductor, ConductorFresnel, Metal, fresnel_conductor};
pub use dielectric::{Dielectric, fresnel_dielectric};
pub use dispersion::{Dispersion, LINE_C_NM, LINE_D_NM, LINE_F_NM};
pub use lambertian::Lambertian;
pub use mirror::Mirror;
pub use pbr::Pbr;
pub use rough_dielectric::RoughDielectric;

use crate::math::{Rgb, Vec2, Vec3, luminance};
use crate::spectrum::Lambda;
use microfacet::Ggx;

/// Glossy lobes narrower than this GGX α are *near-specular*: camera paths continue through
/// them (sampling the lobe) and photons pass them by, as for mirrors and glass; wider lobes are
/// *rough*: camera paths stop there and read the photon maps, which store photons on them.
///
/// Why 0.3: a photon estimate at a glossy point averages the k photons of its disc weighted by
/// the lobe, so only those arriving inside the lobe count. A GGX lobe of α = 0.3 still catches
/// a fifth of the photons of a uniformly lit disc (seen at normal incidence); at α = 0.1 it is
/// about 3%, one photon in a k = 32 estimate, and the highlight breaks into blotches. One more
/// bounce, to a diffuse surface where every photon counts, is cheaper than the photons that
/// would need.
pub const NEAR_SPECULAR_ALPHA: f32 = 0.3;

/// Beer–Lambert absorption in the volume a dielectric encloses (the `KHR_materials_volume`
/// parameters): white light that travels `distance` inside comes out as `color`, so a
/// segment of length d keeps `color`^(d / `distance`) of each channel, i.e. exp(−σₐ d) with
/// σₐ = −ln(`color`) / `distance` (the extension's definition; pbrt-v4's homogeneous medium
/// with no scattering). The volume only absorbs: there is no scattering or emission in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attenuation {
    /// The colour white light turns into at `distance`, each channel in [0, 1] (checked by
    /// the scene builder: absorption only removes light).
    pub color: Rgb,
    /// In scene units, positive.
    pub distance: f32,
}

impl Attenuation {
    /// The fraction of each channel of a path of `lambda` left after travelling `length`
    /// inside.
    #[inline]
    ///
    /// In spectral rendering the absorption coefficient σₐ = −ln(`color`) / `distance` is
    /// what is upsampled, and the transmittance is exp(−σₐ(λ) d). An RGB σₐ has many spectra;
    /// this one is its largest channel m times the reflectance spectrum of σₐ / m, as Mitsuba 3
    /// upsamples a medium's σt given as a colour and a scale (pbrt-v4's unbounded spectrum,
    /// 2m times the reflectance of σₐ / 2m, has the same colour and through the validation
    /// suite's tinted glass lets 1% more red through).
    pub fn transmittance(&self, length: f32, lambda: &Lambda) -> Rgb {
        let length = length.max(0.0);
        if lambda.is_spectral() {
            // A black channel (σ = ∞) is held at the largest finite σ; exp(−σ · 0) = 1 keeps
            // a zero-length segment clear.
            let sigma = (-self.color.map(f32::ln) / self.distance).min(Rgb::splat(f32::MAX));
            let m = sigma.max_element();
            if m.is_nan() || m <= 0.0 {
                return Rgb::ONE;
            }
            return (-(lambda.reflectance(sigma / m) * m) * length).exp();
        }
        // `powf`: 0^0 = 1 keeps a zero-length segment clear even in a black channel, where
        // exp(−∞ · 0) would be NaN.
        let x = length / self.distance;
        let c = self.color;
        Rgb::new(c.x.powf(x), c.y.powf(x), c.z.powf(x))
    }
}

/// Whether the path carries radiance (from the camera) or importance/flux (from the lights).
/// Refraction scales radiance by 1/η² but not flux (Veach 1997, ch. 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    Radiance,
    Importance,
}

/// Flags describing a BSDF's lobes, as pbrt-v4's `BxDFFlags`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Lobes(u8);

impl Lobes {
    pub const NONE: Lobes = Lobes(0);
    pub const REFLECTION: Lobes = Lobes(1);
    pub const TRANSMISSION: Lobes = Lobes(2);
    pub const DIFFUSE: Lobes = Lobes(4);
    pub const GLOSSY: Lobes = Lobes(8);
    pub const SPECULAR: Lobes = Lobes(16);
    pub const DIFFUSE_REFLECTION: Lobes = Lobes(4 | 1);
    pub const GLOSSY_REFLECTION: Lobes = Lobes(8 | 1);
    pub const GLOSSY_TRANSMISSION: Lobes = Lobes(8 | 2);
    pub const SPECULAR_REFLECTION: Lobes = Lobes(16 | 1);
    pub const SPECULAR_TRANSMISSION: Lobes = Lobes(16 | 2);

    /// Whether every flag of `other` is set.
    pub const fn contains(self, other: Lobes) -> bool {
        self.0 & other.0 == other.0
    }

    pub const fn intersects(self, other: Lobes) -> bool {
        self.0 & other.0 != 0
    }

    pub const fn union(self, other: Lobes) -> Lobes {
        Lobes(self.0 | other.0)
    }

    pub const fn is_specular(self) -> bool {
        self.intersects(Lobes::SPECULAR)
    }

    /// Whether any lobe has a density (diffuse or glossy), so that `eval` can be non-zero and
    /// next-event estimation makes sense.
    pub const fn has_density(self) -> bool {
        self.intersects(Lobes(4 | 8))
    }
}

impl std::ops::BitOr for Lobes {
    type Output = Lobes;
    fn bitor(self, rhs: Lobes) -> Lobes {
        self.union(rhs)
    }
}

/// Which lobes of a material a call concerns. The photon-mapping integrators split every
/// material in two: the *rough* part (diffuse lobes, and glossy lobes of α ≥
/// [`NEAR_SPECULAR_ALPHA`]), which is estimated from the photon maps, and the *smooth* part
/// (specular lobes, near-specular glossy lobes and every transmission), which paths follow.
/// Dielectrics are smooth at any roughness: a photon estimate of transmitted light would need
/// the photons on the far side of the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    All,
    Rough,
    Smooth,
}

impl Part {
    /// Whether a lobe of the given kind (and α, for glossy lobes) belongs to this part.
    pub fn includes(self, lobe: Lobes, alpha: f32) -> bool {
        let rough = !lobe.intersects(Lobes::TRANSMISSION)
            && (lobe.contains(Lobes::DIFFUSE)
                || (lobe.contains(Lobes::GLOSSY) && alpha >= NEAR_SPECULAR_ALPHA));
        match self {
            Part::All => true,
            Part::Rough => rough,
            Part::Smooth => !rough,
        }
    }
}

/// One branch of a delta lobe: its direction and its probability-free weight (F for glass's
/// reflection, (1 − F)·T (/η² for radiance) for its refraction).
#[derive(Clone, Copy, Debug)]
pub struct SpecularBranch {
    pub wi: Vec3,
    pub weight: Rgb,
}

/// A sampled direction with its weight.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled incident direction (local frame).
    pub wi: Vec3,
    /// f · |cos θi| / pdf: the factor the path throughput is multiplied by.
    pub weight: Rgb,
    /// Solid-angle density of `wi` (over the lobes of the part sampled); for a specular lobe
    /// the discrete probability of choosing it.
    pub pdf: f32,
    /// The lobe `wi` came from.
    pub lobe: Lobes,
    /// Relative index of refraction across the surface in the direction of travel (the index
    /// on `wi`'s side over `wo`'s) when `wi` was refracted; 1 for reflection. Radiance
    /// crossing it is scaled by 1/eta² (Veach 1997, §5.2), which Russian roulette undoes
    /// (see [`crate::integrator`]'s path tracer).
    pub eta: f32,
}

impl BsdfSample {
    /// Whether `wi` came from a Dirac delta lobe (mirror or smooth glass).
    pub fn is_specular(&self) -> bool {
        self.lobe.is_specular()
    }
}

#[derive(Clone, Copy, Debug)]
pub enum Material {
    Lambertian(Lambertian),
    Mirror(Mirror),
    Dielectric(Dielectric),
    Conductor(Conductor),
    RoughDielectric(RoughDielectric),
    Pbr(Pbr),
}

impl Material {
    /// The union of the material's lobes.
    #[inline]
    pub fn lobes(&self) -> Lobes {
        match self {
            Material::Lambertian(_) => Lobes::DIFFUSE_REFLECTION,
            Material::Mirror(_) => Lobes::SPECULAR_REFLECTION,
            Material::Dielectric(_) => Lobes::SPECULAR_REFLECTION | Lobes::SPECULAR_TRANSMISSION,
            Material::Conductor(m) => m.lobes(),
            Material::RoughDielectric(_) => Lobes::GLOSSY_REFLECTION | Lobes::GLOSSY_TRANSMISSION,
            Material::Pbr(m) => m.lobes(),
        }
    }

    /// Whether any of the material's lobes belongs to `part`. Every material but `pbr` has
    /// one lobe (a union of flags), which [`Part::includes`] places with its α.
    #[inline]
    pub fn has(&self, part: Part) -> bool {
        match self {
            Material::Pbr(m) => m.has(part),
            _ => part.includes(self.lobes(), self.ggx().map_or(0.0, Ggx::narrowest_alpha)),
        }
    }

    /// The lobes of one part.
    pub fn part_lobes(&self, part: Part) -> Lobes {
        match self {
            Material::Pbr(m) => m.part_lobes(part),
            _ if self.has(part) => self.lobes(),
            _ => Lobes::NONE,
        }
    }

    /// The microfacet distribution of the material's glossy lobes, if it has any.
    fn ggx(&self) -> Option<&Ggx> {
        match self {
            Material::Conductor(m) => Some(&m.ggx),
            Material::RoughDielectric(m) => Some(&m.ggx),
            Material::Pbr(m) => Some(&m.ggx),
            Material::Lambertian(_) | Material::Mirror(_) | Material::Dielectric(_) => None,
        }
    }

    /// The GGX α of the material's glossy lobes in `part` ([`Ggx::narrowest_alpha`]; ∞
    /// without any).
    pub fn glossy_alpha(&self, part: Part) -> f32 {
        if !self.part_lobes(part).contains(Lobes::GLOSSY) {
            return f32::INFINITY;
        }
        self.ggx().map_or(f32::INFINITY, Ggx::narrowest_alpha)
    }

    /// True when every lobe is a delta: no density, so next-event estimation is pointless.
    pub fn is_specular(&self) -> bool {
        !self.lobes().has_density()
    }

    /// Whether the shading frame should be flipped to the side of `wo` (two-sided materials).
    pub fn is_two_sided(&self) -> bool {
        !matches!(self, Material::Dielectric(_) | Material::RoughDielectric(_))
    }

    /// The material as met by a path that reached it through the volume it encloses: every
    /// lobe, reflection and refraction alike, scaled by `transmittance`, the Beer–Lambert
    /// transmittance of the segment travelled inside (see [`Attenuation`]), since whatever
    /// the path does here it has crossed that segment. Densities are unchanged, so sample
    /// weights carry the factor and MIS weights do not. Only dielectrics enclose a volume;
    /// other materials are returned as they are.
    #[inline]
    pub fn attenuated(self, transmittance: Rgb) -> Material {
        match self {
            Material::Dielectric(mut m) => {
                m.segment *= transmittance;
                Material::Dielectric(m)
            }
            Material::RoughDielectric(mut m) => {
                m.segment *= transmittance;
                Material::RoughDielectric(m)
            }
            Material::Lambertian(_)
            | Material::Mirror(_)
            | Material::Conductor(_)
            | Material::Pbr(_) => self,
        }
    }

    /// The material as a path of `lambda` sees it: in spectral rendering every colour is
    /// upsampled to the path's wavelengths (albedos and tints as reflectances, a conductor's
    /// η and k without bound), and a glass whose index follows `dispersion` takes the index at
    /// the hero wavelength and ends the others ([`Lambda::keep_hero_only`], its factor on both
    /// branches: the directions it refracts into hold for the hero alone). RGB paths get it
    /// unchanged: a dispersive glass's `ior` is its index at the d line.
    pub fn at(self, lambda: &mut Lambda, dispersion: Dispersion) -> Material {
        if !lambda.is_spectral() {
            return self;
        }
        let refract_at = |lambda: &mut Lambda, ior: &mut f32, weight: &mut Rgb| {
            if let Some(n) = lambda.hero().and_then(|l| dispersion.ior(l)) {
                *ior = n;
                *weight *= lambda.keep_hero_only();
            }
        };
        match self {
            Material::Lambertian(mut m) => {
                m.albedo = lambda.reflectance(m.albedo);
                Material::Lambertian(m)
            }
            Material::Mirror(mut m) => {
                m.reflectance = lambda.reflectance(m.reflectance);
                Material::Mirror(m)
            }
            Material::Dielectric(mut m) => {
                m.transmittance = lambda.reflectance(m.transmittance);
                refract_at(lambda, &mut m.ior, &mut m.segment);
                Material::Dielectric(m)
            }
            Material::RoughDielectric(mut m) => {
                m.transmittance = lambda.reflectance(m.transmittance);
                refract_at(lambda, &mut m.ior, &mut m.segment);
                Material::RoughDielectric(m)
            }
            Material::Conductor(mut m) => {
                m.fresnel = match m.fresnel {
                    ConductorFresnel::Complex { eta, k } => ConductorFresnel::Complex {
                        eta: lambda.unbounded(eta),
                        k: lambda.unbounded(k),
                    },
                    ConductorFresnel::Schlick { f0 } => ConductorFresnel::Schlick {
                        f0: lambda.reflectance(f0),
                    },
                };
                Material::Conductor(m)
            }
            Material::Pbr(mut m) => {
                m.base_color = lambda.reflectance(m.base_color);
                Material::Pbr(m)
            }
        }
    }

    /// Whether the material encloses a volume (a path on the inner side of its outward
    /// normal is inside it): dielectrics.
    pub fn encloses_volume(&self) -> bool {
        !self.is_two_sided()
    }

    /// BSDF value of every lobe for a pair of directions (zero for delta lobes).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        self.eval_part(wo, wi, mode, Part::All)
    }

    /// BSDF value of the lobes in `part`.
    #[inline]
    pub fn eval_part(&self, wo: Vec3, wi: Vec3, mode: TransportMode, part: Part) -> Rgb {
        if part != Part::All && !self.has(part) {
            return Rgb::ZERO;
        }
        match self {
            Material::Lambertian(m) => m.eval(wo, wi),
            Material::Mirror(_) | Material::Dielectric(_) => Rgb::ZERO,
            Material::Conductor(m) => m.eval(wo, wi),
            Material::RoughDielectric(m) => m.eval(wo, wi, mode),
            Material::Pbr(m) => m.eval(wo, wi, part),
        }
    }

    /// Solid-angle density with which [`Material::sample`] picks `wi` (zero for delta lobes).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_part(wo, wi, Part::All)
    }

    /// Density with which [`Material::sample_part`] for `part` picks `wi`.
    #[inline]
    pub fn pdf_part(&self, wo: Vec3, wi: Vec3, part: Part) -> f32 {
        if part != Part::All && !self.has(part) {
            return 0.0;
        }
        match self {
            Material::Lambertian(m) => m.pdf(wo, wi),
            Material::Mirror(_) | Material::Dielectric(_) => 0.0,
            Material::Conductor(m) => m.pdf(wo, wi),
            Material::RoughDielectric(m) => m.pdf(wo, wi),
            Material::Pbr(m) => m.pdf(wo, wi, part),
        }
    }

    /// Sample an incident direction from every lobe. `u_lobe` picks a lobe, `u` the direction
    /// within it.
    #[inline]
    pub fn sample(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        self.sample_part(wo, u_lobe, u, mode, Part::All)
    }

    /// Sample an incident direction from the lobes in `part`.
    #[inline]
    pub fn sample_part(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
        part: Part,
    ) -> Option<BsdfSample> {
        if part != Part::All && !self.has(part) {
            return None;
        }
        match self {
            Material::Lambertian(m) => m.sample(wo, u),
            Material::Mirror(m) => m.sample(wo),
            Material::Dielectric(m) => m.sample(wo, u_lobe, mode),
            Material::Conductor(m) => m.sample(wo, u),
            Material::RoughDielectric(m) => m.sample(wo, u_lobe, u, mode),
            Material::Pbr(m) => m.sample(wo, u_lobe, u, part),
        }
    }

    /// The branches of the material's delta lobes at `wo`, each with its whole weight, so that a
    /// path can follow all of them instead of choosing: both of smooth glass, the one of a
    /// mirror, a polished metal or a polished pbr coat; none for lobes with a density.
    pub fn specular_branches(&self, wo: Vec3, mode: TransportMode) -> [Option<SpecularBranch>; 2] {
        let mirrored = |weight: Rgb| {
            (wo.z > 0.0).then_some(SpecularBranch {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight,
            })
        };
        match self {
            Material::Dielectric(m) => {
                let (r, t) = m.branches(wo, mode);
                [Some(r), t]
            }
            Material::Mirror(m) => [mirrored(m.reflectance), None],
            Material::Conductor(m) if m.ggx.is_delta() => [mirrored(m.fresnel.eval(wo.z)), None],
            Material::Pbr(m) if m.ggx.is_delta() => [mirrored(m.coat_reflectance(wo)), None],
            _ => [None, None],
        }
    }

    /// Hemispherical-directional reflectance (albedo) seen from `wo`, for Russian roulette and
    /// for the albedo AOV (approximate for microfacet lobes: their Fresnel at `wo`).
    pub fn albedo(&self, wo: Vec3) -> Rgb {
        self.albedo_part(wo, Part::All)
    }

    /// The albedo of the lobes in `part` (approximate for microfacet lobes), by which the
    /// progressive integrators choose between the two parts.
    pub fn albedo_part(&self, wo: Vec3, part: Part) -> Rgb {
        if !self.has(part) {
            return Rgb::ZERO;
        }
        match self {
            Material::Lambertian(m) => m.albedo,
            Material::Mirror(m) => m.reflectance,
            Material::Dielectric(m) => {
                let f = fresnel_dielectric(wo.z, m.ior);
                m.segment * (Rgb::splat(f) + (1.0 - f) * m.transmittance)
            }
            Material::Conductor(m) => m.fresnel.eval(wo.z.abs()),
            Material::RoughDielectric(m) => {
                let f = fresnel_dielectric(wo.z, m.ior);
                m.segment * (Rgb::splat(f) + (1.0 - f) * m.transmittance)
            }
            Material::Pbr(m) => m.albedo(wo, part),
        }
    }

    /// Whether a sampled lobe belongs to the smooth part (see [`Part`]).
    pub fn is_smooth_lobe(&self, lobe: Lobes) -> bool {
        // Every lobe of a material without a rough part is smooth: dielectrics are smooth at
        // any roughness.
        if !self.has(Part::Rough) {
            return true;
        }
        let alpha = self.ggx().map_or(0.0, Ggx::narrowest_alpha);
        Part::Smooth.includes(lobe, alpha)
    }

    /// Luminance of [`Material::albedo_part`].
    pub fn part_weight(&self, wo: Vec3, part: Part) -> f32 {
        luminance(self.albedo_part(wo, part))
    }
}
