//! Direct lighting by ray tracing: what the original project's "SimpleRT" pass set out to do,
//! with radiometry: emission seen directly, next-event estimation of every light with several
//! samples per area light, and mirror and glass followed recursively. No indirect diffuse light.

use super::delta::smooth_branches;
use super::lighting::{MediumPoint, direct_light, direct_light_in_medium};
use super::medium_segment::{LightsSampled, MediumSegment};
use super::{RayStats, Sample, ShadingPoint};
use crate::material::Part;
use crate::math::{Ray, Rgb, Vec3};
use crate::medium::{MediumId, spectral_mis};
use crate::sampling::Sampler;
use crate::scene::{Hit, Interaction, Scene};
use crate::spectrum::Lambda;

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
    lambda: &mut Lambda,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Sample {
    stats.camera += 1;
    // Spectral MIS in media (see `crate::medium`): the hero channel of the distances.
    let hero = scene.draw_hero_channel(rng);
    let mut walk = Walk {
        rng,
        stats,
        first_diffuse: None,
        hero,
    };
    let beauty = trace(
        c,
        scene,
        ray,
        Branch {
            depth: 0,
            weight: 1.0,
            medium: scene.camera_medium(),
            ratio: Rgb::ONE,
            lambda: *lambda,
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
struct Walk<'a, S: Sampler> {
    rng: &'a mut S,
    stats: &'a mut RayStats,
    first_diffuse: Option<(f32, Rgb, Vec3)>,
    hero: usize,
}

/// Where a branch of the camera path is: its specular depth, its largest channel weight, the
/// medium it travels in, the channels' densities of its distances over the hero's, and its
/// wavelengths (a dispersive glass on one branch leaves the others their three).
#[derive(Clone, Copy)]
struct Branch {
    depth: u32,
    weight: f32,
    medium: Option<MediumId>,
    ratio: Rgb,
    lambda: Lambda,
}

/// The light along `ray`. In a medium, a distance is sampled: light scattered once toward
/// the camera at that point (single scattering), or the surface beyond.
fn trace(
    c: &DirectConfig,
    scene: &Scene,
    ray: &Ray,
    at: Branch,
    walk: &mut Walk<impl Sampler>,
) -> Rgb {
    let step = scene.next_interaction(ray, at.medium, (walk.hero, &at.lambda), &mut *walk.rng);
    walk.stats.bounce += u64::from(step.crossings);
    // Point lights' light scattered once on the ray's first stretch through a medium, sampled
    // by distance toward them (see `MediumSegment`); free flight's light samples below are
    // weighed against it.
    let segment = MediumSegment::new(scene, &step, &at.lambda, at.ratio);
    let single = segment.as_ref().map_or(Rgb::ZERO, |s| {
        s.single_scattering(
            scene,
            LightsSampled::Each,
            &at.lambda,
            &mut *walk.rng,
            walk.stats,
        ) * spectral_mis(at.ratio)
    });
    if step.weight == Rgb::ZERO {
        return single;
    }
    let ratio = at.ratio * step.ratio;
    let (hit, medium) = match step.interaction {
        // Seen from the camera or along delta lobes: no light sample could have found it.
        Interaction::Escaped => {
            return single + step.weight * scene.escaped(ray.dir, &at.lambda) * spectral_mis(ratio);
        }
        Interaction::Scatter { p, medium } => {
            let mp = MediumPoint {
                p,
                wo: -ray.dir,
                medium,
                lambda: at.lambda,
            };
            let reached = segment.as_ref().and_then(|s| s.free_flight_point(&step, p));
            let l =
                direct_light_in_medium(c.light_samples, scene, &mp, reached, walk.rng, walk.stats);
            return single + step.weight * l * spectral_mis(ratio);
        }
        Interaction::Surface { hit, medium } => (hit, medium),
    };
    single
        + step.weight
            * surface(
                c,
                scene,
                ray,
                &hit,
                Branch {
                    medium,
                    ratio,
                    ..at
                },
                walk,
            )
}

/// Emission, direct light and the delta lobes at a surface `ray` reached.
fn surface(
    c: &DirectConfig,
    scene: &Scene,
    ray: &Ray,
    hit: &Hit,
    mut at: Branch,
    walk: &mut Walk<impl Sampler>,
) -> Rgb {
    let wo = -ray.dir;
    let mut l = scene.emitted(hit, wo, &at.lambda);
    let sp = ShadingPoint::new(scene, hit, wo, &mut at.lambda).in_medium(at.medium);
    let lobes = sp.material.lobes();
    if lobes.has_density() {
        if sp.material.has(Part::Rough) && walk.first_diffuse.is_none_or(|f| at.weight > f.0) {
            walk.first_diffuse = Some((at.weight, sp.material.albedo(sp.wo_local), sp.frame.n));
        }
        l += direct_light(c.light_samples, scene, &sp, None, walk.rng, walk.stats);
    }
    l *= spectral_mis(at.ratio);
    if lobes.is_specular() && at.depth < c.max_depth {
        l += specular(c, scene, &sp, at, walk);
    }
    l
}

/// Follow the delta lobes (see [`smooth_branches`]: every branch up to `split_depth`, one
/// sampled from every lobe beyond).
fn specular(
    c: &DirectConfig,
    scene: &Scene,
    sp: &ShadingPoint,
    at: Branch,
    walk: &mut Walk<impl Sampler>,
) -> Rgb {
    let leaving = smooth_branches(sp, Part::All, at.depth, c.split_depth, walk.rng);
    let mut l = Rgb::ZERO;
    // Lobes with a density are direct_light's.
    for b in leaving.branches.into_iter().flatten() {
        if b.glossy_pdf.is_some() || b.weight == Rgb::ZERO {
            continue;
        }
        let wi = sp.frame.to_world(b.wi);
        let next = Ray::new(sp.hit.offset_origin(wi), wi);
        walk.stats.bounce += 1;
        let branch = Branch {
            depth: at.depth + 1,
            weight: at.weight * b.weight.max_element(),
            medium: scene.medium_after(sp.hit, sp.medium, wi),
            ratio: at.ratio,
            lambda: sp.lambda,
        };
        l += b.weight * trace(c, scene, &next, branch, walk);
    }
    l
}
