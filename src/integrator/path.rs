//! Unidirectional path tracing with next-event estimation, multiple importance sampling
//! (Veach & Guibas 1995, power heuristic) and Russian roulette: the ground truth.

use super::lighting::{light_pdf_for_hit, one_light_by_power, power_heuristic};
use super::{RayStats, Sample, ShadingPoint};
use crate::material::TransportMode;
use crate::math::{Ray, Rgb, Vec3, offset_origin};
use crate::sampling::Rng;
use crate::scene::{NO_LIGHT, Scene};

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
    rng: &mut Rng,
    stats: &mut RayStats,
) -> Sample {
    let mut out = Sample::default();
    let mut l = Rgb::ZERO;
    let mut beta = Rgb::ONE;
    let mut ray = *camera_ray;
    // Density of the BSDF sample that produced `ray`, and whether it was a delta lobe.
    let mut prev_pdf = 0.0f32;
    let mut prev_specular = true;
    let mut prev_point = ray.origin;
    stats.camera += 1;
    for depth in 0..c.max_depth {
        if depth > 0 {
            stats.bounce += 1;
        }
        let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
            if let Some((i, env)) = scene.environment() {
                let w = if prev_specular {
                    1.0
                } else {
                    power_heuristic(prev_pdf, scene.light_choice_pmf(i) * env.pdf(ray.dir))
                };
                l += beta * env.radiance(ray.dir) * w;
            }
            break;
        };
        let wo = -ray.dir;
        if hit.light != NO_LIGHT {
            let le = scene.emitted(&hit, wo);
            if le != Rgb::ZERO {
                let w = if prev_specular {
                    1.0
                } else {
                    power_heuristic(prev_pdf, light_pdf_for_hit(scene, prev_point, &hit))
                };
                l += beta * le * w;
            }
        }
        let sp = ShadingPoint::new(scene, &hit, wo);
        if !sp.material.is_specular() {
            if out.normal == Vec3::ZERO {
                // The albedo and normal AOVs: the first diffuse surface on the path.
                out.albedo = sp.material.albedo(sp.wo_local);
                out.normal = sp.frame.n;
            }
            l += beta * one_light_by_power(scene, &sp, rng, stats);
        }
        let u_lobe = rng.next_f32();
        let Some(s) =
            sp.material
                .sample(sp.wo_local, u_lobe, rng.next_2d(), TransportMode::Radiance)
        else {
            break;
        };
        beta *= s.weight;
        if beta == Rgb::ZERO {
            break;
        }
        if depth + 1 >= c.rr_depth {
            let q = beta.max_element().min(0.95);
            if rng.next_f32() >= q {
                break;
            }
            beta /= q;
        }
        let wi = sp.frame.to_world(s.wi);
        prev_pdf = s.pdf;
        prev_specular = s.is_specular();
        prev_point = hit.p;
        ray = Ray::new(offset_origin(hit.p, hit.ng, wi), wi);
    }
    out.beauty = l;
    out
}
