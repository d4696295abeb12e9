//! The photon integrator's rays through media: the transmittance to the surface a ray
//! reaches and the light the media along it scatter toward its origin, by the beam radiance
//! estimate over the volume photons (Jarosz, Zwicker and Jensen 2008).

use super::PhotonIntegrator;
use crate::integrator::RayStats;
use crate::math::{Ray, Rgb};
use crate::medium::{MediumAt, MediumId, TransmittanceProfile};
use crate::photon::Kernel;
use crate::photon::beam::VolumePhotonMap;
use crate::sampling::Sampler;
use crate::scene::{MAX_CROSSINGS, Scene};
use crate::spectrum::Lambda;

impl PhotonIntegrator {
    /// Follow `ray`, which starts in `medium`, to the first surface that is there, crossing
    /// invisible boundaries: the transmittance to it and the light the media along the way
    /// scatter toward the ray's origin, by the beam radiance estimate over each segment in a
    /// medium, at the path's channels `lambda`. Without media: the closest hit, transmittance
    /// one, nothing drawn.
    pub(super) fn through_media(
        &self,
        scene: &Scene,
        ray: &Ray,
        mut medium: Option<MediumId>,
        lambda: &Lambda,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Passage {
        let mut passage = Passage {
            hit: scene.intersect(ray, f32::INFINITY),
            medium,
            transmittance: Rgb::ONE,
            in_scattered: Rgb::ZERO,
        };
        if !scene.has_media() {
            return passage;
        }
        let mut ray = *ray;
        for _ in 0..=MAX_CROSSINGS {
            let t_max = passage.hit.map_or(f32::INFINITY, |h| h.t);
            if let Some(id) = medium {
                let m = scene.medium(id).at(lambda);
                let profile = m.transmittance_profile(&ray, t_max, rng);
                let scatters = scene.medium(id).scatters();
                if let Some(map) = self.volume.as_deref().filter(|_| scatters) {
                    let kernel = self.settings.global.kernel;
                    let segment = Segment {
                        ray: &ray,
                        t_max,
                        id,
                        medium: &m,
                        profile: &profile,
                    };
                    passage.in_scattered +=
                        passage.transmittance * beam_estimate(map, &segment, kernel, lambda);
                }
                passage.transmittance *= profile.at(t_max);
            }
            match passage.hit {
                Some(h) if scene.is_invisible(&h) => {
                    medium = scene.medium_after(&h, medium, ray.dir);
                    ray = Ray::new(h.offset_origin(ray.dir), ray.dir);
                    stats.bounce += 1;
                    passage.hit = scene.intersect(&ray, f32::INFINITY);
                    passage.medium = medium;
                }
                _ => return passage,
            }
        }
        passage.hit = None;
        passage.transmittance = Rgb::ZERO;
        passage
    }
}

/// Where a ray through media arrives (see [`PhotonIntegrator::through_media`]).
pub(super) struct Passage {
    pub hit: Option<crate::scene::Hit>,
    /// The medium the hit was reached through.
    pub medium: Option<MediumId>,
    pub transmittance: Rgb,
    pub in_scattered: Rgb,
}

/// A ray's segment in one medium: up to `t_max`, in medium `id` (seen at the path's
/// channels), with the transmittance along it.
struct Segment<'a> {
    ray: &'a Ray,
    t_max: f32,
    id: MediumId,
    medium: &'a MediumAt<'a>,
    profile: &'a TransmittanceProfile,
}

/// The beam radiance estimate over a segment (Jarosz et al. 2008): Σ K(d) σs(x) p(wo, wi)
/// Φ/σs Tr(t) over the photons of its medium whose spheres the segment passes, x the point
/// of the ray nearest the photon, at distance t and d from it, with the 2D kernel K
/// normalised on the disc of each photon's radius (the global map's kernel). Photon powers
/// are stored over σs where they scattered (see `photon::trace`), in RGB: a spectral path
/// reads each as light (as it reads the surface maps' estimates).
fn beam_estimate(map: &VolumePhotonMap, segment: &Segment, kernel: Kernel, lambda: &Lambda) -> Rgb {
    let (ray, medium) = (segment.ray, segment.medium);
    let wo = -ray.dir;
    let mut sum = Rgb::ZERO;
    map.for_each_along(ray, 0.0, segment.t_max, &mut |p, t, d2| {
        if p.medium != segment.id {
            return;
        }
        let x = ray.at(t);
        let weight = kernel.weight(d2, p.radius * p.radius);
        sum += lambda.illuminant(p.power)
            * medium.sigma_s_at(x)
            * segment.profile.at(t)
            * (weight * medium.phase().eval(wo, p.incoming));
    });
    sum * map.power_scale
}
