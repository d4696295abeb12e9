//! Lights: the closed set, one file each. Every light reports its total emitted power (flux in
//! watts per RGB channel) and can be sampled from a shading point for next-event estimation.

mod aperture;
mod area;
mod directional;
mod environment;
mod point;
mod spot;

pub use aperture::Aperture;
pub use area::AreaLight;
pub use directional::DirectionalLight;
pub use environment::{EnvironmentLight, EnvironmentMap};

pub use point::PointLight;
pub use spot::SpotLight;

use crate::math::{Rgb, Vec2, Vec3, offset_origin};
use crate::spectrum::Lambda;

/// A light sampled from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light.
    pub wi: Vec3,
    /// Incident radiance along `wi` for area lights; for delta lights, intensity / distance²
    /// (the delta's integral), with `pdf` = 1.
    pub radiance: Rgb,
    /// Solid-angle density of `wi` (1 for delta lights).
    pub pdf: f32,
    /// The sampled point on the light, the far end of the shadow ray.
    pub point: Vec3,
    /// Normal at the sampled point (zero for point and spot lights).
    pub normal: Vec3,
    /// A bound on each coordinate of `point`'s distance from the light's surface (zero where
    /// it has none).
    pub error: Vec3,
    pub is_delta: bool,
}

impl LightSample {
    /// The far end of a shadow ray from `origin` to this sample: the sampled point, moved off
    /// the light's surface toward `origin`. A point, spot, directional or environment light
    /// has no surface to shadow itself with (its normal and error are zero), and its point
    /// stays where it is.
    pub fn end_seen_from(&self, origin: Vec3) -> Vec3 {
        if self.is_delta {
            self.point
        } else {
            offset_origin(self.point, self.error, self.normal, origin - self.point)
        }
    }
}

/// A photon leaving a light: where, which way, and the flux it carries (watts per channel)
/// such that the expected sum over emitted photons is the light's power.
#[derive(Clone, Copy, Debug)]
pub struct PhotonEmission {
    pub origin: Vec3,
    pub dir: Vec3,
    /// Surface normal at the origin (zero for point and spot lights), for the ray offset.
    pub normal: Vec3,
    /// A bound on each coordinate of `origin`'s distance from the light's surface (zero where
    /// it has none), for the ray offset.
    pub error: Vec3,
    /// Flux of this one emitted photon: emitted radiance or intensity divided by the density of
    /// choosing this origin and direction.
    pub flux: Rgb,
}

#[derive(Clone, Debug)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    Directional(DirectionalLight),
    Area(AreaLight),
    Environment(EnvironmentLight),
}

impl Light {
    /// Total emitted power Φ in watts per channel.
    pub fn power(&self) -> Rgb {
        match self {
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Directional(l) => l.power(),
            Light::Area(l) => l.power(),
            Light::Environment(l) => l.power(),
        }
    }

    /// Sample a direction toward the light from `p`; the radiance is at the channels of
    /// `lambda`.
    #[inline]
    pub fn sample_li(&self, p: Vec3, u_pick: f32, u: Vec2, lambda: &Lambda) -> Option<LightSample> {
        match self {
            Light::Point(l) => l.sample_li(p, lambda),
            Light::Spot(l) => l.sample_li(p, lambda),
            Light::Directional(l) => l.sample_li(p, lambda),
            Light::Area(l) => l.sample_li(p, u_pick, u, lambda),
            Light::Environment(l) => l.sample_li(p, u, lambda),
        }
    }

    /// Emit one photon; `u_pick` chooses a shape, `u_pos` a point, `u_dir` a direction. Its
    /// flux is at the channels of `lambda`.
    pub fn emit(
        &self,
        u_pick: f32,
        u_pos: Vec2,
        u_dir: Vec2,
        lambda: &Lambda,
    ) -> Option<PhotonEmission> {
        match self {
            Light::Point(l) => Some(l.emit(u_dir, lambda)),
            Light::Spot(l) => l.emit(u_dir, lambda),
            Light::Directional(l) => l.emit(u_pick, u_pos, lambda),
            Light::Area(l) => l.emit(u_pick, u_pos, u_dir, lambda),
            Light::Environment(l) => l.emit(u_pick, u_pos, u_dir, lambda),
        }
    }

    /// Solid-angle density with which [`Light::sample_li`] from `p` picks the point `q` on the
    /// light's surface (normal `n`): what multiple importance sampling weighs a BSDF sample
    /// that hit the light against. Zero for lights with no surface a ray can hit: delta
    /// lights, which no BSDF sample finds, and the sky, which rays meet by leaving the scene
    /// (its density is [`EnvironmentLight::pdf`] of the direction).
    pub fn pdf_li(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        match self {
            Light::Area(l) => l.pdf_li(p, q, n),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Environment(_) => 0.0,
        }
    }

    /// Density with which [`Light::emit`] (after the choice of this light) sends a photon
    /// from `p` (surface normal `n`, zero off surfaces) in direction `w`: position density
    /// (per area; per area of the emission disc for lights at infinity, whose photons may
    /// start anywhere on the line) times direction density (per solid angle; 1 for a delta
    /// direction). Vertex connection and merging weighs the techniques of a path with it
    /// (Georgiev et al. 2012).
    pub fn pdf_emit(&self, p: Vec3, n: Vec3, w: Vec3) -> f32 {
        match self {
            Light::Point(_) => crate::sampling::UNIFORM_SPHERE_PDF,
            Light::Spot(l) => l.pdf_emit(w),
            Light::Directional(l) => l.aperture.density(p, w),
            Light::Area(l) => l.pdf_emit(n, w),
            Light::Environment(l) => l.pdf(-w) * l.aperture.density(p, w),
        }
    }

    /// Density with which [`Light::sample_li`] picks the point it returned, in the measure
    /// of the light's first vertex: per area on an area light (uniform by area, wherever the
    /// receiver is), per solid angle for the sky, 1 for a delta light.
    pub fn pdf_direct_area(&self, w: Vec3) -> f32 {
        match self {
            Light::Area(l) => 1.0 / l.area(),
            Light::Environment(l) => l.pdf(-w),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => 1.0,
        }
    }

    /// Lights at infinity (the sky and directional lights): their photons start on a disc,
    /// not at a point of the scene, so no distance enters their first segment's density.
    pub fn is_at_infinity(&self) -> bool {
        matches!(self, Light::Directional(_) | Light::Environment(_))
    }

    /// Where a light that shines from one point is: point and spot lights.
    pub fn point_position(&self) -> Option<Vec3> {
        match self {
            Light::Point(l) => Some(l.position),
            Light::Spot(l) => Some(l.position),
            Light::Directional(_) | Light::Area(_) | Light::Environment(_) => None,
        }
    }

    pub fn is_delta(&self) -> bool {
        !matches!(self, Light::Area(_) | Light::Environment(_))
    }

    /// Whether direct lighting at `p` samples the BSDF toward this light too, combined with
    /// the light's own samples by multiple importance sampling: always for the sky (a BSDF
    /// narrower than it is common), for an area light only where `p` is near it
    /// ([`AreaLight::is_near`]), never for delta lights (a BSDF sample cannot find them).
    pub fn is_bsdf_sampled_at(&self, p: Vec3) -> bool {
        match self {
            Light::Area(l) => l.is_near(p),
            Light::Environment(_) => true,
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => false,
        }
    }
}
