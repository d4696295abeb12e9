//! Camera paths to their first rough surface: the "visible points" of progressive photon
//! mapping (Hachisuka et al. 2008), with the light that needs no photons gathered on the way.

use super::delta::{smooth_branches, stop_probability};
use super::lighting::{
    MediumPoint, direct_light, direct_light_in_medium, emission_weight, escaped_radiance,
};
use super::medium_segment::{LightsSampled, MediumSegment};
use super::{RayStats, ShadingPoint};
use crate::material::{Material, Part, TransportMode};
use crate::math::{Frame, Ray, Rgb, Vec3};
use crate::medium::{MediumId, spectral_mis};
use crate::sampling::Sampler;
use crate::scene::{Interaction, Scene};
use crate::spectrum::Lambda;

/// Where a camera path stopped on a rough surface.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint {
    pub p: Vec3,
    pub frame: Frame,
    pub wo_local: Vec3,
    /// The geometric normal on the side of the camera path (see [`crate::scene::Hit::ng_facing`]).
    pub ng: Vec3,
    /// The material at the point, textures resolved; photons are evaluated with its rough part.
    pub material: Material,
    /// Throughput of the path from the camera, divided by the probabilities of its choices.
    pub beta: Rgb,
    /// Length of the path from the camera (for the pixel footprint).
    pub distance: f32,
    /// Whether a dispersive glass on the way left the path its hero wavelength alone (see
    /// [`Lambda::keep_hero_only`]).
    pub hero_only: bool,
}

/// Where a camera path stopped at a scattering point in a medium.
#[derive(Clone, Copy, Debug)]
pub struct VolumePoint {
    pub p: Vec3,
    /// Toward the camera.
    pub wo: Vec3,
    pub medium: MediumId,
    /// Throughput of the path from the camera, σs of the scattering included, divided by the
    /// probabilities of its choices.
    pub beta: Rgb,
    /// Length of the path from the camera (for the pixel footprint).
    pub distance: f32,
    /// Whether a dispersive glass on the way left the path its hero wavelength alone (see
    /// [`Lambda::keep_hero_only`]).
    pub hero_only: bool,
}

/// A camera path: emission seen through mirrors and glass plus direct light (next-event
/// estimation) at the visible point, both weighted by the path throughput, and the point: on
/// a surface or in a medium.
#[derive(Clone, Copy, Debug, Default)]
pub struct CameraPath {
    pub direct: Rgb,
    pub visible: Option<VisiblePoint>,
    pub volume: Option<VolumePoint>,
}

