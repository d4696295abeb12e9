//! Light subpaths: traced from the lights, their vertices kept for the camera subpaths, and
//! each vertex connected to the camera (light tracing).

use super::{
    LightVertex, PassContext, PathMis, VcmMode, continuation, continue_subpath, mis, shading_ratio,
};
use crate::integrator::RayStats;
use crate::material::TransportMode;
use crate::math::{Ray, Rgb, Vec3, offset_origin};
use crate::sampling::Rng;
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

/// Trace the pass's light subpaths, subpath `i` with the random stream keyed by (seed, pass,
/// i); `stopped()` is checked between chunks.
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
                let mut rng = Rng::keyed(seed, &[pass, u64::from(i), 0x119b7]);
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
fn trace_one(ctx: &PassContext, rng: &mut Rng, out: &mut LightSubpaths) {
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
        vm: vc * ctx.mis_vc,
    };
    let origin = if e.normal == Vec3::ZERO {
        e.origin
    } else {
        offset_origin(e.origin, e.normal, e.dir)
    };
    let mut ray = Ray::new(origin, e.dir);
    for depth in 1..=ctx.max_depth {
        out.rays.bounce += 1;
        let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
            return;
        };
        let wo = -ray.dir;
        let lambda_in = lambda;
        let (material, frame) = scene.surface(&hit, wo, &mut lambda);
        let cos_in = wo.dot(hit.ng).abs();
        path_mis.arrive(hit.t * hit.t, cos_in, depth > 1 || !light.is_at_infinity());
        let wo_local = frame.to_local(wo);
        let q = continuation(&material);
        if material.lobes().has_density() {
            let vertex = LightVertex {
                hit,
                wo,
                beta: beta * shading_ratio(wo, frame.n, hit.ng),
                mis: path_mis,
                continuation: q,
                depth,
                lambda_in,
                hero_only: lambda.is_hero_only(),
            };
            connect_to_camera(ctx, &vertex, &material, &frame, out);
            if ctx.mode != VcmMode::LightTrace {
                out.vertices.push(vertex);
            }
        }
        if depth == ctx.max_depth {
            return;
        }
        let mode = TransportMode::Importance;
        let Some((s, wi)) = continue_subpath(
            ctx,
            &material,
            &frame,
            hit.ng,
            wo_local,
            q,
            mode,
            rng,
            &mut path_mis,
        ) else {
            return;
        };
        // The adjoint BSDF under shading normals (Veach 1997, §5.3):
        // f*(wo → wi) = f(wi → wo) |wo·ns| |wi·ng| / (|wo·ng| |wi·ns|).
        let departure = shading_ratio(wi, frame.n, hit.ng);
        if departure == 0.0 {
            return;
        }
        beta *= s.weight * (shading_ratio(wo, frame.n, hit.ng) / (departure * q));
        if !beta.is_finite() || beta == Rgb::ZERO {
            return;
        }
        ray = Ray::new(offset_origin(hit.p, hit.ng, wi), wi);
    }
}

/// Light tracing: the light vertex seen by the camera, splatted into the pixel that sees it
/// and weighed against the camera subpaths that could have found the same path.
fn connect_to_camera(
    ctx: &PassContext,
    v: &LightVertex,
    material: &crate::material::Material,
    frame: &crate::math::Frame,
    out: &mut LightSubpaths,
) {
    let camera = ctx.camera;
    let Some(film) = camera.raster(v.hit.p) else {
        return;
    };
    let to_camera = camera.position - v.hit.p;
    let dist2 = to_camera.length_squared();
    let dist = dist2.sqrt();
    let w = to_camera / dist;
    let wo_local = frame.to_local(v.wo);
    let wi_local = frame.to_local(w);
    let f = material.eval(wo_local, wi_local, TransportMode::Importance);
    if f == Rgb::ZERO {
        return;
    }
    let cos_here = w.dot(v.hit.ng).abs();
    // The camera's density of the vertex's position, per unit area of the surface.
    let camera_pdf_area = camera.pixel_solid_angle_density(-w) * cos_here / dist2;
    if camera_pdf_area.is_nan() || camera_pdf_area <= 0.0 {
        return;
    }
    let weight = if ctx.mode == VcmMode::LightTrace {
        1.0
    } else {
        let reverse = material.pdf(wi_local, wo_local) * v.continuation;
        let w_light = mis(camera_pdf_area / ctx.light_paths as f32)
            * (ctx.mis_vm + v.mis.vcm + v.mis.vc * mis(reverse));
        1.0 / (w_light + 1.0)
    };
    let value = v.beta * f * (weight * camera_pdf_area / ctx.light_paths as f32);
    if !value.is_finite() || value == Rgb::ZERO {
        return;
    }
    out.rays.shadow += 1;
    let origin = offset_origin(v.hit.p, v.hit.ng, w);
    let to = camera.position - origin;
    let d = to.length();
    if ctx.scene.occluded(origin, to / d, d) {
        return;
    }
    let pixel = film.y as u32 * camera.width + film.x as u32;
    out.splats.push((pixel, value));
}
