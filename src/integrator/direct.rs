//! Direct lighting by ray tracing: what the original project's "SimpleRT" pass set out to do,
//! with radiometry: emission seen directly, next-event estimation of every light with several
//! samples per area light, and mirror and glass followed recursively. No indirect diffuse light.

use super::{RayStats, Sample, ShadingPoint, own_light_pdf_for_hit, power_heuristic, shadowed};
use crate::material::{Part, TransportMode};
use crate::math::{Ray, Rgb, Vec3, offset_origin};
use crate::sampling::{Rng, Sampler};
use crate::scene::{NO_LIGHT, Scene};

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
        // Seen from the camera or along delta lobes: no light sample could have found it.
        return scene.escaped(ray.dir);
    };
    let wo = -ray.dir;
    let mut l = scene.emitted(&hit, wo);
    let sp = ShadingPoint::new(scene, &hit, wo);
    let lobes = sp.material.lobes();
    if lobes.has_density() {
        if sp.material.has(Part::Rough) && walk.first_diffuse.is_none_or(|f| at.weight > f.0) {
            walk.first_diffuse = Some((at.weight, sp.material.albedo(sp.wo_local), sp.frame.n));
        }
        l += direct_light(c, scene, &sp, None, walk.rng, walk.stats);
    }
    if lobes.is_specular() && at.depth < c.max_depth {
        l += specular(c, scene, &sp, at, walk);
    }
    l
}

/// Light arriving directly from every light, averaged over `light_samples` samples for area
/// lights, through every lobe with a density.
///
/// The rough part is estimated by multiple importance sampling (Veach & Guibas 1995, power
/// heuristic, with the sample counts) where light sampling alone would be poor
/// ([`crate::light::Light::is_bsdf_sampled_at`]: the sky, and area lights seen from close by, where the 1/r²
/// of the area measure makes its variance unbounded): `light_samples` samples of each such
/// light, and samples of the rough part of the BSDF (as many under a sky, one otherwise), which
/// count the emission or sky they find there.
///
/// `continued` is the probability with which the caller's walk also samples the material's
/// smooth part here (and so may hit the same light): the smooth lobes' share of each light
/// sample is then weighted by the power heuristic against that sampling (with the sample
/// counts: n light samples, one BSDF sample), and the walk weights its emission hits by
/// [`emission_weight`]. `None`: the walk never counts emission it finds through lobes with a
/// density.
pub(crate) fn direct_light(
    c: &DirectConfig,
    scene: &Scene,
    sp: &ShadingPoint,
    continued: Option<f32>,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let m = &sp.material;
    let mis = continued.filter(|_| m.has(Part::Smooth));
    let has_smooth = m.has(Part::Smooth);
    let has_rough = m.has(Part::Rough);
    let n = c.light_samples.max(1);
    let mut sum = Rgb::ZERO;
    let mut any_bsdf_sampled = false;
    // Under a sky, which every rough point sees, as many BSDF samples as light samples (the
    // BSDF is often the narrower factor there); otherwise one, for the near area lights.
    let bsdf_samples = if scene.environment().is_some() { n } else { 1 };
    let counts = BsdfCounts {
        light: n as f32,
        bsdf: bsdf_samples as f32,
    };
    for light in scene.lights() {
        let samples = if light.is_delta() { 1 } else { n };
        let bsdf_sampled = has_rough && light.is_bsdf_sampled_at(sp.hit.p);
        any_bsdf_sampled |= bsdf_sampled;
        let mut acc = Rgb::ZERO;
        for _ in 0..samples {
            let u_pick = rng.next_f32();
            let Some(ls) = light.sample_li(sp.hit.p, u_pick, rng.next_2d()) else {
                continue;
            };
            let wi = sp.frame.to_local(ls.wi);
            let mut f = m.eval_part(sp.wo_local, wi, TransportMode::Radiance, Part::Rough);
            if bsdf_sampled {
                let p_bsdf = m.pdf_part(sp.wo_local, wi, Part::Rough);
                f *= power_heuristic(counts.light * ls.pdf, counts.bsdf * p_bsdf);
            }
            if has_smooth {
                let smooth = m.eval_part(sp.wo_local, wi, TransportMode::Radiance, Part::Smooth);
                f += match mis {
                    Some(p_continue) if !ls.is_delta => {
                        let p_bsdf = p_continue * m.pdf_part(sp.wo_local, wi, Part::Smooth);
                        smooth * power_heuristic(n as f32 * ls.pdf, p_bsdf)
                    }
                    _ => smooth,
                };
            }
            acc += shadowed(scene, sp, &ls, f, stats);
        }
        sum += acc / samples as f32;
    }
    if any_bsdf_sampled {
        let mut acc = Rgb::ZERO;
        for _ in 0..bsdf_samples {
            acc += emission_by_rough_bsdf(scene, sp, counts, rng, stats);
        }
        sum += acc / counts.bsdf;
    }
    sum
}

