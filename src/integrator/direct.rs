//! Direct lighting by ray tracing: what the original project's "SimpleRT" pass set out to do,
//! with radiometry: emission seen directly, next-event estimation of every light with several
//! samples per area light, and mirror and glass followed recursively. No indirect diffuse light.

use super::{RayStats, Sample, ShadingPoint, light_sample_contribution};
use crate::material::{Material, TransportMode};
use crate::math::{Ray, Rgb, Vec3, offset_origin};
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
) -> Sample {
    stats.camera += 1;
    let mut walk = Walk {
        rng,
        stats,
        first_diffuse: None,
    };
    let beauty = trace(
        c,
        scene,
        ray,
        Branch {
            depth: 0,
            weight: 1.0,
        },
        &mut walk,
    );
    let (albedo, normal) = walk
        .first_diffuse
        .map_or((Rgb::ZERO, Vec3::ZERO), |f| (f.1, f.2));
    Sample {
        beauty,
        albedo,
        normal,
        ..Sample::default()
    }
}

/// What a camera sample carries down every branch: its random numbers, its ray counts, and
/// the first diffuse surface met on the heaviest branch so far (weight, albedo, normal), for
/// the albedo and normal AOVs.
struct Walk<'a> {
    rng: &'a mut Rng,
    stats: &'a mut RayStats,
    first_diffuse: Option<(f32, Rgb, Vec3)>,
}

/// Where a branch of the camera path is: its specular depth and its largest channel weight.
#[derive(Clone, Copy)]
struct Branch {
    depth: u32,
    weight: f32,
}

fn trace(c: &DirectConfig, scene: &Scene, ray: &Ray, at: Branch, walk: &mut Walk) -> Rgb {
    let Some(hit) = scene.intersect(ray, f32::INFINITY) else {
        return Rgb::ZERO;
    };
    let wo = -ray.dir;
    let mut l = scene.emitted(&hit, wo);
    let sp = ShadingPoint::new(scene, &hit, wo);
    match sp.material {
        Material::Lambertian(_) => {
            if walk.first_diffuse.is_none_or(|f| at.weight > f.0) {
                walk.first_diffuse = Some((at.weight, sp.material.albedo(sp.wo_local), sp.frame.n));
            }
            l += direct_light(c, scene, &sp, walk.rng, walk.stats);
        }
        Material::Mirror(_) | Material::Dielectric(_) if at.depth < c.max_depth => {
            l += specular(c, scene, &sp, at, walk);
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
    at: Branch,
    walk: &mut Walk,
) -> Rgb {
    let follow = |wi_local, weight: Rgb, walk: &mut Walk| {
        if weight == Rgb::ZERO {
            return Rgb::ZERO;
        }
        let wi = sp.frame.to_world(wi_local);
        let next = Ray::new(offset_origin(sp.hit.p, sp.hit.ng, wi), wi);
        walk.stats.bounce += 1;
        let branch = Branch {
            depth: at.depth + 1,
            weight: at.weight * weight.max_element(),
        };
        weight * trace(c, scene, &next, branch, walk)
    };
    match sp.material {
        Material::Dielectric(d) if at.depth < c.split_depth => {
            let (reflected, refracted) = d.branches(sp.wo_local, TransportMode::Radiance);
            let mut l = follow(reflected.wi, reflected.weight, walk);
            if let Some(t) = refracted {
                l += follow(t.wi, t.weight, walk);
            }
            l
        }
        m => {
            let u_lobe = walk.rng.next_f32();
            let u = walk.rng.next_2d();
            match m.sample(sp.wo_local, u_lobe, u, TransportMode::Radiance) {
                Some(s) => follow(s.wi, s.weight, walk),
                None => Rgb::ZERO,
            }
        }
    }
}
