//! Integrators: estimate the radiance arriving along a camera ray.
//!
//! The closed set: `direct` (ray-traced direct light, the original "SimpleRT" pass done right),
//! `path` (the unidirectional reference every later integrator is tested against) and
//! `photon` (Jensen's two-pass photon mapping).

mod delta;
mod direct;
mod lighting;
mod medium_segment;
mod path;
mod photon;
pub mod vcm;
mod visible;

pub use direct::DirectConfig;
pub use path::PathConfig;
pub use photon::{PhotonIntegrator, PhotonSettings};
pub use visible::{CameraPath, VisiblePoint, VolumePoint, trace_camera_path};

use crate::material::Material;
use crate::math::{Frame, Ray, Rgb, Vec3};
use crate::sampling::Sampler;
use crate::scene::{Hit, Scene};
use crate::spectrum::Lambda;

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

impl Sample {
    /// The sample of a path of `lambda` in linear Rec. 709 RGB: its light through CIE XYZ
    /// ([`Lambda::to_rgb`]), its albedo as the colour the reflectance has under the white of
    /// RGB (D65), as an albedo given in RGB would. RGB samples are returned as they are.
    pub fn to_rgb(self, lambda: &Lambda) -> Self {
        if !lambda.is_spectral() {
            return self;
        }
        Self {
            beauty: lambda.to_rgb(self.beauty),
            direct: lambda.to_rgb(self.direct),
            caustic: lambda.to_rgb(self.caustic),
            indirect: lambda.to_rgb(self.indirect),
            albedo: lambda.to_rgb(self.albedo * lambda.illuminant(Rgb::ONE)),
            normal: self.normal,
        }
    }

    /// The sample scaled so that no channel of its radiance exceeds `max`, its colour (and
    /// the split `direct + caustic + indirect = beauty`) kept: the clamp of pbrt-v4's
    /// `maxcomponentvalue`. It trades the variance of rare bright paths for a darker bias.
    pub fn clamped(self, max: f32) -> Self {
        let peak = self.beauty.max_element();
        if peak <= max || !peak.is_finite() {
            return self;
        }
        let scale = max / peak;
        Self {
            beauty: self.beauty * scale,
            direct: self.direct * scale,
            caustic: self.caustic * scale,
            indirect: self.indirect * scale,
            ..self
        }
    }
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

    /// One camera sample along `ray`, carrying the channels of `lambda` (the sample's
    /// values are at them: see [`Sample::to_rgb`]); a dispersive glass on the path may end
    /// all but its hero wavelength.
    pub fn sample(
        &self,
        scene: &Scene,
        ray: &Ray,
        lambda: &mut Lambda,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Sample {
        match self {
            Integrator::Direct(c) => direct::radiance(c, scene, ray, lambda, rng, stats),
            Integrator::Path(c) => path::radiance(c, scene, ray, lambda, rng, stats),
            Integrator::Photon(p) => p.sample(scene, ray, lambda, rng, stats),
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
    /// The medium the path reached the point through (see [`Scene::medium_after`]).
    pub medium: Option<crate::medium::MediumId>,
    /// The path's wavelengths, after the point's material (a dispersive glass ends all but
    /// the hero).
    pub lambda: Lambda,
}

impl<'a> ShadingPoint<'a> {
    /// The point a path of `lambda` reached; `lambda` is updated as the material requires.
    pub fn new(scene: &'a Scene, hit: &'a Hit, wo: Vec3, lambda: &mut Lambda) -> Self {
        let (material, frame) = scene.surface(hit, wo, lambda);
        Self {
            hit,
            material,
            frame,
            wo_local: frame.to_local(wo),
            ng: hit.ng_facing(wo),
            medium: scene.atmosphere(),
            lambda: *lambda,
        }
    }

    /// The point reached through `medium`.
    pub fn in_medium(self, medium: Option<crate::medium::MediumId>) -> Self {
        Self { medium, ..self }
    }
}
