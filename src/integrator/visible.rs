//! Camera paths to their first diffuse surface: the "visible points" of progressive photon
//! mapping (Hachisuka et al. 2008), with the light that needs no photons gathered on the way.

use super::direct::{DirectConfig, direct_light};
use super::{RayStats, ShadingPoint};
use crate::material::{Material, TransportMode};
use crate::math::{Frame, Ray, Rgb, Vec3, offset_origin};
use crate::sampling::Rng;
use crate::scene::Scene;

/// Where a camera path met its first diffuse surface.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint {
    pub p: Vec3,
    pub frame: Frame,
    pub wo_local: Vec3,
    /// The material at the point, textures resolved.
    pub material: Material,
    /// Throughput of the specular chain from the camera.
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

/// Follow `ray` through specular surfaces (choosing glass branches by Fresnel) to the first
/// diffuse hit.
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
    stats.camera += 1;
    for depth in 0..=max_depth {
        let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
            return out;
        };
        distance += hit.t;
        let wo = -ray.dir;
        out.direct += beta * scene.emitted(&hit, wo);
        let sp = ShadingPoint::new(scene, &hit, wo);
        if !sp.material.is_specular() {
            let c = DirectConfig {
                light_samples,
                ..DirectConfig::default()
            };
            out.direct += beta * direct_light(&c, scene, &sp, rng, stats);
            out.visible = Some(VisiblePoint {
                p: hit.p,
                frame: sp.frame,
                wo_local: sp.wo_local,
                material: sp.material,
                beta,
                distance,
            });
            return out;
        }
        if depth == max_depth {
            return out;
        }
        let u_lobe = rng.next_f32();
        let Some(s) =
            sp.material
                .sample(sp.wo_local, u_lobe, rng.next_2d(), TransportMode::Radiance)
        else {
            return out;
        };
        beta *= s.weight;
        let wi = sp.frame.to_world(s.wi);
        ray = Ray::new(offset_origin(hit.p, hit.ng, wi), wi);
        stats.bounce += 1;
    }
    out
}
