//! Camera paths to their first rough surface: the "visible points" of progressive photon
//! mapping (Hachisuka et al. 2008), with the light that needs no photons gathered on the way.

use super::direct::{DirectConfig, direct_light, emission_weight, escaped_radiance};
use super::{RayStats, ShadingPoint};
use crate::material::{Material, Part, TransportMode};
use crate::math::{Frame, Ray, Rgb, Vec3, offset_origin};
use crate::sampling::Rng;
use crate::scene::Scene;

/// Where a camera path stopped on a rough surface.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint {
    pub p: Vec3,
    pub frame: Frame,
    pub wo_local: Vec3,
    /// The material at the point, textures resolved; photons are evaluated with its rough part.
    pub material: Material,
    /// Throughput of the path from the camera, divided by the probabilities of its choices.
    pub beta: Rgb,
    /// Length of the path from the camera (for the pixel footprint).
    pub distance: f32,
}

/// A camera path: emission seen through mirrors and glass plus direct light (next-event
/// estimation) at the visible point, both weighted by the path throughput, and the point.
#[derive(Clone, Copy, Debug, Default)]
pub struct CameraPath {
    pub direct: Rgb,
    pub visible: Option<VisiblePoint>,
}

/// Follow `ray` along the smooth parts of materials (see [`Part`]) to a point where it stops
/// on a rough part. At a material with both parts the path stops with the probability q of the
/// rough part's share of the albedo and follows the smooth part otherwise, dividing by the
/// probability taken, so that one visible point per path stays unbiased.
pub fn trace_camera_path(
    scene: &Scene,
    ray: &Ray,
    max_depth: u32,
    light_samples: u32,
    rng: &mut Rng,
    stats: &mut RayStats,
) -> CameraPath {
    let mut out = CameraPath::default();
    let mut beta = Rgb::ONE;
    let mut ray = *ray;
    let mut distance = 0.0;
    let c = DirectConfig {
        light_samples,
        ..DirectConfig::default()
    };
    // The previous point and the density of the glossy sample that left it, for MIS.
    let mut arrival: Option<(Vec3, f32)> = None;
    stats.camera += 1;
    for depth in 0..=max_depth {
        let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
            out.direct += beta * escaped_radiance(&c, scene, ray.dir, arrival.map(|a| a.1));
            return out;
        };
        distance += hit.t;
        let wo = -ray.dir;
        let mut le = scene.emitted(&hit, wo);
        if let Some((from, p_bsdf)) = arrival
            && le != Rgb::ZERO
        {
            le *= emission_weight(&c, scene, from, &hit, p_bsdf);
        }
        out.direct += beta * le;
        let sp = ShadingPoint::new(scene, &hit, wo);
        let m = &sp.material;
        let stop = stop_probability(m, sp.wo_local, depth < max_depth);
        if m.lobes().has_density() {
            out.direct += beta * direct_light(&c, scene, &sp, Some(1.0 - stop), rng, stats);
        }
        if stop > 0.0 && (stop >= 1.0 || rng.next_f32() < stop) {
            out.visible = Some(VisiblePoint {
                p: hit.p,
                frame: sp.frame,
                wo_local: sp.wo_local,
                material: sp.material,
                beta: beta / stop,
                distance,
            });
            return out;
        }
        if depth == max_depth {
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
            return out;
        };
        let go_on = 1.0 - stop;
        beta *= s.weight / go_on;
        arrival = (!s.is_specular()).then_some((hit.p, go_on * s.pdf));
        let wi = sp.frame.to_world(s.wi);
        ray = Ray::new(offset_origin(hit.p, hit.ng, wi), wi);
        stats.bounce += 1;
    }
    out
}

/// Probability that a camera path stops at a material: 1 with only a rough part (or when it
/// may go no further), 0 with only a smooth part, else the rough part's share of the albedo
/// seen from `wo`, kept within [0.1, 0.9] so neither choice is starved.
fn stop_probability(m: &Material, wo: Vec3, may_go_on: bool) -> f32 {
    match (m.has(Part::Rough), m.has(Part::Smooth) && may_go_on) {
        (true, false) => 1.0,
        (false, _) => 0.0,
        (true, true) => {
            let rough = m.part_weight(wo, Part::Rough);
            let smooth = m.part_weight(wo, Part::Smooth);
            if rough + smooth > 0.0 {
                (rough / (rough + smooth)).clamp(0.1, 0.9)
            } else {
                0.5
            }
        }
    }
}
