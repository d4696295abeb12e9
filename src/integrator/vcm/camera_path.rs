//! Camera subpaths: at every vertex with a density, next-event estimation, connections to
//! the pixel's light subpath and merging with every light subpath's vertices nearby; and the
//! emission each subpath finds.

use super::site::{self, Scatterer, Site};
use super::{
    LightVertex, PassContext, PathMis, VcmMode, VertexGrid, continuation, continue_subpath,
    hero_tripled_once, mis, spectral_weight,
};
use crate::integrator::RayStats;
use crate::material::TransportMode;
use crate::math::{Ray, Rgb, Vec3, plane_tolerance};
use crate::medium::spectral_mis;
use crate::photon::estimate::{EXACT_NORMAL_ERROR, disc_distance2};
use crate::photon::grid::QueryScratch;
use crate::sampling::Sampler;
use crate::scene::{Interaction, NO_LIGHT};
use crate::spectrum::Lambda;

/// A camera subpath's vertex with a density, with what its connections and merges need.
struct CameraVertex {
    site: Site,
    /// Toward the previous vertex.
    wo: Vec3,
    scatterer: Scatterer,
    continuation: f32,
    mis: PathMis,
    /// Segments from the camera.
    depth: u32,
    hero_only: bool,
    /// Each channel's density of the subpath's distances in media over the hero's.
    ratio: Rgb,
}

/// The light a camera subpath along `ray` brings back, at the pass's wavelengths, using
/// `light_path` (the vertices of the pixel's light subpath) for connections and `grid` over
/// `vertices` (every light subpath's) for merges.
pub fn camera_sample(
    ctx: &PassContext,
    ray: Ray,
    light_path: &[LightVertex],
    merge: Option<&VertexGrid>,
    scratch: &mut QueryScratch,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let scene = ctx.scene;
    let mut lambda = ctx.lambda;
    let mut ray = ray;
    let camera_pdf = ctx.camera.pixel_solid_angle_density(ray.dir);
    let mut path_mis = PathMis {
        vcm: mis(ctx.light_paths as f32 / camera_pdf),
        vc: 0.0,
    };
    let mut beta = Rgb::ONE;
    let mut l = Rgb::ZERO;
    let mut medium = scene.camera_medium();
    let mut ratio = Rgb::ONE;
    // Whether every scattering so far was by a delta lobe (the emission such a subpath finds
    // is all that light tracing cannot).
    let mut specular_only = true;
    stats.camera += 1;
    for depth in 1..=ctx.max_depth + 1 {
        if depth > 1 {
            stats.bounce += 1;
        }
        let step = scene.next_interaction(&ray, medium, (ctx.hero, &lambda), rng);
        stats.bounce += u64::from(step.crossings);
        beta *= step.weight;
        ratio *= step.ratio;
        let spectral = spectral_mis(ratio);
        let wo = -ray.dir;
        let (site, scatterer) = match step.interaction {
            Interaction::Escaped => {
                if let Some((i, _)) = scene.environment() {
                    let le = scene.escaped(ray.dir, &lambda);
                    let found = Found {
                        index: i,
                        p: ray.origin,
                        n: Vec3::ZERO,
                        dir: ray.dir,
                    };
                    l +=
                        beta * le * (found.weight(ctx, depth, specular_only, &path_mis) * spectral);
                }
                break;
            }
            Interaction::Scatter { p, medium } => {
                let dist2 = (p - ray.origin).length_squared();
                let s = site::medium_scatterer(scene, medium, p, wo, &lambda);
                path_mis.arrive(dist2, s.measure(wo), true);
                (Site::Medium { p, medium }, s)
            }
            Interaction::Surface { hit, medium } => {
                let dist2 = (hit.p - ray.origin).length_squared();
                path_mis.arrive(dist2, wo.dot(hit.ng).abs(), true);
                let le = if hit.light != NO_LIGHT {
                    scene.emitted(&hit, wo, &lambda)
                } else {
                    Rgb::ZERO
                };
                if le != Rgb::ZERO {
                    let found = Found {
                        index: hit.light as usize,
                        p: hit.p,
                        n: hit.ng,
                        dir: ray.dir,
                    };
                    l +=
                        beta * le * (found.weight(ctx, depth, specular_only, &path_mis) * spectral);
                }
                if depth > ctx.max_depth {
                    break;
                }
                let s = Scatterer::at_surface(scene, &hit, wo, &mut lambda);
                (Site::Surface { hit, medium }, s)
            }
        };
        if depth > ctx.max_depth {
            break;
        }
        let q = continuation(&scatterer);
        if scatterer.has_density() && ctx.mode != VcmMode::LightTrace {
            let v = CameraVertex {
                site,
                wo,
                scatterer,
                continuation: q,
                mis: path_mis,
                depth,
                hero_only: lambda.is_hero_only(),
                ratio,
            };
            let techniques = Techniques { light_path, merge };
            l += beta * techniques.gather(ctx, &v, &lambda, scratch, rng, stats);
        }
        let mode = TransportMode::Radiance;
        let Some(s) = continue_subpath(ctx, &scatterer, q, mode, rng, &mut path_mis) else {
            break;
        };
        specular_only &= s.specular;
        beta *= s.weight / q;
        if !beta.is_finite() || beta == Rgb::ZERO {
            break;
        }
        (ray, medium) = site::ray_from(scene, &site, s.wi);
    }
    l
}

