//! Light subpaths: traced from the lights, their vertices kept for the camera subpaths, and
//! each vertex connected to the camera (light tracing).

use super::site::{self, Scatterer, Site};
use super::{
    LightVertex, PassContext, PathMis, VcmMode, continuation, continue_subpath, mis, shading_ratio,
};
use crate::integrator::RayStats;
use crate::material::TransportMode;
use crate::math::{Ray, Rgb, Vec3, offset_origin};
use crate::sampling::{PixelSampler, Rng, Sampler};
use crate::scene::Interaction;
use rayon::prelude::*;
use std::ops::Range;

/// Light subpaths traced per parallel task: a fixed size, so the work and its order do not
/// depend on the thread count.
const CHUNK: u32 = 1024;

/// Every light subpath of a pass.
#[derive(Debug, Default)]
pub struct LightSubpaths {
    /// The vertices of all subpaths, subpath after subpath.
    pub vertices: Vec<LightVertex>,
    /// Where each subpath's vertices end in `vertices` (subpath i: `ends[i-1]..ends[i]`).
    ends: Vec<u32>,
    /// Light reaching the camera from light vertices: (pixel index, value already divided by
    /// the number of light subpaths), in subpath order.
    pub splats: Vec<(u32, Rgb)>,
    pub rays: RayStats,
}

impl LightSubpaths {
    /// The vertices of subpath `i`.
    pub fn of(&self, i: usize) -> &[LightVertex] {
        let start = if i == 0 { 0 } else { self.ends[i - 1] as usize };
        &self.vertices[start..self.ends[i] as usize]
    }
}

/// Trace the pass's light subpaths, subpath `i` drawing from a [`PixelSampler`] keyed by
/// (seed, i) with the pass as its index; `stopped()` is checked between chunks.
pub fn trace_light_subpaths(
    ctx: &PassContext,
    seed: u64,
    pass: u64,
    stopped: &(impl Fn() -> bool + Sync),
) -> LightSubpaths {
    let n = ctx.light_paths;
    let chunks: Vec<LightSubpaths> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|k| {
            let mut out = LightSubpaths::default();
            if stopped() {
                return out;
            }
            let range: Range<u32> = k * CHUNK..((k + 1) * CHUNK).min(n);
            for i in range {
                let key = Rng::keyed(seed, &[u64::from(i), 0x119b7]).next_u64();
                let mut rng = PixelSampler::new(key, pass as u32);
                trace_one(ctx, &mut rng, &mut out);
                out.ends.push(out.vertices.len() as u32);
            }
            out
        })
        .collect();
    let mut all = LightSubpaths::default();
    for c in chunks {
        let base = all.vertices.len() as u32;
        all.ends.extend(c.ends.iter().map(|e| e + base));
        all.vertices.extend(c.vertices);
        all.splats.extend(c.splats);
        all.rays.add(&c.rays);
    }
    all
}

