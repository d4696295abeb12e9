//! Jensen's two-pass photon mapping ("Global Illumination Using Photon Maps", 1996; "Realistic
//! Image Synthesis Using Photon Mapping", 2001, ch. 9).
//!
//! Every material is split into a rough part (diffuse lobes, glossy lobes of α ≥
//! [`crate::material::NEAR_SPECULAR_ALPHA`]) and a smooth part (delta lobes, near-specular
//! glossy lobes, transmission); see [`Part`]. Camera paths follow the smooth parts; at every
//! point x with a rough part the radiance it reflects through that part is split by light path
//! so that none is counted twice:
//! - **direct** (L x, and emission met along the smooth parts): next-event estimation of every
//!   light through every lobe with a density, weighted by MIS against the smooth part's
//!   sampling for the glossy lobes the path also follows;
//! - **caustic** (L S+ x, S a smooth-part bounce): the caustic map's radiance estimate at x,
//!   the rough part evaluated per photon;
//! - **indirect** (L … R S* x, R a rough-part bounce): final gathering — rays sampled from the
//!   rough part at x whose rough hits y (reached directly or along smooth parts) return the
//!   radiance y reflects: ρ(y)/π · E(y) from the irradiance precomputed at photon positions on
//!   diffuse surfaces, a radiance estimate over both maps on glossy ones; a gather ray that
//!   meets a light adds nothing (that light is direct or caustic). With `gather_rays = 0` the
//!   global map is read at x instead, leaving out its direct photons.

mod media;

use super::delta::{smooth_branches, stop_probability};
use super::lighting::{direct_light, emission_weight, escaped_radiance};
use super::{RayStats, Sample, ShadingPoint};
use crate::material::{Part, TransportMode};
use crate::math::{Frame, Ray, Rgb, Vec3};
use crate::medium::MediumId;
use crate::photon::IrradianceCache;
use crate::photon::beam::VolumePhotonMap;
use crate::photon::cache::estimate_apart_from_sites;
use crate::photon::estimate::{self, GatherParams, Kernel, Selection};
use crate::photon::{MapKind, PhotonMap, PhotonMaps};
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::Lambda;
use std::f32::consts::FRAC_1_PI;
use std::sync::Arc;

/// Precomputed irradiance points are capped: beyond this, more points only cost build time
/// (10 M photons took 34 s to precompute at stride 4). Sparser points bias lookups toward
/// bright areas, where photons (and so points) are denser: +0.9% at 250k points for 10 M.
const MAX_CACHE_POINTS: usize = 1_000_000;

/// At gather hits, rough parts whose glossy lobes are at least this rough are read from the
/// irradiance cache as if diffuse (see `reflected_at`): the validation scenes' means move by
/// less than their noise, and renders of glTF files with the default roughness 1 are five
/// times faster.
const GATHER_AS_DIFFUSE_ALPHA: f32 = 0.5;

/// Glass seen from the camera is split into both branches up to this many bounces.
const SPLIT_DEPTH: u32 = 3;

/// Where a camera path is: its depth along smooth lobes, whether it is still the camera ray's
/// own line (for the AOVs), and how it arrived (the previous point and the density of the
/// glossy sample that left it; `None` after the camera or a delta lobe) for weighting emission.
#[derive(Clone, Copy)]
struct Vertex {
    depth: u32,
    first: bool,
    arrival: Option<(Vec3, f32)>,
    /// The medium the path is in.
    medium: Option<MediumId>,
    /// The path's wavelengths.
    lambda: Lambda,
}

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
                max_radius: 0.025 * scene_diagonal,
                kernel: Kernel::Epanechnikov,
            },
            cache_stride: 4,
            cache_radius: 0.025 * scene_diagonal,
            indirect_scale: 1.0,
            aim_at_hot_regions: true,
        }
    }
}