/// How many light samples (per light) and rough BSDF samples direct lighting takes at a point:
/// the sample counts of the power heuristic.
#[derive(Clone, Copy)]
struct BsdfCounts {
    light: f32,
    bsdf: f32,
}

/// One sample of the rough part: the emission or sky it finds, if direct lighting at this
/// point samples that light by BSDF too, weighted by the power heuristic with the counts.
fn emission_by_rough_bsdf(
    scene: &Scene,
    sp: &ShadingPoint,
    counts: BsdfCounts,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let u_lobe = rng.next_f32();
    let Some(s) = sp.material.sample_part(
        sp.wo_local,
        u_lobe,
        rng.next_2d(),
        TransportMode::Radiance,
        Part::Rough,
    ) else {
        return Rgb::ZERO;
    };
    let wi = sp.frame.to_world(s.wi);
    stats.shadow += 1;
    let ray = Ray::new(offset_origin(sp.hit.p, sp.hit.ng, wi), wi);
    let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
        return match scene.environment() {
            Some((_, sky)) => {
                s.weight
                    * sky.radiance(wi)
                    * power_heuristic(counts.bsdf * s.pdf, counts.light * sky.pdf(wi))
            }
            None => Rgb::ZERO,
        };
    };
    if hit.light == NO_LIGHT || !scene.lights()[hit.light as usize].is_bsdf_sampled_at(sp.hit.p) {
        return Rgb::ZERO;
    }
    let le = scene.emitted(&hit, -wi);
    if le == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let p_light = own_light_pdf_for_hit(scene, sp.hit.p, &hit);
    s.weight * le * power_heuristic(counts.bsdf * s.pdf, counts.light * p_light)
}

/// The MIS weight of emission found by sampling the smooth part of the previous vertex (with
/// density `p_bsdf`, selection included), against [`direct_light`]'s light samples there.
pub(crate) fn emission_weight(
    c: &DirectConfig,
    scene: &Scene,
    from: Vec3,
    hit: &crate::scene::Hit,
    p_bsdf: f32,
) -> f32 {
    let p_light = own_light_pdf_for_hit(scene, from, hit);
    power_heuristic(p_bsdf, c.light_samples.max(1) as f32 * p_light)
}

/// Light from the environment along a ray that left the scene, weighted like
/// [`emission_weight`] when it left by sampling a glossy smooth lobe with density `p_bsdf`.
pub(crate) fn escaped_radiance(
    c: &DirectConfig,
    scene: &Scene,
    dir: Vec3,
    p_bsdf: Option<f32>,
) -> Rgb {
    let Some((_, env)) = scene.environment() else {
        return Rgb::ZERO;
    };
    let w = p_bsdf.map_or(1.0, |p| {
        power_heuristic(p, c.light_samples.max(1) as f32 * env.pdf(dir))
    });
    env.radiance(dir) * w
}

/// Follow the delta lobes: every branch up to `split_depth`, one chosen by the BSDF beyond.
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
    if at.depth < c.split_depth {
        let mut l = Rgb::ZERO;
        for b in sp
            .material
            .specular_branches(sp.wo_local, TransportMode::Radiance)
            .into_iter()
            .flatten()
        {
            l += follow(b.wi, b.weight, walk);
        }
        return l;
    }
    let u_lobe = walk.rng.next_f32();
    let u = walk.rng.next_2d();
    match sp
        .material
        .sample(sp.wo_local, u_lobe, u, TransportMode::Radiance)
    {
        // Lobes with a density are direct_light's.
        Some(s) if s.is_specular() => follow(s.wi, s.weight, walk),
        _ => Rgb::ZERO,
    }
}
