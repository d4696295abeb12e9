//! Jensen's two-pass photon mapping ("Global Illumination Using Photon Maps", 1996; "Realistic
//! Image Synthesis Using Photon Mapping", 2001, ch. 9).
//!
//! Camera paths follow mirrors and glass to the first diffuse surface x. There the radiance is
//! split by light path so that none is counted twice:
//! - **direct** (L D E, and emission seen directly or through mirrors and glass): next-event
//!   estimation of every light, as in the `direct` integrator;
//! - **caustic** (L S+ D E): the caustic map's radiance estimate at x;
//! - **indirect** (L … D S* D E, at least one diffuse bounce before x): final gathering —
//!   cosine-distributed rays from x whose diffuse hits y (reached directly or through mirrors
//!   and glass) return ρ(y)/π · E(y), the irradiance precomputed from both maps at photon
//!   positions; a gather ray that meets a light adds nothing (that light is direct or caustic).
//!   With `gather_rays = 0` the global map is read at x instead, leaving out its direct photons.

use super::direct::{DirectConfig, direct_light};
use super::{RayStats, Sample, ShadingPoint};
use crate::material::{Material, TransportMode};
use crate::math::{Frame, Ray, Rgb, offset_origin};
use crate::photon::IrradianceCache;
use crate::photon::PhotonMaps;
use crate::photon::cache::estimate_apart_from_sites;
use crate::photon::estimate::{self, GatherParams, Kernel};
use crate::sampling::{Rng, cosine_hemisphere};
use crate::scene::Scene;
use std::f32::consts::{FRAC_1_PI, PI};
use std::sync::Arc;

/// Precomputed irradiance points are capped: beyond this, more points only cost build time
/// (10 M photons took 34 s to precompute at stride 4). Sparser points bias lookups toward
/// bright areas, where photons (and so points) are denser: +0.9% at 250k points for 10 M.
const MAX_CACHE_POINTS: usize = 1_000_000;

/// Glass seen from the camera is split into both branches up to this many bounces.
const SPLIT_DEPTH: u32 = 3;

/// Render-time parameters of the photon integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonSettings {
    /// Maximum specular bounces followed from the camera.
    pub max_depth: u32,
    /// Samples per area light at each diffuse hit.
    pub light_samples: u32,
    /// Final-gather rays per camera sample; 0 reads the global map directly.
    pub gather_rays: u32,
    pub caustic: GatherParams,
    pub global: GatherParams,
    /// Every n-th global photon carries precomputed irradiance (more sparsely for maps of
    /// over `MAX_CACHE_POINTS · n` photons).
    pub cache_stride: usize,
    /// Farthest a gather ray's hit may be from a precomputed irradiance point.
    pub cache_radius: f32,
    /// Weight on the indirect part (1 is physically correct; the original project's knob).
    pub indirect_scale: f32,
    /// Aim half the gather rays at hot regions where they matter (see `photon::hot`); off
    /// only to measure what it does.
    pub aim_at_hot_regions: bool,
}

impl PhotonSettings {
    /// Defaults scaled to the scene: gather radii are fractions of the diagonal of its bounds,
    /// so a scene in millimetres and one in metres render alike.
    pub fn auto(scene_diagonal: f32) -> Self {
        Self {
            max_depth: 16,
            light_samples: 4,
            gather_rays: 4,
            caustic: GatherParams {
                k: 32,
                max_radius: 0.01 * scene_diagonal,
                kernel: Kernel::Epanechnikov,
            },
            global: GatherParams {
                k: 32,
                max_radius: 0.05 * scene_diagonal,
                kernel: Kernel::Epanechnikov,
            },
            cache_stride: 4,
            cache_radius: 0.05 * scene_diagonal,
            indirect_scale: 1.0,
            aim_at_hot_regions: true,
        }
    }
}

impl PhotonSettings {
    /// Photons per estimate when the global map is read directly (no final gather): its noise
    /// is seen as is, so it needs many more photons than estimates that a gather averages.
    pub const DIRECT_VISUALISATION_K: usize = 256;
}

/// The photon integrator with its maps (and, for final gathering, precomputed irradiance).
#[derive(Clone, Debug)]
pub struct PhotonIntegrator {
    pub settings: PhotonSettings,
    pub maps: Arc<PhotonMaps>,
    cache: Option<Arc<IrradianceCache>>,
}

impl PhotonIntegrator {
    /// Prepare for rendering: precomputes irradiance when final gathering is on.
    pub fn new(settings: PhotonSettings, maps: Arc<PhotonMaps>) -> Self {
        let cache = (settings.gather_rays > 0).then(|| {
            let stride = settings
                .cache_stride
                .max(maps.global.len().div_ceil(MAX_CACHE_POINTS));
            Arc::new(IrradianceCache::build(
                &maps.global,
                &[&maps.caustic],
                stride,
                &settings.global,
            ))
        });
        Self {
            settings,
            maps,
            cache,
        }
    }