/// Emission a camera subpath found: on light `index` at `p` (normal `n`; the sky: any point
/// of the ray), arriving along `dir`.
struct Found {
    index: usize,
    p: Vec3,
    n: Vec3,
    dir: Vec3,
}

impl Found {
    /// The weight of this emission, found by a camera subpath of `depth` segments, against
    /// next-event estimation and the light subpaths that could have made the same path.
    fn weight(
        &self,
        ctx: &PassContext,
        depth: u32,
        specular_only: bool,
        path_mis: &PathMis,
    ) -> f32 {
        if depth == 1 {
            // Seen directly: no other technique makes this path.
            return 1.0;
        }
        if ctx.mode == VcmMode::LightTrace {
            return if specular_only { 1.0 } else { 0.0 };
        }
        let light = &ctx.scene.lights()[self.index];
        let pick = ctx.scene.light_choice_pmf(self.index);
        let pdf_direct = light.pdf_direct_area(-self.dir) * pick;
        let pdf_emit = light.pdf_emit(self.p, self.n, -self.dir) * pick;
        let w_camera = mis(pdf_direct) * path_mis.vcm + mis(pdf_emit) * path_mis.vc;
        1.0 / (1.0 + w_camera)
    }
}

/// What a camera vertex is joined with besides a light sample: the pixel's light subpath,
/// and the grid of every light subpath's vertices when merging.
struct Techniques<'a> {
    light_path: &'a [LightVertex],
    merge: Option<&'a VertexGrid>,
}

impl Techniques<'_> {
    /// The light every technique but emission hits brings to the camera vertex `v`: next-event
    /// estimation, connections and merges, each weighed.
    fn gather(
        &self,
        ctx: &PassContext,
        v: &CameraVertex,
        lambda: &Lambda,
        scratch: &mut QueryScratch,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Rgb {
        let mut found = next_event(ctx, v, lambda, rng, stats);
        for y in self.light_path {
            if y.depth + v.depth > ctx.max_depth {
                break;
            }
            found += connect(ctx, v, y, rng, stats);
        }
        if let Some(grid) = self.merge {
            found += merged(ctx, v, grid, scratch);
        }
        found
    }
}

/// Next-event estimation at a camera vertex: one light chosen by power, sampled once.
fn next_event(
    ctx: &PassContext,
    v: &CameraVertex,
    lambda: &Lambda,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let scene = ctx.scene;
    let Some((index, pick, _)) = scene.choose_light(rng.next_f32()) else {
        return Rgb::ZERO;
    };
    let light = &scene.lights()[index];
    let u_pick = rng.next_f32();
    let p = v.site.p();
    let Some(ls) = light.sample_li(p, u_pick, rng.next_2d(), lambda) else {
        return Rgb::ZERO;
    };
    let (f, pdf_bsdf, reverse) = v.scatterer.eval(ls.wi, TransportMode::Radiance);
    if f == Rgb::ZERO || ls.radiance == Rgb::ZERO {
        return Rgb::ZERO;
    }
    // The density of the light's vertex seen from here, per solid angle: a light at a point
    // (density 1 of its position) has dist² (ls.pdf is 1, with 1/dist² in its radiance).
    let pdf_direct = pick
        * if light.is_delta() && !light.is_at_infinity() {
            (ls.point - p).length_squared()
        } else {
            ls.pdf
        };
    let cos_light = if ls.normal == Vec3::ZERO {
        1.0
    } else {
        ls.normal.dot(ls.wi).abs()
    };
    let pdf_emit = light.pdf_emit(ls.point, ls.normal, -ls.wi) * pick;
    let pdf_bsdf = if light.is_delta() {
        0.0
    } else {
        pdf_bsdf * v.continuation
    };
    let reverse = reverse * v.continuation;
    let m = ctx.merge_factors(&v.scatterer);
    let w_light = mis(pdf_bsdf / pdf_direct);
    let w_camera = mis(pdf_emit * v.scatterer.measure(ls.wi) / (pdf_direct * cos_light))
        * (m.mis_vm + v.mis.vcm + v.mis.vc * mis(reverse));
    let weight = 1.0 / (w_light + 1.0 + w_camera);
    stats.shadow += 1;
    let tr = light_transmittance(ctx, v, &ls, rng);
    if tr == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let cosine = v.scatterer.shading_cosine(ls.wi);
    f * tr * ls.radiance * (weight * cosine * spectral_mis(v.ratio) / (ls.pdf * pick))
}

