//! Direct lighting by ray tracing: what the original project's "SimpleRT" pass set out to do,
//! with radiometry: emission seen directly, next-event estimation of every light with several
//! samples per area light, and mirror and glass followed recursively. No indirect diffuse light.

use super::{RayStats, ShadingPoint, light_sample_contribution};
use crate::material::{Material, TransportMode};
use crate::math::{Ray, Rgb, offset_origin};
use crate::sampling::Rng;
use crate::scene::Scene;

#[derive(Clone, Debug)]
pub struct DirectConfig {
    /// Maximum number of specular bounces followed.
    pub max_depth: u32,
    /// Samples per area light at every diffuse hit (point and spot lights need one).
    pub light_samples: u32,
    /// Glass is split into both its reflected and refracted branch up to this depth, and
    /// sampled by Fresnel beyond it: less noise where it shows most.
    pub split_depth: u32,
}

impl Default for DirectConfig {
    fn default() -> Self {
        Self {
            max_depth: 16,
            light_samples: 4,
            split_depth: 2,
        }
    }
}

pub(super) fn radiance(
    c: &DirectConfig,
    scene: &Scene,
    ray: &Ray,
    rng: &mut Rng,
    stats: &mut RayStats,
) -> Rgb {
    stats.camera += 1;
    trace(c, scene, ray, 0, rng, stats)
}

fn trace(
    c: &DirectConfig,
    scene: &Scene,
    ray: &Ray,
    depth: u32,
    rng: &mut Rng,
    stats: &mut RayStats,
) -> Rgb {
    let Some(hit) = scene.intersect(ray, f32::INFINITY) else {
        return Rgb::ZERO;
    };
    let wo = -ray.dir;
    let mut l = scene.emitted(&hit, wo);
    let sp = ShadingPoint::new(scene, &hit, wo);
    match sp.material {
        Material::Lambertian(_) => l += direct_light(c, scene, &sp, rng, stats),
        Material::Mirror(_) | Material::Dielectric(_) if depth < c.max_depth => {
            l += specular(c, scene, &sp, depth, rng, stats);
        }
        _ => {}
    }
    l
}

/// Light arriving directly from every light, averaged over `light_samples` samples for area lights.
pub(crate) fn direct_light(
    c: &DirectConfig,
    scene: &Scene,
    sp: &ShadingPoint,
    rng: &mut Rng,
    stats: &mut RayStats,
) -> Rgb {
    let mut sum = Rgb::ZERO;
    for light in scene.lights() {
        let n = if light.is_delta() {
            1
        } else {
            c.light_samples.max(1)
        };
        let mut acc = Rgb::ZERO;
        for _ in 0..n {
            let u_pick = rng.next_f32();
            let Some(ls) = light.sample_li(sp.hit.p, u_pick, rng.next_2d()) else {
                continue;
            };
            if let Some((value, _)) = light_sample_contribution(scene, sp, &ls, stats) {
                acc += value;
            }
        }
        sum += acc / n as f32;
    }
    sum
}

fn specular(
    c: &DirectConfig,
    scene: &Scene,
    sp: &ShadingPoint,
    depth: u32,
    rng: &mut Rng,
    stats: &mut RayStats,
) -> Rgb {
    let follow = |wi_local, weight: Rgb, rng: &mut Rng, stats: &mut RayStats| {
        if weight == Rgb::ZERO {
            return Rgb::ZERO;
        }
        let wi = sp.frame.to_world(wi_local);
        let next = Ray::new(offset_origin(sp.hit.p, sp.hit.ng, wi), wi);
        stats.bounce += 1;
        weight * trace(c, scene, &next, depth + 1, rng, stats)
    };
    match sp.material {
        Material::Dielectric(d) if depth < c.split_depth => {
            let (reflected, refracted) = d.branches(sp.wo_local, TransportMode::Radiance);
            let mut l = follow(reflected.wi, reflected.weight, rng, stats);
            if let Some(t) = refracted {
                l += follow(t.wi, t.weight, rng, stats);
            }
            l
        }
        m => {
            let u_lobe = rng.next_f32();
            match m.sample(sp.wo_local, u_lobe, rng.next_2d(), TransportMode::Radiance) {
                Some(s) => follow(s.wi, s.weight, rng, stats),
                None => Rgb::ZERO,
            }
        }
    }
}