    /// Clusters of hot cache sites that final gathering aims at (0 without final gathering).
    pub fn hot_clusters(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.hot_clusters().len())
    }

    pub fn cache_points(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.len())
    }

    fn direct_config(&self) -> DirectConfig {
        DirectConfig {
            max_depth: self.settings.max_depth,
            light_samples: self.settings.light_samples,
            ..DirectConfig::default()
        }
    }

    pub(super) fn sample(
        &self,
        scene: &Scene,
        ray: &Ray,
        rng: &mut Rng,
        stats: &mut RayStats,
    ) -> Sample {
        stats.camera += 1;
        let mut s = self.trace(scene, ray, 0, rng, stats, true);
        s.indirect *= self.settings.indirect_scale;
        s.beauty = s.direct + s.caustic + s.indirect;
        s
    }

    fn trace(
        &self,
        scene: &Scene,
        ray: &Ray,
        depth: u32,
        rng: &mut Rng,
        stats: &mut RayStats,
        first: bool,
    ) -> Sample {
        let mut out = Sample::default();
        let Some(hit) = scene.intersect(ray, f32::INFINITY) else {
            return out;
        };
        let wo = -ray.dir;
        out.direct = scene.emitted(&hit, wo);
        let sp = ShadingPoint::new(scene, &hit, wo);
        if sp.material.is_specular() {
            if depth < self.settings.max_depth {
                self.specular(scene, &sp, depth, rng, stats, first, &mut out);
            }
            return out;
        }
        if first || out.albedo == Rgb::ZERO {
            out.albedo = sp.material.albedo(sp.wo_local);
            out.normal = sp.frame.n;
        }
        out.direct += direct_light(&self.direct_config(), scene, &sp, rng, stats);
        let m = &self.maps;
        out.caustic = estimate::radiance(
            &m.caustic,
            hit.p,
            &sp.frame,
            sp.wo_local,
            &sp.material,
            &self.settings.caustic,
            false,
        );
        out.indirect = match &self.cache {
            Some(_) => self.final_gather(scene, &sp, rng, stats),
            None => estimate::radiance(
                &m.global,
                hit.p,
                &sp.frame,
                sp.wo_local,
                &sp.material,
                &self.settings.global,
                true,
            ),
        };
        out
    }

    /// Follow mirror and glass. Glass is split into both branches for the first
    /// `SPLIT_DEPTH` bounces (weights F and 1 − F), since choosing one at random makes bright
    /// reflections of the light and the caustic flicker between samples.
    #[expect(
        clippy::too_many_arguments,
        reason = "recursive helper carrying the path state"
    )]
    fn specular(
        &self,
        scene: &Scene,
        sp: &ShadingPoint,
        depth: u32,
        rng: &mut Rng,
        stats: &mut RayStats,
        first: bool,
        out: &mut Sample,
    ) {
        let mut branches: [Option<(crate::math::Vec3, Rgb)>; 2] = [None, None];
        match sp.material {
            Material::Dielectric(d) if depth < SPLIT_DEPTH => {
                let (r, t) = d.branches(sp.wo_local, TransportMode::Radiance);
                branches[0] = Some((r.wi, r.weight));
                branches[1] = t.map(|t| (t.wi, t.weight));
            }
            m => {
                let u_lobe = rng.next_f32();
                branches[0] = m
                    .sample(sp.wo_local, u_lobe, rng.next_2d(), TransportMode::Radiance)
                    .map(|b| (b.wi, b.weight));
            }
        }
        let mut heaviest = 0.0;
        for (wi_local, weight) in branches.into_iter().flatten() {
            if weight == Rgb::ZERO {
                continue;
            }
            let wi = sp.frame.to_world(wi_local);
            let next = Ray::new(offset_origin(sp.hit.p, sp.hit.ng, wi), wi);
            stats.bounce += 1;
            let s = self.trace(scene, &next, depth + 1, rng, stats, false);
            out.direct += weight * s.direct;
            out.caustic += weight * s.caustic;
            out.indirect += weight * s.indirect;
            // The albedo and normal AOVs follow the strongest branch.
            if first && weight.max_element() > heaviest {
                heaviest = weight.max_element();
                out.albedo = s.albedo;
                out.normal = s.normal;
            }
        }
    }

    /// Indirect light at a diffuse point by final gathering over the precomputed irradiance.
    ///
    /// Where the scene has hot regions (see [`crate::photon::hot`]) above the surface, half
    /// the rays aim at them and half are cosine-distributed; each ray is weighted by the
    /// balance heuristic over both (Veach 1997, §9.2.1: f / (n_c p_c + n_h p_h)), which keeps
    /// the estimate unbiased and removes the speckles that small, bright regions made.
    fn final_gather(
        &self,
        scene: &Scene,
        sp: &ShadingPoint,
        rng: &mut Rng,
        stats: &mut RayStats,
    ) -> Rgb {
        let n = self.settings.gather_rays;
        let hot = self
            .cache
            .as_ref()
            .filter(|_| self.settings.aim_at_hot_regions)
            .and_then(|c| c.hot_sampler(sp.hit.p, sp.frame.n));
        let n_hot = if hot.is_some() { n / 2 } else { 0 };
        let n_cosine = n - n_hot;
        let (c_count, h_count) = (n_cosine as f32, n_hot as f32);
        let mut sum = Rgb::ZERO;
        let mut trace = |wi: crate::math::Vec3, rng: &mut Rng, stats: &mut RayStats| {
            let cos = wi.dot(sp.frame.n);
            if cos <= 0.0 {
                return;
            }
            // f·cos / (n_c p_c + n_h p_h) with f = ρ/π and p_c = cos/π.
            let p_hot = hot.as_ref().map_or(0.0, |h| h.pdf(wi));
            let weight = cos / (c_count * cos + h_count * PI * p_hot);
            if !(weight > 0.0 && weight.is_finite()) {
                return;
            }
            let ray = Ray::new(offset_origin(sp.hit.p, sp.hit.ng, wi), wi);
            sum += weight * self.gathered_radiance(scene, &ray, rng, stats);
        };
        // Cosine rays, stratified on a jittered grid when their count is a square (else in u).
        let side = (n_cosine as f32).sqrt() as u32;
        let strata = if side * side == n_cosine { side } else { 1 };
        for k in 0..n_cosine {
            let mut u = rng.next_2d();
            if strata > 1 {
                u = (glam::Vec2::new((k % strata) as f32, (k / strata) as f32) + u) / strata as f32;
            } else {
                u.x = (k as f32 + u.x) / c_count;
            }
            trace(sp.frame.to_world(cosine_hemisphere(u)), rng, stats);
        }
        if let Some(h) = &hot {
            for k in 0..n_hot {
                let u_cell = (k as f32 + rng.next_f32()) / h_count;
                let wi = h.sample(u_cell, rng.next_2d());
                trace(wi, rng, stats);
            }
        }
        // ρ for a Lambertian surface (the weights above carry the 1/π and the ray counts).
        sp.material.albedo(sp.wo_local) * sum
    }

    /// Radiance arriving along a gather ray from diffuse surfaces (through mirrors and glass),
    /// from the precomputed irradiance; emission is left out (counted as direct or caustic).
    fn gathered_radiance(
        &self,
        scene: &Scene,
        ray: &Ray,
        rng: &mut Rng,
        stats: &mut RayStats,
    ) -> Rgb {
        let mut ray = *ray;
        let mut weight = Rgb::ONE;
        for _ in 0..self.settings.max_depth.max(1) {
            stats.bounce += 1;
            let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
                return Rgb::ZERO;
            };
            let wo = -ray.dir;
            let material = scene.material_at(&hit);
            let frame: Frame = hit.frame(&material, wo);
            if let Material::Lambertian(l) = material {
                let e = self.lookup(&hit, frame.n).unwrap_or(Rgb::ZERO);
                return weight * l.albedo * FRAC_1_PI * e;
            }
            let u_lobe = rng.next_f32();
            let Some(b) = material.sample(
                frame.to_local(wo),
                u_lobe,
                rng.next_2d(),
                TransportMode::Radiance,
            ) else {
                return Rgb::ZERO;
            };
            weight *= b.weight;
            let wi = frame.to_world(b.wi);
            ray = Ray::new(offset_origin(hit.p, hit.ng, wi), wi);
        }
        Rgb::ZERO
    }

    /// Irradiance at a gather ray's diffuse hit: the nearest precomputed site's, or an
    /// estimate made at the hit itself where there is no site near or the site is hot. Beside
    /// a hot region irradiance changes by orders of magnitude within millimetres, and the
    /// nearest site is often inside the peak (the sites are as dense as the photons): reading
    /// it made the room under a two-sided light strip 5% too bright at 100k photons.
    fn lookup(&self, hit: &crate::scene::Hit, n: crate::math::Vec3) -> Option<Rgb> {
        let cache = self.cache.as_ref()?;
        match cache.lookup_site(hit.p, n, self.settings.cache_radius) {
            Some((e, false)) => Some(e),
            _ => Some(estimate_apart_from_sites(
                &self.maps.global,
                &[&self.maps.caustic],
                cache.stride(),
                hit.p,
                n,
                &self.settings.global,
            )),
        }
    }
}