/// Follow `ray` along the smooth parts of materials (see [`Part`]) to a point where it stops
/// on a rough part. At a material with both parts the path stops with the probability q of the
/// rough part's share of the albedo and follows the smooth part otherwise, dividing by the
/// probability taken, so that one visible point per path stays unbiased.
///
/// Light found along delta lobes alone (the light seen in a mirror or through glass) is
/// summed over both branches of glass for the first [`SPLIT_DEPTH`] bounces instead (see
/// [`DeltaChain`]), except in scenes with media.
///
/// In a medium a distance is sampled (see [`Scene::next_interaction`]); a path that scatters
/// there stops at a [`VolumePoint`], with the light arriving there directly: a medium is
/// rough everywhere, as a diffuse surface is (Knaus and Zwicker 2011 treat media so).
///
/// The path carries the channels of `lambda` (a progressive pass's wavelengths).
pub fn trace_camera_path<S: Sampler>(
    scene: &Scene,
    ray: &Ray,
    lambda: Lambda,
    max_depth: u32,
    light_samples: u32,
    rng: &mut S,
    stats: &mut RayStats,
) -> CameraPath {
    let mut out = CameraPath::default();
    let mut beta = Rgb::ONE;
    let mut ray = *ray;
    let mut distance = 0.0;
    // The previous point and the density of the glossy sample that left it, for MIS.
    let mut arrival: Option<(Vec3, f32)> = None;
    // While every bounce has been along a delta lobe: the weight of the light found. The
    // branches are traced without media, so scenes with media follow one branch.
    let mut chain = (!scene.has_media()).then_some(DeltaChain { weight: Rgb::ONE });
    let mut medium = scene.camera_medium();
    // Spectral MIS in media (see `crate::medium`).
    let hero = scene.draw_hero_channel(rng);
    let mut ratio = Rgb::ONE;
    let mut lambda = lambda;
    stats.camera += 1;
    for depth in 0..=max_depth {
        let step = scene.next_interaction(&ray, medium, (hero, &lambda), rng);
        stats.bounce += u64::from(step.crossings);
        // Point lights' light scattered once on the ray's first stretch through a medium,
        // sampled by distance toward them (see `MediumSegment`); free flight's light samples
        // below are weighed against it.
        let segment = MediumSegment::new(scene, &step, &lambda, ratio);
        if let Some(segment) = &segment {
            let single = segment.single_scattering(scene, LightsSampled::Each, &lambda, rng, stats);
            out.direct += beta * single * spectral_mis(ratio);
        }
        beta *= step.weight;
        ratio *= step.ratio;
        let mis = spectral_mis(ratio);
        let (hit, reached_through) = match step.interaction {
            Interaction::Escaped => {
                let w = chain.map_or(beta * mis, |d| d.weight);
                let sky =
                    escaped_radiance(light_samples, scene, ray.dir, arrival.map(|a| a.1), &lambda);
                out.direct += w * sky;
                return out;
            }
            Interaction::Scatter { p, medium } => {
                let mp = MediumPoint {
                    p,
                    wo: -ray.dir,
                    medium,
                    lambda,
                };
                let beta = beta * mis;
                let reached = segment.as_ref().and_then(|s| s.free_flight_point(&step, p));
                let direct = direct_light_in_medium(light_samples, scene, &mp, reached, rng, stats);
                out.direct += beta * direct;
                out.volume = Some(VolumePoint {
                    p,
                    wo: mp.wo,
                    medium,
                    beta,
                    distance: distance + (p - ray.origin).length(),
                    hero_only: lambda.is_hero_only(),
                });
                return out;
            }
            Interaction::Surface { hit, medium } => (hit, medium),
        };
        distance += if step.crossings == 0 {
            hit.t
        } else {
            (hit.p - ray.origin).length()
        };
        let wo = -ray.dir;
        let mut le = scene.emitted(&hit, wo, &lambda);
        if let Some((from, p_bsdf)) = arrival
            && le != Rgb::ZERO
        {
            le *= emission_weight(light_samples, scene, from, &hit, p_bsdf);
        }
        out.direct += chain.map_or(beta * mis, |d| d.weight) * le;
        let sp = ShadingPoint::new(scene, &hit, wo, &mut lambda).in_medium(reached_through);
        let m = &sp.material;
        let may_go_on = depth < max_depth;
        // Only the delta branches of the first bounces are summed; deeper ones are sampled.
        let split = chain.filter(|_| depth < SPLIT_DEPTH && may_go_on);
        // The light along the delta branches here other than the one followed (all of them
        // when the path stops here).
        let other_branches = |followed: Option<Vec3>, rng: &mut S, stats: &mut RayStats| {
            split.map_or(Rgb::ZERO, |d| {
                let mut walk = DeltaWalk::new(scene, max_depth, rng, stats);
                d.branches(&mut walk, &sp, followed, depth)
            })
        };
        let stop = stop_probability(m, sp.wo_local, may_go_on);
        if m.lobes().has_density() {
            out.direct +=
                beta * mis * direct_light(light_samples, scene, &sp, Some(1.0 - stop), rng, stats);
        }
        if stop > 0.0 && (stop >= 1.0 || rng.next_f32() < stop) {
            out.direct += other_branches(None, rng, stats);
            out.visible = Some(VisiblePoint {
                p: hit.p,
                frame: sp.frame,
                wo_local: sp.wo_local,
                ng: sp.ng,
                material: sp.material,
                beta: beta * mis / stop,
                distance,
                hero_only: lambda.is_hero_only(),
            });
            return out;
        }
        if !may_go_on {
            return out;
        }
        let u_lobe = rng.next_f32();
        let Some(s) = m.sample_part(
            sp.wo_local,
            u_lobe,
            rng.next_2d(),
            TransportMode::Radiance,
            Part::Smooth,
        ) else {
            out.direct += other_branches(None, rng, stats);
            return out;
        };
        let go_on = 1.0 - stop;
        chain = match (chain, split) {
            _ if !s.is_specular() => None,
            (_, Some(d)) => {
                out.direct += other_branches(Some(s.wi), rng, stats);
                Some(d.followed(&sp, s.wi))
            }
            (Some(d), None) => Some(DeltaChain {
                weight: d.weight * s.weight / go_on,
            }),
            (None, None) => None,
        };
        beta *= s.weight / go_on;
        arrival = (!s.is_specular()).then_some((hit.p, go_on * s.pdf));
        let wi = sp.frame.to_world(s.wi);
        medium = scene.medium_after(&hit, reached_through, wi);
        ray = Ray::new(hit.offset_origin(wi), wi);
        stats.bounce += 1;
    }
    out
}