/// The fraction of the light sample's light that reaches the camera vertex (both ends moved
/// off their surfaces, as the path tracer's shadow rays are).
fn light_transmittance(
    ctx: &PassContext,
    v: &CameraVertex,
    ls: &crate::light::LightSample,
    rng: &mut impl Sampler,
) -> Rgb {
    let (origin, medium) = v.site.leave(ctx.scene, ls.wi);
    let end = ls.end_seen_from(origin);
    site::transmittance_to(ctx.scene, origin, medium, end, &ctx.lambda, rng)
}

/// A connection of a camera vertex to a light vertex, weighed against every other
/// technique for the same path.
fn connect(
    ctx: &PassContext,
    x: &CameraVertex,
    y: &LightVertex,
    rng: &mut impl Sampler,
    stats: &mut RayStats,
) -> Rgb {
    let d = y.site.p() - x.site.p();
    let dist2 = d.length_squared();
    if dist2 == 0.0 {
        return Rgb::ZERO;
    }
    let w = d / dist2.sqrt();
    let (f_x, pdf_x, reverse_x) = x.scatterer.eval(w, TransportMode::Radiance);
    if f_x == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let scatterer_y = y.scatterer(ctx);
    let (f_y, pdf_y, reverse_y) = scatterer_y.eval(-w, TransportMode::Importance);
    if f_y == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let measure_x = x.scatterer.measure(w);
    let measure_y = scatterer_y.measure(w);
    // Each side's density of the other's position, per unit area (volume).
    let camera_pdf = pdf_x * x.continuation * measure_y / dist2;
    let light_pdf = pdf_y * y.continuation * measure_x / dist2;
    let (m_x, m_y) = (
        ctx.merge_factors(&x.scatterer),
        ctx.merge_factors(&scatterer_y),
    );
    let w_light =
        mis(camera_pdf) * (m_y.mis_vm + y.mis.vcm + y.mis.vc * mis(reverse_y * y.continuation));
    let w_camera =
        mis(light_pdf) * (m_x.mis_vm + x.mis.vcm + x.mis.vc * mis(reverse_x * x.continuation));
    let weight = 1.0 / (w_light + 1.0 + w_camera);
    // The geometric term: the camera side's shading cosine (the light side's is in its
    // throughput), the light side's geometric one; none in a medium.
    let cos_y = match scatterer_y {
        Scatterer::Surface { .. } => measure_y,
        Scatterer::Medium { .. } => 1.0,
    };
    let value = f_x
        * f_y
        * y.beta
        * (weight * x.scatterer.shading_cosine(w) * cos_y / dist2
            * hero_tripled_once(x.hero_only, y.hero_only)
            * spectral_weight(x.ratio, y.ratio));
    if value == Rgb::ZERO || !value.is_finite() {
        return Rgb::ZERO;
    }
    stats.shadow += 1;
    value * site::transmittance(ctx.scene, &x.site, &y.site, &ctx.lambda, rng)
}

/// The merges at a camera vertex: Σ f · β over the light vertices within the radius on the
/// same surface (the disc rule of the photon gathers, `photon::estimate::disc_distance2`: the
/// normals agree and the vertex lies in the tangent plane, so that a ceiling 1 cm above a
/// light's lower face lends it nothing) or in the same medium, for a vertex in a medium, each
/// weighed against the other techniques, over the density estimate's η_VCM.
fn merged(
    ctx: &PassContext,
    x: &CameraVertex,
    grid: &VertexGrid,
    scratch: &mut QueryScratch,
) -> Rgb {
    let mut sum = Rgb::ZERO;
    let (ng, medium) = match &x.site {
        Site::Surface { hit, .. } => (hit.ng_facing(x.wo), None),
        Site::Medium { medium, .. } => (Vec3::ZERO, Some(*medium)),
    };
    let m = ctx.merge_factors(&x.scatterer);
    let p = x.site.p();
    let tolerance = plane_tolerance(p);
    let r2 = grid.radius2();
    grid.for_each_near(p, scratch, |y, d2| {
        if y.depth + x.depth > ctx.max_depth + 1 {
            return;
        }
        let same_kind = match medium {
            Some(id) => y.in_medium(id),
            None => disc_distance2(y.position - p, d2, ng, y.ng, tolerance, EXACT_NORMAL_ERROR)
                .is_some_and(|m2| m2 <= r2),
        };
        if !same_kind {
            return;
        }
        let (f, camera_pdf, reverse) = x.scatterer.eval(y.wo, TransportMode::Radiance);
        if f == Rgb::ZERO {
            return;
        }
        let camera_pdf = camera_pdf * x.continuation;
        let reverse = reverse * y.continuation;
        let w_light = m.mis_vc * (y.vcm + y.vc * mis(camera_pdf));
        let w_camera = m.mis_vc * (x.mis.vcm + x.mis.vc * mis(reverse));
        let weight = 1.0 / (w_light + 1.0 + w_camera);
        sum += f
            * y.beta
            * (weight
                * hero_tripled_once(x.hero_only, y.hero_only)
                * spectral_weight(x.ratio, y.ratio));
    });
    sum * m.normalization
}
