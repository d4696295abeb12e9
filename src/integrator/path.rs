//! Unidirectional path tracing with next-event estimation, multiple importance sampling
//! (Veach & Guibas 1995, power heuristic) and Russian roulette: the ground truth.

use super::lighting::{
    MediumPoint, light_pdf_for_hit, one_light_by_power, one_light_in_medium, power_heuristic,
};
use super::medium_segment::{LightsSampled, MediumSegment};
use super::{RayStats, Sample, ShadingPoint};
use crate::material::TransportMode;
use crate::math::{Ray, Rgb, Vec3};
use crate::medium::spectral_mis;
use crate::sampling::Sampler;
use crate::scene::{Interaction, NO_LIGHT, Scene};
use crate::spectrum::Lambda;

#[derive(Clone, Debug)]
pub struct PathConfig {
    /// Maximum number of surface interactions on a path.
    pub max_depth: u32,
    /// Russian roulette starts after this many bounces.
    pub rr_depth: u32,
}

impl Default for PathConfig {
    fn default() -> Self {
        Self {
            max_depth: 256,
            rr_depth: 6,
        }
    }
}

pub(super) fn radiance(
    c: &PathConfig,
    scene: &Scene,
    camera_ray: &Ray,
    lambda: &mut Lambda,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Sample {
    let mut out = Sample::default();
    let mut l = Rgb::ZERO;
    let mut beta = Rgb::ONE;
    // The product of eta² over the refractions so far, which undoes their 1/eta² in `beta`
    // for Russian roulette: radiance compressed inside glass is no less likely to matter.
    let mut eta_scale = 1.0f32;
    let mut ray = *camera_ray;
    let mut medium = scene.camera_medium();
    // Spectral MIS in media (see `crate::medium`): the hero channel distances are drawn
    // with, and each channel's density of them over the hero's. Contributions are divided by
    // the mean ratio.
    let hero = scene.draw_hero_channel(rng);
    let mut ratio = Rgb::ONE;
    // Density of the BSDF or phase sample that produced `ray`, and whether it was a delta lobe.
    let mut prev_pdf = 0.0f32;
    let mut prev_specular = true;
    let mut prev_point = ray.origin;
    stats.camera += 1;
    for depth in 0..c.max_depth {
        if depth > 0 {
            stats.bounce += 1;
        }
        let step = scene.next_interaction(&ray, medium, (hero, lambda), rng);
        stats.bounce += u64::from(step.crossings);
        // Point lights' light scattered once on the ray's first stretch through a medium,
        // sampled by distance toward them (see `MediumSegment`).
        let segment = MediumSegment::new(scene, &step, lambda, ratio);
        if let Some(segment) = &segment {
            l += beta
                * segment.single_scattering(scene, LightsSampled::OneByPower, lambda, rng, stats)
                * spectral_mis(ratio);
        }
        beta *= step.weight;
        ratio *= step.ratio;
        let mis = spectral_mis(ratio);
        let (hit, reached_through) = match step.interaction {
            Interaction::Escaped => {
                if let Some((i, env)) = scene.environment() {
                    let w = if prev_specular {
                        1.0
                    } else {
                        power_heuristic(prev_pdf, scene.light_choice_pmf(i) * env.pdf(ray.dir))
                    };
                    l += beta * env.radiance(ray.dir, lambda) * (w * mis);
                }
                break;
            }
            Interaction::Scatter { p, medium: m } => {
                // Volumetric path tracing (Pharr et al. 2016, §15.3): light sampled at the
                // scattering point, then a direction drawn from the phase function.
                if beta == Rgb::ZERO {
                    break;
                }
                let mp = MediumPoint {
                    p,
                    wo: -ray.dir,
                    medium: m,
                    lambda: *lambda,
                };
                let reached = segment.as_ref().and_then(|s| s.free_flight_point(&step, p));
                l += beta * one_light_in_medium(scene, &mp, reached, rng, stats) * mis;
                let s = scene.medium(m).phase().sample(mp.wo, rng.next_2d());
                if !survives_roulette(c, depth, &mut beta, eta_scale * mis, rng) {
                    break;
                }
                prev_pdf = s.pdf;
                prev_specular = false;
                prev_point = p;
                ray = Ray::new(p, s.wi);
                medium = Some(m);
                continue;
            }
            Interaction::Surface { hit, medium } => (hit, medium),
        };
        let wo = -ray.dir;
        if hit.light != NO_LIGHT {
            let le = scene.emitted(&hit, wo, lambda);
            if le != Rgb::ZERO {
                let w = if prev_specular {
                    1.0
                } else {
                    power_heuristic(prev_pdf, light_pdf_for_hit(scene, prev_point, &hit))
                };
                l += beta * le * (w * mis);
            }
        }
        let sp = ShadingPoint::new(scene, &hit, wo, lambda).in_medium(reached_through);
        if !sp.material.is_specular() {
            if out.normal == Vec3::ZERO {
                // The albedo and normal AOVs: the first diffuse surface on the path.
                out.albedo = sp.material.albedo(sp.wo_local);
                out.normal = sp.frame.n;
            }
            l += beta * one_light_by_power(scene, &sp, rng, stats) * mis;
        }
        let u_lobe = rng.next_f32();
        let Some(s) =
            sp.material
                .sample(sp.wo_local, u_lobe, rng.next_2d(), TransportMode::Radiance)
        else {
            break;
        };
        beta *= s.weight;
        eta_scale *= s.eta * s.eta;
        if beta == Rgb::ZERO || !survives_roulette(c, depth, &mut beta, eta_scale * mis, rng) {
            break;
        }
        let wi = sp.frame.to_world(s.wi);
        prev_pdf = s.pdf;
        prev_specular = s.is_specular();
        prev_point = hit.p;
        medium = scene.medium_after(&hit, reached_through, wi);
        ray = Ray::new(hit.offset_origin(wi), wi);
    }
    out.beauty = l;
    out
}

/// Russian roulette from `rr_depth` on, on the throughput `beta` times `scale` (the path's
/// spectral MIS factor and the eta² of its refractions; pbrt-v4 §14.1.4): the path goes on
/// with probability min(max, 0.95), its throughput divided by it.
fn survives_roulette(
    c: &PathConfig,
    depth: u32,
    beta: &mut Rgb,
    scale: f32,
    rng: &mut impl Sampler,
) -> bool {
    if depth + 1 < c.rr_depth {
        return true;
    }
    let q = (beta.max_element() * scale).min(0.95);
    if rng.next_f32() >= q {
        return false;
    }
    *beta /= q;
    true
}