/// One light subpath: emitted from a light chosen by power, followed until Russian roulette
/// or the depth limit ends it.
fn trace_one(ctx: &PassContext, rng: &mut impl Sampler, out: &mut LightSubpaths) {
    let scene = ctx.scene;
    let Some((index, pick, _)) = scene.choose_light(rng.next_f32()) else {
        return;
    };
    let light = &scene.lights()[index];
    let mut lambda = ctx.lambda;
    let u_pick = rng.next_f32();
    let (u_pos, u_dir) = (rng.next_2d(), rng.next_2d());
    let Some(e) = light.emit(u_pick, u_pos, u_dir, &lambda) else {
        return;
    };
    let pdf_emit = light.pdf_emit(e.origin, e.normal, e.dir) * pick;
    let pdf_direct = light.pdf_direct_area(e.dir) * pick;
    if pdf_emit.is_nan() || pdf_emit <= 0.0 || !e.flux.is_finite() {
        return;
    }
    // The emitted flux is the light's radiance (or intensity) over the density of its origin
    // and direction; the choice of the light divides it too.
    let mut beta = e.flux / pick;
    let cos_light = if e.normal == Vec3::ZERO || light.is_at_infinity() {
        1.0
    } else {
        e.normal.dot(e.dir).abs()
    };
    let vc = if light.is_delta() {
        0.0
    } else {
        mis(cos_light / pdf_emit)
    };
    let mut path_mis = PathMis {
        vcm: mis(pdf_direct / pdf_emit),
        vc,
    };
    let origin = if e.normal == Vec3::ZERO {
        e.origin
    } else {
        offset_origin(e.origin, e.error, e.normal, e.dir)
    };
    let mut ray = Ray::new(origin, e.dir);
    let mut medium = scene.light_medium(index);
    let mut ratio = Rgb::ONE;
    for depth in 1..=ctx.max_depth {
        out.rays.bounce += 1;
        let step = scene.next_interaction(&ray, medium, (ctx.hero, &lambda), rng);
        out.rays.bounce += u64::from(step.crossings);
        beta *= step.weight;
        ratio *= step.ratio;
        let wo = -ray.dir;
        let lambda_in = lambda;
        let (site, scatterer) = match step.interaction {
            Interaction::Escaped => return,
            Interaction::Scatter { p, medium } => (
                Site::Medium { p, medium },
                site::medium_scatterer(scene, medium, p, wo, &lambda),
            ),
            Interaction::Surface { hit, medium } => {
                let scatterer = Scatterer::at_surface(scene, &hit, wo, &mut lambda);
                (Site::Surface { hit, medium }, scatterer)
            }
        };
        let dist2 = (site.p() - ray.origin).length_squared();
        let measure_in = scatterer.measure(wo);
        path_mis.arrive(dist2, measure_in, depth > 1 || !light.is_at_infinity());
        let q = continuation(&scatterer);
        // Flux lands on the geometric surface; what a BSDF at the vertex multiplies is the
        // shading irradiance (in a medium there is no surface).
        let arrival = match &scatterer {
            Scatterer::Surface { frame, ng, .. } => shading_ratio(wo, frame.n, *ng),
            Scatterer::Medium { .. } => 1.0,
        };
        if scatterer.has_density() {
            let vertex = LightVertex {
                site,
                wo,
                beta: beta * arrival,
                mis: path_mis,
                continuation: q,
                depth,
                lambda_in,
                hero_only: lambda.is_hero_only(),
                ratio,
            };
            connect_to_camera(ctx, &vertex, &scatterer, rng, out);
            if ctx.mode != VcmMode::LightTrace {
                out.vertices.push(vertex);
            }
        }
        if depth == ctx.max_depth {
            return;
        }
        let mode = TransportMode::Importance;
        let Some(s) = continue_subpath(ctx, &scatterer, q, mode, rng, &mut path_mis) else {
            return;
        };
        // The adjoint BSDF under shading normals (Veach 1997, §5.3):
        // f*(wo → wi) = f(wi → wo) |wo·ns| |wi·ng| / (|wo·ng| |wi·ns|).
        let departure = match &scatterer {
            Scatterer::Surface { frame, ng, .. } => shading_ratio(s.wi, frame.n, *ng),
            Scatterer::Medium { .. } => 1.0,
        };
        if departure == 0.0 {
            return;
        }
        beta *= s.weight * (arrival / (departure * q));
        if !beta.is_finite() || beta == Rgb::ZERO {
            return;
        }
        (ray, medium) = site::ray_from(scene, &site, s.wi);
    }
}

/// Light tracing: the light vertex seen by the camera, splatted into the pixel that sees it
/// and weighed against the camera subpaths that could have found the same path.
fn connect_to_camera(
    ctx: &PassContext,
    v: &LightVertex,
    scatterer: &Scatterer,
    rng: &mut impl Sampler,
    out: &mut LightSubpaths,
) {
    let camera = ctx.camera;
    let p = v.site.p();
    let Some(film) = camera.raster(p) else {
        return;
    };
    let to_camera = camera.position - p;
    let dist2 = to_camera.length_squared();
    let dist = dist2.sqrt();
    let w = to_camera / dist;
    let (f, _, reverse) = scatterer.eval(w, TransportMode::Importance);
    if f == Rgb::ZERO {
        return;
    }
    // The camera's density of the vertex, per unit area of a surface (per unit volume in a
    // medium, for the weights), and the geometric factor the contribution takes.
    let camera_pdf = camera.pixel_solid_angle_density(-w) / dist2;
    let camera_pdf_vertex = camera_pdf * scatterer.measure(w);
    let geometric = match scatterer {
        Scatterer::Surface { .. } => camera_pdf_vertex,
        Scatterer::Medium { .. } => camera_pdf,
    };
    if camera_pdf_vertex.is_nan() || camera_pdf_vertex <= 0.0 {
        return;
    }
    let weight = if ctx.mode == VcmMode::LightTrace {
        1.0
    } else {
        let m = ctx.merge_factors(scatterer);
        let w_light = mis(camera_pdf_vertex / ctx.light_paths as f32)
            * (m.mis_vm + v.mis.vcm + v.mis.vc * mis(reverse * v.continuation));
        1.0 / (w_light + 1.0)
    };
    let value = v.beta
        * f
        * (weight * geometric * crate::medium::spectral_mis(v.ratio) / ctx.light_paths as f32);
    if !value.is_finite() || value == Rgb::ZERO {
        return;
    }
    out.rays.shadow += 1;
    let (origin, medium) = v.site.leave(ctx.scene, w);
    let tr = site::transmittance_to(ctx.scene, origin, medium, camera.position, &ctx.lambda, rng);
    if tr == Rgb::ZERO {
        return;
    }
    let pixel = film.y as u32 * camera.width + film.x as u32;
    out.splats.push((pixel, value * tr));
}
