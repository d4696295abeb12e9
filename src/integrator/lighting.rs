//! Next-event estimation: light reaching a shading point sampled from the lights, and the
//! weights of multiple importance sampling (Veach & Guibas 1995, power heuristic) that
//! combine those samples with the BSDF's. Every integrator lights its points here; each
//! passes what it needs (its light-sample count), and none names a kind of light.

use super::medium_segment::FreeFlightPoint;
use super::{RayStats, ShadingPoint};
use crate::light::LightSample;
use crate::material::{Part, TransportMode};
use crate::math::{Ray, Rgb, Vec3, segment_reach};
use crate::medium::MediumId;
use crate::sampling::Sampler;
use crate::scene::{Hit, NO_LIGHT, Scene};
use crate::spectrum::Lambda;

/// Unoccluded contribution f·L·|cos|/pdf of one light sample, before any MIS weight; zero if
/// the light is hidden. Also returns the BSDF's density for the same direction (for MIS).
pub(crate) fn light_sample_contribution(
    scene: &Scene,
    sp: &ShadingPoint,
    ls: &LightSample,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Option<(Rgb, f32)> {
    let wi_local = sp.frame.to_local(ls.wi);
    let f = sp
        .material
        .eval(sp.wo_local, wi_local, TransportMode::Radiance);
    if f == Rgb::ZERO {
        return None;
    }
    let value = shadowed(scene, sp, ls, f, rng, stats);
    (value != Rgb::ZERO).then(|| (value, sp.material.pdf(sp.wo_local, wi_local)))
}

/// f·L·|cos|/pdf of one light sample for the BSDF value `f`, or zero if the light is hidden
/// (times the transmittance of the media between, in a scene with media).
pub(crate) fn shadowed(
    scene: &Scene,
    sp: &ShadingPoint,
    ls: &LightSample,
    f: Rgb,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    if f == Rgb::ZERO {
        return Rgb::ZERO;
    }
    stats.shadow += 1;
    let tr = visibility(scene, sp, ls, rng);
    if tr == Rgb::ZERO {
        return Rgb::ZERO;
    }
    f * tr * ls.radiance * (sp.frame.n.dot(ls.wi).abs() / ls.pdf)
}

/// The fraction of the light sample's light that reaches the shading point: one or zero
/// (whether the segment between them is free), or the transmittance of the media along it.
/// Both ends are moved off their surfaces (the light's end toward the shading point), and
/// the ray runs between the moved ends: reusing the direction and length measured from the
/// unmoved point made the segment cross the light's own plane when a surface saw the light at
/// a grazing angle, so the light shadowed itself (a patch beside a quad light lost 63% of its
/// irradiance).
fn visibility(scene: &Scene, sp: &ShadingPoint, ls: &LightSample, rng: &mut impl Sampler) -> Rgb {
    let hit = sp.hit;
    let origin = hit.offset_origin(ls.wi);
    if scene.has_media() {
        let medium = scene.medium_after(hit, sp.medium, ls.wi);
        return scene.transmittance(origin, ls.end_seen_from(origin), medium, &sp.lambda, rng);
    }
    let free = if ls.is_delta {
        let dist = (ls.point - origin).length();
        !scene.occluded(origin, ls.wi, segment_reach(origin, ls.point, dist))
    } else {
        scene.segment_is_clear(origin, ls.end_seen_from(origin))
    };
    if free { Rgb::ONE } else { Rgb::ZERO }
}

/// A point where light scatters in a medium, seen from direction `wo`.
pub(crate) struct MediumPoint {
    pub p: Vec3,
    pub wo: Vec3,
    pub medium: MediumId,
    /// The wavelengths of the path that scattered here.
    pub lambda: Lambda,
}

/// phase·L·Tr/pdf of one light sample at a point in a medium (no cosine: a medium has no
/// surface), and the phase function's density for the same direction (for MIS).
fn in_scattered(
    scene: &Scene,
    mp: &MediumPoint,
    ls: &LightSample,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> (Rgb, f32) {
    let phase = scene.medium(mp.medium).phase().eval(mp.wo, ls.wi);
    if phase == 0.0 || ls.pdf == 0.0 {
        return (Rgb::ZERO, phase);
    }
    stats.shadow += 1;
    let end = ls.end_seen_from(mp.p);
    let tr = scene.transmittance(mp.p, end, Some(mp.medium), &mp.lambda, rng);
    (tr * ls.radiance * (phase / ls.pdf), phase)
}

/// One light, chosen by power, sampled once from a point in a medium; MIS-weighted against
/// sampling the phase function for lights with an area (the path tracer's next-event
/// estimation in media, Pharr et al. 2016 §15.3).
///
/// `reached`: the point as free flight found it on a stretch whose point lights' light is
/// also sampled by distance ([`super::medium_segment::MediumSegment`]); a sample of a point or
/// spot light is then weighted against that.
pub(crate) fn one_light_in_medium(
    scene: &Scene,
    mp: &MediumPoint,
    reached: Option<FreeFlightPoint>,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let Some((i, ls)) = light_by_power(scene, mp.p, &mp.lambda, rng) else {
        return Rgb::ZERO;
    };
    let (value, phase_pdf) = in_scattered(scene, mp, &ls, rng, stats);
    if !ls.is_delta {
        return value * power_heuristic(ls.pdf, phase_pdf);
    }
    value * reached.map_or(1.0, |r| r.weight(&scene.lights()[i]))
}

/// Light arriving directly at a point in a medium from every light, `light_samples` samples
/// for those with an area: single scattering, for the `direct` integrator and the
/// progressive methods' camera paths. `reached` as for [`one_light_in_medium`], with
/// [`super::medium_segment::LightsSampled::Each`].
pub(crate) fn direct_light_in_medium(
    light_samples: u32,
    scene: &Scene,
    mp: &MediumPoint,
    reached: Option<FreeFlightPoint>,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let mut sum = Rgb::ZERO;
    for light in scene.lights() {
        let samples = if light.is_delta() {
            1
        } else {
            light_samples.max(1)
        };
        let mut acc = Rgb::ZERO;
        for _ in 0..samples {
            let u_pick = rng.next_f32();
            if let Some(ls) = light.sample_li(mp.p, u_pick, rng.next_2d(), &mp.lambda) {
                acc += in_scattered(scene, mp, &ls, rng, stats).0;
            }
        }
        let weight = reached.map_or(1.0, |r| r.weight(light));
        sum += acc * weight / samples as f32;
    }
    sum
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
/// from `from` (no choice between lights: [`direct_light`] samples every light).
fn own_light_pdf_for_hit(scene: &Scene, from: Vec3, hit: &Hit) -> f32 {
    scene.lights()[hit.light as usize].pdf_li(from, hit.p, hit.ng)
}

/// Light arriving directly from every light, averaged over `light_samples` samples for area
/// lights and the sky, through every lobe with a density.
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
    light_samples: u32,
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
    let n = light_samples.max(1);
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
            let Some(ls) = light.sample_li(sp.hit.p, u_pick, rng.next_2d(), &sp.lambda) else {
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
            acc += shadowed(scene, sp, &ls, f, rng, stats);
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
    let ray = Ray::new(sp.hit.offset_origin(wi), wi);
    let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
        return match scene.environment() {
            Some((_, sky)) => {
                s.weight
                    * sky.radiance(wi, &sp.lambda)
                    * power_heuristic(counts.bsdf * s.pdf, counts.light * sky.pdf(wi))
            }
            None => Rgb::ZERO,
        };
    };
    if hit.light == NO_LIGHT || !scene.lights()[hit.light as usize].is_bsdf_sampled_at(sp.hit.p) {
        return Rgb::ZERO;
    }
    let le = scene.emitted(&hit, -wi, &sp.lambda);
    if le == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let p_light = own_light_pdf_for_hit(scene, sp.hit.p, &hit);
    s.weight * le * power_heuristic(counts.bsdf * s.pdf, counts.light * p_light)
}

/// The MIS weight of emission found by sampling the smooth part of the previous vertex (with
/// density `p_bsdf`, selection included), against [`direct_light`]'s light samples there.
pub(crate) fn emission_weight(
    light_samples: u32,
    scene: &Scene,
    from: Vec3,
    hit: &Hit,
    p_bsdf: f32,
) -> f32 {
    let p_light = own_light_pdf_for_hit(scene, from, hit);
    power_heuristic(p_bsdf, light_samples.max(1) as f32 * p_light)
}

/// Light from the environment along a ray that left the scene, weighted like
/// [`emission_weight`] when it left by sampling a glossy smooth lobe with density `p_bsdf`.
pub(crate) fn escaped_radiance(
    light_samples: u32,
    scene: &Scene,
    dir: Vec3,
    p_bsdf: Option<f32>,
    lambda: &Lambda,
) -> Rgb {
    let Some((_, env)) = scene.environment() else {
        return Rgb::ZERO;
    };
    let w = p_bsdf.map_or(1.0, |p| {
        power_heuristic(p, light_samples.max(1) as f32 * env.pdf(dir))
    });
    env.radiance(dir, lambda) * w
}

/// A sample of one light chosen by power, seen from `p`, and the light's index; the sample's
/// density includes the choice.
#[inline]
fn light_by_power(
    scene: &Scene,
    p: Vec3,
    lambda: &Lambda,
    rng: &mut impl Sampler,
) -> Option<(usize, LightSample)> {
    // The position on the light first: it is what stratified numbers help most.
    let u = rng.next_2d();
    let u_choose = rng.next_f32();
    let u_pick = rng.next_f32();
    let (i, pmf, _) = scene.choose_light(u_choose)?;
    let mut ls = scene.lights()[i].sample_li(p, u_pick, u, lambda)?;
    ls.pdf *= pmf;
    Some((i, ls))
}

/// One light, chosen by power, sampled once; MIS-weighted against BSDF sampling for area lights.
pub(crate) fn one_light_by_power(
    scene: &Scene,
    sp: &ShadingPoint,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let Some((_, ls)) = light_by_power(scene, sp.hit.p, &sp.lambda, rng) else {
        return Rgb::ZERO;
    };
    let Some((value, bsdf_pdf)) = light_sample_contribution(scene, sp, &ls, rng, stats) else {
        return Rgb::ZERO;
    };
    if ls.is_delta {
        value
    } else {
        value * power_heuristic(ls.pdf, bsdf_pdf)
    }
}