/// Glass is split into both its branches for the first bounces of a delta chain, and sampled
/// by Fresnel beyond (as in the `direct` integrator).
const SPLIT_DEPTH: u32 = 2;

/// A camera path whose bounces have all been along delta lobes, and the weight with which it
/// counts the light it finds.
///
/// One visible point per path means the path follows one branch of glass, chosen by Fresnel.
/// The light it finds along delta lobes alone, though, needs no visible point. So for the first
/// [`SPLIT_DEPTH`] bounces the branches not followed are traced for that light alone, each
/// with its own weight, and the branch followed counts it with its own weight too, not divided
/// by the probability of choosing it: every branch counts with its weight whatever the choice,
/// which is unbiased and leaves no variance in the choice. Without this the light seen in the
/// glass sphere (through an internal reflection of a few per cent) arrived whole in a few
/// passes and not at all in the rest: on `cornell` it was most of the camera side's variance.
#[derive(Clone, Copy, Debug)]
struct DeltaChain {
    weight: Rgb,
}

impl DeltaChain {
    /// The light along the delta branches at `sp` other than the one toward `followed` (local
    /// direction; `None`: all of them), each with its weight.
    fn branches(
        self,
        walk: &mut DeltaWalk,
        sp: &ShadingPoint,
        followed: Option<Vec3>,
        depth: u32,
    ) -> Rgb {
        let mut l = Rgb::ZERO;
        for b in sp
            .material
            .specular_branches(sp.wo_local, TransportMode::Radiance)
            .into_iter()
            .flatten()
            .filter(|b| followed.is_none_or(|wi| !same_side(b.wi, wi)))
        {
            l += branch_emission(walk, sp, b.wi, b.weight, depth + 1);
        }
        self.weight * l
    }

    /// The chain after following the delta branch toward `wi` (local direction).
    fn followed(self, sp: &ShadingPoint, wi: Vec3) -> DeltaChain {
        let branch = sp
            .material
            .specular_branches(sp.wo_local, TransportMode::Radiance)
            .into_iter()
            .flatten()
            .find(|b| same_side(b.wi, wi));
        DeltaChain {
            weight: self.weight * branch.map_or(Rgb::ZERO, |b| b.weight),
        }
    }
}

/// Whether two local directions leave on the same side of the surface: the two delta branches
/// of glass do not, so this tells which one a sample took.
fn same_side(a: Vec3, b: Vec3) -> bool {
    (a.z > 0.0) == (b.z > 0.0)
}

/// The light arriving at `sp` from local direction `wi` along delta lobes alone, times
/// `weight`: emission and sky found through mirrors and glass. `depth` is the depth of the hit
/// it finds; from there every branch is followed while it is below [`SPLIT_DEPTH`], one sampled
/// beyond (see [`smooth_branches`]).
fn branch_emission(
    walk: &mut DeltaWalk,
    sp: &ShadingPoint,
    wi_local: Vec3,
    weight: Rgb,
    depth: u32,
) -> Rgb {
    if weight == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let scene = walk.scene;
    let wi = sp.frame.to_world(wi_local);
    let ray = Ray::new(sp.hit.offset_origin(wi), wi);
    walk.stats.bounce += 1;
    let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
        return weight * scene.escaped(wi, &sp.lambda);
    };
    let mut lambda = sp.lambda;
    let next = ShadingPoint::new(scene, &hit, -wi, &mut lambda);
    let mut l = scene.emitted(&hit, -wi, &sp.lambda);
    let m = &next.material;
    if depth < walk.max_depth && m.lobes().is_specular() {
        let leaving = smooth_branches(&next, Part::Smooth, depth, SPLIT_DEPTH, &mut *walk.rng);
        // Paths that leave along a lobe with a density are not delta chains.
        for b in leaving.branches.into_iter().flatten() {
            if b.glossy_pdf.is_none() {
                l += branch_emission(walk, &next, b.wi, b.weight, depth + 1);
            }
        }
    }
    weight * l
}

/// What [`branch_emission`]'s recursion carries: the scene, the depth limit, and the camera
/// path's random numbers and ray counts.
struct DeltaWalk<'a> {
    scene: &'a Scene,
    max_depth: u32,
    rng: &'a mut dyn Sampler,
    stats: &'a mut RayStats,
}

impl<'a> DeltaWalk<'a> {
    fn new(
        scene: &'a Scene,
        max_depth: u32,
        rng: &'a mut dyn Sampler,
        stats: &'a mut RayStats,
    ) -> Self {
        Self {
            scene,
            max_depth,
            rng,
            stats,
        }
    }
}