impl PhotonSettings {
    /// [`PhotonSettings::auto`] for a scene: scaled to what its camera sees.
    pub fn for_scene(scene: &Scene) -> Self {
        Self::auto(scene.view_diagonal())
    }

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
    /// With final gathering: the global map's photons whose last scattering was by a smooth
    /// lobe (see [`Self::final_gather`]), in a map of their own so that their sparse
    /// estimates do not search through the others.
    after_smooth: Option<Arc<PhotonMap>>,
    /// The photons scattered in media, for the beam radiance estimate (none without media).
    volume: Option<Arc<VolumePhotonMap>>,
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
        let after_smooth = cache.is_some().then(|| {
            let photons = maps
                .global
                .photons()
                .iter()
                .filter(|p| p.smooth_last_scattering())
                .copied()
                .collect();
            Arc::new(PhotonMap::build(
                MapKind::Global,
                photons,
                maps.global.power_scale,
            ))
        });
        // Volume photons take the global map's k and largest radius for their spheres.
        let volume = (!maps.volume.is_empty()).then(|| {
            Arc::new(VolumePhotonMap::build(
                &maps.volume,
                settings.global.k,
                settings.global.max_radius,
                maps.global.power_scale,
            ))
        });
        Self {
            settings,
            maps,
            cache,
            after_smooth,
            volume,
        }
    }

    /// Clusters of hot cache sites that final gathering aims at (0 without final gathering).
    pub fn hot_clusters(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.hot_clusters().len())
    }

    pub fn cache_points(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.len())
    }

    pub(super) fn sample(
        &self,
        scene: &Scene,
        ray: &Ray,
        lambda: &Lambda,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Sample {
        stats.camera += 1;
        let start = Vertex {
            depth: 0,
            first: true,
            arrival: None,
            medium: scene.camera_medium(),
            lambda: *lambda,
        };
        let mut s = self.trace(scene, ray, start, rng, stats);
        s.indirect *= self.settings.indirect_scale;
        s.beauty = s.direct + s.caustic + s.indirect;
        s
    }

    fn trace(
        &self,
        scene: &Scene,
        ray: &Ray,
        at: Vertex,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Sample {
        let light_samples = self.settings.light_samples;
        let passage = self.through_media(scene, ray, at.medium, &at.lambda, rng, stats);
        let mut out = match passage.hit {
            None => Sample {
                direct: escaped_radiance(
                    light_samples,
                    scene,
                    ray.dir,
                    at.arrival.map(|a| a.1),
                    &at.lambda,
                ),
                ..Sample::default()
            },
            Some(hit) => {
                let at = Vertex {
                    medium: passage.medium,
                    ..at
                };
                self.shade(scene, ray, hit, at, rng, stats)
            }
        };
        if scene.has_media() {
            out.direct *= passage.transmittance;
            out.caustic *= passage.transmittance;
            out.indirect = out.indirect * passage.transmittance + passage.in_scattered;
        }
        out
    }

    /// What a camera path finds at the surface `hit` it reached along `ray`: emission, direct
    /// light, the caustic and indirect estimates, and what its smooth part brings.
    fn shade(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: crate::scene::Hit,
        at: Vertex,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Sample {
        let mut out = Sample::default();
        let light_samples = self.settings.light_samples;
        let wo = -ray.dir;
        out.direct = scene.emitted(&hit, wo, &at.lambda);
        if let Some((from, p_bsdf)) = at.arrival
            && out.direct != Rgb::ZERO
        {
            out.direct *= emission_weight(light_samples, scene, from, &hit, p_bsdf);
        }
        let mut lambda = at.lambda;
        let sp = ShadingPoint::new(scene, &hit, wo, &mut lambda).in_medium(at.medium);
        let at = Vertex { lambda, ..at };
        let m = &sp.material;
        // The photon maps hold RGB power (see `photon::trace`): a spectral path reads them
        // with the material in RGB and takes the estimate as an RGB illuminant at its own
        // wavelengths.
        let m_rgb = match lambda {
            Lambda::Rgb => sp.material,
            Lambda::Sampled { .. } => scene.surface(&hit, wo, &mut Lambda::Rgb).0,
        };
        let rough = m.has(Part::Rough);
        if rough && (at.first || out.albedo == Rgb::ZERO) {
            out.albedo = m.albedo(sp.wo_local);
            out.normal = sp.frame.n;
        }
        if m.lobes().has_density() {
            out.direct += direct_light(light_samples, scene, &sp, Some(1.0), rng, stats);
        }
        if rough {
            let maps = &self.maps;
            out.caustic = lambda.illuminant(estimate::radiance(
                &maps.caustic,
                hit.p,
                sp.ng,
                &sp.frame,
                sp.wo_local,
                &m_rgb,
                &self.settings.caustic,
                Selection::All,
            ));
            out.indirect = match &self.cache {
                Some(_) => self.final_gather(scene, &sp, &m_rgb, rng, stats),
                None => lambda.illuminant(estimate::radiance(
                    &maps.global,
                    hit.p,
                    sp.ng,
                    &sp.frame,
                    sp.wo_local,
                    &m_rgb,
                    &self.settings.global,
                    Selection::Indirect,
                )),
            };
        }
        if m.has(Part::Smooth) && at.depth < self.settings.max_depth {
            let at = Vertex {
                first: at.first && !rough,
                ..at
            };
            self.follow_smooth(scene, &sp, at, rng, stats, &mut out);
        }
        out
    }

    /// Follow the smooth part of the material (mirrors, glass, near-specular glossy lobes):
    /// every delta branch for the first `SPLIT_DEPTH` bounces, one sampled direction beyond
    /// (see [`smooth_branches`]).
    fn follow_smooth(
        &self,
        scene: &Scene,
        sp: &ShadingPoint,
        at: Vertex,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
        out: &mut Sample,
    ) {
        let m = &sp.material;
        let leaving = smooth_branches(sp, Part::Smooth, at.depth, SPLIT_DEPTH, rng);
        let mut heaviest = 0.0;
        for b in leaving.branches.into_iter().flatten() {
            let mut weight = b.weight;
            if weight == Rgb::ZERO {
                continue;
            }
            // Past the first bounce, Russian roulette on a coat over a rough base (without it
            // every coated surface went on to the maximum depth): the path goes on with the
            // probability the progressive methods' camera paths do ([`stop_probability`]).
            // Mirrors and glass, and split branches, always go on.
            if at.depth >= 1 && !leaving.split && m.has(Part::Rough) {
                let survive = 1.0 - stop_probability(m, sp.wo_local, true);
                if survive < 1.0 && (survive <= 0.0 || rng.next_f32() >= survive) {
                    continue;
                }
                weight /= survive;
            }
            let wi = sp.frame.to_world(b.wi);
            let next = Ray::new(sp.hit.offset_origin(wi), wi);
            stats.bounce += 1;
            let s = self.trace(
                scene,
                &next,
                Vertex {
                    depth: at.depth + 1,
                    first: false,
                    arrival: b.glossy_pdf.map(|p| (sp.hit.p, p)),
                    medium: scene.medium_after(sp.hit, at.medium, wi),
                    lambda: at.lambda,
                },
                rng,
                stats,
            );
            out.direct += weight * s.direct;
            out.caustic += weight * s.caustic;
            out.indirect += weight * s.indirect;
            // The albedo and normal AOVs follow the strongest branch.
            if at.first && weight.max_element() > heaviest {
                heaviest = weight.max_element();
                out.albedo = s.albedo;
                out.normal = s.normal;
            }
        }
    }

    /// Indirect light at a rough point by final gathering over the precomputed irradiance.
    ///
    /// Gather rays sample the rough part of the BSDF (cosine-distributed on diffuse surfaces).
    /// Where the scene has hot regions (see [`crate::photon::hot`]) above the surface, half
    /// the rays aim at them instead; each ray is weighted by the balance heuristic over both
    /// (Veach 1997, §9.2.1: f·cos / (n_b p_b + n_h p_h)), which keeps the estimate unbiased
    /// and removes the speckles that small, bright regions made.
    ///
    /// The indirect paths into x are split by the scattering just before x. A gather ray
    /// reads only the rough part of the surface it meets; the paths whose last scattering was
    /// by a smooth part (x ← glass or mirror ← …) are the global map's photons at x so marked
    /// ([`crate::photon::Photon::smooth_last_scattering`]).
    /// Gather rays sent through glass found the bright spots behind it (a caustic's focus, a
    /// lit floor magnified by a glass sphere) with no density that aims at them: those were
    /// the speckles of `scenes/caustics.toml` on its dark wall and inside its sphere.
    fn final_gather<S: Sampler>(
        &self,
        scene: &Scene,
        sp: &ShadingPoint,
        m_rgb: &crate::material::Material,
        rng: &mut S,
        stats: &mut RayStats,
    ) -> Rgb {
        let n = self.settings.gather_rays;
        let hot = self
            .cache
            .as_ref()
            .filter(|_| self.settings.aim_at_hot_regions)
            .and_then(|c| c.hot_sampler(sp.hit.p, sp.frame.n));
        let n_hot = if hot.is_some() { n / 2 } else { 0 };
        let n_bsdf = n - n_hot;
        let (b_count, h_count) = (n_bsdf as f32, n_hot as f32);
        let m = &sp.material;
        let mut sum = Rgb::ZERO;
        let mut trace = |wi: Vec3, rng: &mut S, stats: &mut RayStats| {
            let cos = wi.dot(sp.frame.n);
            if cos <= 0.0 {
                return;
            }
            let wi_local = sp.frame.to_local(wi);
            let f = m.eval_part(sp.wo_local, wi_local, TransportMode::Radiance, Part::Rough);
            let p_bsdf = m.pdf_part(sp.wo_local, wi_local, Part::Rough);
            let p_hot = hot.as_ref().map_or(0.0, |h| h.pdf(wi));
            let weight = f * (cos / (b_count * p_bsdf + h_count * p_hot));
            if !(weight.max_element() > 0.0 && weight.is_finite()) {
                return;
            }
            let ray = Ray::new(sp.hit.offset_origin(wi), wi);
            let medium = scene.medium_after(sp.hit, sp.medium, wi);
            let gathered = self.gathered_radiance(scene, &ray, medium, rng, stats);
            sum += weight * sp.lambda.illuminant(gathered);
        };
        // BSDF rays, stratified on a jittered grid when their count is a square (else in u).
        let side = (n_bsdf as f32).sqrt() as u32;
        let strata = if side * side == n_bsdf { side } else { 1 };
        for k in 0..n_bsdf {
            let u_lobe = rng.next_f32();
            let mut u = rng.next_2d();
            if strata > 1 {
                u = (glam::Vec2::new((k % strata) as f32, (k / strata) as f32) + u) / strata as f32;
            } else {
                u.x = (k as f32 + u.x) / b_count;
            }
            if let Some(s) =
                m.sample_part(sp.wo_local, u_lobe, u, TransportMode::Radiance, Part::Rough)
            {
                trace(sp.frame.to_world(s.wi), rng, stats);
            }
        }
        if let Some(h) = &hot {
            for k in 0..n_hot {
                let u_cell = (k as f32 + rng.next_f32()) / h_count;
                let wi = h.sample(u_cell, rng.next_2d());
                trace(wi, rng, stats);
            }
        }
        let after_smooth = self.after_smooth.as_ref().map_or(Rgb::ZERO, |map| {
            sp.lambda.illuminant(estimate::radiance(
                map,
                sp.hit.p,
                sp.ng,
                &sp.frame,
                sp.wo_local,
                m_rgb,
                &self.settings.global,
                Selection::All,
            ))
        });
        sum + after_smooth
    }

    /// Radiance arriving along a gather ray (which starts in `medium`) from the rough part of
    /// the surface it hits, from the photon maps, and from the media it crosses by the beam
    /// estimate; emission is left out (counted as direct or caustic), and so is the light
    /// that the surface's smooth part sends (see [`Self::final_gather`]). In RGB, as the maps
    /// are.
    fn gathered_radiance(
        &self,
        scene: &Scene,
        ray: &Ray,
        medium: Option<MediumId>,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Rgb {
        stats.bounce += 1;
        let passage = self.through_media(scene, ray, medium, &Lambda::Rgb, rng, stats);
        let Some(hit) = passage.hit else {
            return passage.in_scattered;
        };
        let wo = -ray.dir;
        let (material, frame) = scene.surface(&hit, wo, &mut Lambda::Rgb);
        if !material.has(Part::Rough) {
            return passage.in_scattered;
        }
        passage.transmittance * self.reflected_at(&hit, &frame, frame.to_local(wo), &material)
            + passage.in_scattered
    }

    /// Radiance reflected by the rough part at a gather ray's hit, from every photon: the
    /// precomputed irradiance times ρ(wo)/π where the rough part is diffuse or broadly glossy
    /// (GGX α ≥ `GATHER_AS_DIFFUSE_ALPHA`), a radiance estimate over both maps (the BSDF
    /// evaluated per photon) where it is narrower. A gather hit is already an average over
    /// directions, as the irradiance cache is over photons; reading both maps at every hit on
    /// glTF's default roughness (α = 1) made renders five times slower. (The diffuse base of a
    /// `pbr` material is weighted by 1 − F(v·h), which depends on the light's direction; its
    /// albedo seen from `wo` stands for it.)
    fn reflected_at(
        &self,
        hit: &crate::scene::Hit,
        frame: &Frame,
        wo_local: Vec3,
        material: &crate::material::Material,
    ) -> Rgb {
        let ng = hit.ng_facing(frame.to_world(wo_local));
        if material.glossy_alpha(Part::Rough) >= GATHER_AS_DIFFUSE_ALPHA {
            // The rough part only reflects, and reflection needs `wo` above the shading plane
            // (a smooth mesh's normal can turn it below while the surface faces it).
            if wo_local.z <= 0.0 {
                return Rgb::ZERO;
            }
            let e = self.lookup(hit, ng).unwrap_or(Rgb::ZERO);
            return material.albedo_part(wo_local, Part::Rough) * FRAC_1_PI * e;
        }
        let g = &self.settings.global;
        estimate::radiance(
            &self.maps.global,
            hit.p,
            ng,
            frame,
            wo_local,
            material,
            g,
            Selection::All,
        ) + estimate::radiance(
            &self.maps.caustic,
            hit.p,
            ng,
            frame,
            wo_local,
            material,
            g,
            Selection::All,
        )
    }

    /// Irradiance at a gather ray's diffuse hit: the nearest precomputed site's, or an
    /// estimate made at the hit itself where there is no site near or the site is hot. Beside
    /// a hot region irradiance changes by orders of magnitude within millimetres, and the
    /// nearest site is often inside the peak (the sites are as dense as the photons): reading
    /// it made the room under a two-sided light strip 5% too bright at 100k photons.
    fn lookup(&self, hit: &crate::scene::Hit, n: Vec3) -> Option<Rgb> {
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
