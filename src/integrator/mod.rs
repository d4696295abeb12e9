//! Integrators: estimate the radiance arriving along a camera ray.
//!
//! The closed set: `direct` (ray-traced direct light, the original "SimpleRT" pass done right),
//! `path` (the unidirectional reference every later integrator is tested against) and
//! `photon` (Jensen's two-pass photon mapping).

mod direct;
mod path;
mod photon;
mod visible;

pub use direct::DirectConfig;
pub use path::PathConfig;
pub use photon::{PhotonIntegrator, PhotonSettings};
pub use visible::{CameraPath, VisiblePoint, trace_camera_path};

use crate::light::{Light, LightSample};
use crate::material::{Material, TransportMode};
use crate::math::{Frame, Ray, Rgb, Vec3, offset_origin};
use crate::sampling::Rng;
use crate::scene::{Hit, Scene};

/// Counts of rays traced, for the summary line and benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayStats {
    pub camera: u64,
    /// Closest-hit rays after the first hit.
    pub bounce: u64,
    pub shadow: u64,
}

impl RayStats {
    pub fn total(&self) -> u64 {
        self.camera + self.bounce + self.shadow
    }

    pub fn add(&mut self, o: &RayStats) {
        self.camera += o.camera;
        self.bounce += o.bounce;
        self.shadow += o.shadow;
    }
}

/// What one camera sample brings back. `beauty` is the radiance; the photon integrator also
/// splits it by light path (`direct + caustic + indirect = beauty`), and every integrator
/// reports the albedo and shading normal of the first diffuse surface seen (for denoisers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    pub beauty: Rgb,
    pub direct: Rgb,
    pub caustic: Rgb,
    pub indirect: Rgb,
    pub albedo: Rgb,
    pub normal: Vec3,
}

#[derive(Clone, Debug)]
pub enum Integrator {
    Direct(DirectConfig),
    Path(PathConfig),
    Photon(Box<PhotonIntegrator>),
}

impl Integrator {
    pub fn name(&self) -> &'static str {
        match self {
            Integrator::Direct(_) => "direct",
            Integrator::Path(_) => "path",
            Integrator::Photon(_) => "photon",
        }
    }

    /// Whether samples carry the direct / caustic / indirect split.
    pub fn splits_components(&self) -> bool {
        matches!(self, Integrator::Photon(_))
    }

    /// One camera sample along `ray`.
    pub fn sample(&self, scene: &Scene, ray: &Ray, rng: &mut Rng, stats: &mut RayStats) -> Sample {
        match self {
            Integrator::Direct(c) => direct::radiance(c, scene, ray, rng, stats),
            Integrator::Path(c) => path::radiance(c, scene, ray, rng, stats),
            Integrator::Photon(p) => p.sample(scene, ray, rng, stats),
        }
    }
}

/// Everything about a shading point the light-sampling code needs.
pub(crate) struct ShadingPoint<'a> {
    pub hit: &'a Hit,
    pub material: Material,
    pub frame: Frame,
    pub wo_local: Vec3,
    /// The geometric normal on the side of `wo` (see [`Hit::ng_facing`]).
    pub ng: Vec3,
}

impl<'a> ShadingPoint<'a> {
    pub fn new(scene: &'a Scene, hit: &'a Hit, wo: Vec3) -> Self {
        let (material, frame) = scene.surface(hit, wo);
        Self {
            hit,
            material,
            frame,
            wo_local: frame.to_local(wo),
            ng: hit.ng_facing(wo),
        }
    }
}

/// Unoccluded contribution f·L·|cos|/pdf of one light sample, before any MIS weight; zero if
/// the light is hidden. Also returns the BSDF's density for the same direction (for MIS).
pub(crate) fn light_sample_contribution(
    scene: &Scene,
    sp: &ShadingPoint,
    ls: &LightSample,
    stats: &mut RayStats,
) -> Option<(Rgb, f32)> {
    let wi_local = sp.frame.to_local(ls.wi);
    let f = sp
        .material
        .eval(sp.wo_local, wi_local, TransportMode::Radiance);
    if f == Rgb::ZERO {
        return None;
    }
    let value = shadowed(scene, sp, ls, f, stats);
    (value != Rgb::ZERO).then(|| (value, sp.material.pdf(sp.wo_local, wi_local)))
}

/// f·L·|cos|/pdf of one light sample for the BSDF value `f`, or zero if the light is hidden.
pub(crate) fn shadowed(
    scene: &Scene,
    sp: &ShadingPoint,
    ls: &LightSample,
    f: Rgb,
    stats: &mut RayStats,
) -> Rgb {
    if f == Rgb::ZERO {
        return Rgb::ZERO;
    }
    stats.shadow += 1;
    if !unoccluded(scene, sp.hit, ls) {
        return Rgb::ZERO;
    }
    f * ls.radiance * (sp.frame.n.dot(ls.wi).abs() / ls.pdf)
}

/// Whether the segment from the shading point to the light sample is free. Both ends are moved
/// off their surfaces (the light's end toward the shading point), and the ray runs between the
/// moved ends: reusing the direction and length measured from the unmoved point made the
/// segment cross the light's own plane when a surface saw the light at a grazing angle, so the
/// light shadowed itself (a patch beside a quad light lost 63% of its irradiance).
fn unoccluded(scene: &Scene, hit: &Hit, ls: &LightSample) -> bool {
    let origin = offset_origin(hit.p, hit.ng, ls.wi);
    if ls.is_delta {
        // A point has no surface to shadow itself with.
        return !scene.occluded(origin, ls.wi, (ls.point - origin).length());
    }
    let target = offset_origin(ls.point, ls.normal, origin - ls.point);
    let d = target - origin;
    let dist = d.length();
    dist > 0.0 && !scene.occluded(origin, d / dist, dist)
}

/// Power heuristic with β = 2 (Veach & Guibas 1995).
pub(crate) fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a + b == 0.0 { 0.0 } else { a / (a + b) }
}

/// Solid-angle density with which light sampling (choice by power, then the light's own
/// sampling) would have produced the direction from `from` to the emitter `hit`.
pub(crate) fn light_pdf_for_hit(scene: &Scene, from: Vec3, hit: &Hit) -> f32 {
    let i = hit.light as usize;
    scene.light_choice_pmf(i) * own_light_pdf_for_hit(scene, from, hit)
}

/// Solid-angle density with which the emitter `hit`'s own sampling produces the direction
/// from `from` (no choice between lights: [`direct::direct_light`] samples every light).
pub(crate) fn own_light_pdf_for_hit(scene: &Scene, from: Vec3, hit: &Hit) -> f32 {
    match &scene.lights()[hit.light as usize] {
        Light::Area(l) => l.pdf_li(from, hit.p, hit.ng),
        Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Environment(_) => 0.0,
    }
}
