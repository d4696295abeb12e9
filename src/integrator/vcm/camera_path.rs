//! Camera subpaths: at every vertex with a density, next-event estimation, connections to
//! the pixel's light subpath and merging with every light subpath's vertices nearby; and the
//! emission each subpath finds.

use super::{
    LightVertex, PassContext, PathMis, VcmMode, VertexGrid, continuation, continue_subpath,
    hero_tripled_once, mis,
};
use crate::integrator::RayStats;
use crate::light::Light;
use crate::material::{Material, TransportMode};
use crate::math::{Frame, Ray, Rgb, Vec3, offset_origin};
use crate::photon::grid::QueryScratch;
use crate::sampling::Rng;
use crate::scene::{Hit, NO_LIGHT};

/// A camera subpath's vertex with a density, with what its connections and merges need.
struct CameraVertex<'a> {
    hit: &'a Hit,
    material: Material,
    frame: Frame,
    wo_local: Vec3,
    continuation: f32,
    mis: PathMis,
    /// Segments from the camera.
    depth: u32,
    hero_only: bool,
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
    rng: &mut Rng,
    stats: &mut RayStats,
) -> Rgb {
    let scene = ctx.scene;
    let mut lambda = ctx.lambda;
    let mut ray = ray;
    let camera_pdf = ctx.camera.pixel_solid_angle_density(ray.dir);
    let mut path_mis = PathMis {
        vcm: mis(ctx.light_paths as f32 / camera_pdf),
        vc: 0.0,
        vm: 0.0,
    };
    let mut beta = Rgb::ONE;
    let mut l = Rgb::ZERO;
    // Whether every scattering so far was by a delta lobe (the emission such a subpath finds
    // is all that light tracing cannot).
    let mut specular_only = true;
    stats.camera += 1;
    for depth in 1..=ctx.max_depth + 1 {
        if depth > 1 {
            stats.bounce += 1;
        }
        let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
            if let Some((i, _)) = scene.environment() {
                let le = scene.escaped(ray.dir, &lambda);
                let w = emission_weight(
                    ctx,
                    i,
                    ray.origin,
                    Vec3::ZERO,
                    ray.dir,
                    depth,
                    specular_only,
                    &path_mis,
                );
                l += beta * le * w;
            }
            break;
        };
        let wo = -ray.dir;
        path_mis.arrive(hit.t * hit.t, wo.dot(hit.ng).abs(), true);
        if hit.light != NO_LIGHT {
            let le = scene.emitted(&hit, wo, &lambda);
            if le != Rgb::ZERO {
                let w = emission_weight(
                    ctx,
                    hit.light as usize,
                    hit.p,
                    hit.ng,
                    ray.dir,
                    depth,
                    specular_only,
                    &path_mis,
                );
                l += beta * le * w;
            }
        }
        if depth > ctx.max_depth {
            break;
        }
        let (material, frame) = scene.surface(&hit, wo, &mut lambda);
        let wo_local = frame.to_local(wo);
        let q = continuation(&material);
        if material.lobes().has_density() && ctx.mode != VcmMode::LightTrace {
            let v = CameraVertex {
                hit: &hit,
                material,
                frame,
                wo_local,
                continuation: q,
                mis: path_mis,
                depth,
                hero_only: lambda.is_hero_only(),
            };
            l += beta * next_event(ctx, &v, &lambda, rng, stats);
            for y in light_path {
                if y.depth + depth > ctx.max_depth {
                    break;
                }
                l += beta * connect(ctx, &v, y, stats);
            }
            if let Some(grid) = merge {
                l += beta * merged(ctx, &v, grid, scratch) * ctx.vm_normalization;
            }
        }
        let mode = TransportMode::Radiance;
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
            break;
        };
        specular_only &= s.is_specular();
        beta *= s.weight / q;
        if !beta.is_finite() || beta == Rgb::ZERO {
            break;
        }
        ray = Ray::new(offset_origin(hit.p, hit.ng, wi), wi);
    }
    l
}

/// The weight of emission a camera subpath of `depth` segments found on light `index`
/// (at `p`, normal `n`; the sky: any point of the ray) arriving along `dir`, against
/// next-event estimation and the light subpaths that could have made the same path.
#[expect(clippy::too_many_arguments, reason = "the hit's parts, named")]
fn emission_weight(
    ctx: &PassContext,
    index: usize,
    p: Vec3,
    n: Vec3,
    dir: Vec3,
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
    let light = &ctx.scene.lights()[index];
    let pick = ctx.scene.light_choice_pmf(index);
    let pdf_direct = light.pdf_direct_area(-dir) * pick;
    let pdf_emit = light.pdf_emit(p, n, -dir) * pick;
    let w_camera = mis(pdf_direct) * path_mis.vcm + mis(pdf_emit) * path_mis.vc;
    1.0 / (1.0 + w_camera)
}

/// Next-event estimation at a camera vertex: one light chosen by power, sampled once.
fn next_event(
    ctx: &PassContext,
    v: &CameraVertex,
    lambda: &crate::spectrum::Lambda,
    rng: &mut Rng,
    stats: &mut RayStats,
) -> Rgb {
    let scene = ctx.scene;
    let Some((index, pick, _)) = scene.choose_light(rng.next_f32()) else {
        return Rgb::ZERO;
    };
    let light = &scene.lights()[index];
    let u_pick = rng.next_f32();
    let Some(ls) = light.sample_li(v.hit.p, u_pick, rng.next_2d(), lambda) else {
        return Rgb::ZERO;
    };
    let wi_local = v.frame.to_local(ls.wi);
    let f = v
        .material
        .eval(v.wo_local, wi_local, TransportMode::Radiance);
    if f == Rgb::ZERO || ls.radiance == Rgb::ZERO {
        return Rgb::ZERO;
    }
    // The density of the light's vertex seen from here, per solid angle: a light at a point
    // (density 1 of its position) has dist² (ls.pdf is 1, with 1/dist² in its radiance).
    let pdf_direct = pick
        * if light.is_delta() && !light.is_at_infinity() {
            (ls.point - v.hit.p).length_squared()
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
        v.material.pdf(v.wo_local, wi_local) * v.continuation
    };
    let reverse = v.material.pdf(wi_local, v.wo_local) * v.continuation;
    let cos_here = ls.wi.dot(v.hit.ng).abs();
    let w_light = mis(pdf_bsdf / pdf_direct);
    let w_camera = mis(pdf_emit * cos_here / (pdf_direct * cos_light))
        * (ctx.mis_vm + v.mis.vcm + v.mis.vc * mis(reverse));
    let weight = 1.0 / (w_light + 1.0 + w_camera);
    stats.shadow += 1;
    if !light_visible(ctx, v.hit, light, &ls) {
        return Rgb::ZERO;
    }
    f * ls.radiance * (weight * wi_local.z.abs() / (ls.pdf * pick))
}

/// Whether the segment from the camera vertex to the light sample is free (both ends moved
/// off their surfaces, as the path tracer's shadow rays are).
fn light_visible(
    ctx: &PassContext,
    hit: &Hit,
    light: &Light,
    ls: &crate::light::LightSample,
) -> bool {
    let origin = offset_origin(hit.p, hit.ng, ls.wi);
    let end = if ls.is_delta || light.is_at_infinity() {
        ls.point
    } else {
        offset_origin(ls.point, ls.normal, origin - ls.point)
    };
    let d = end - origin;
    let dist = d.length();
    dist > 0.0 && !ctx.scene.occluded(origin, d / dist, dist)
}

/// A connection of a camera vertex to a light vertex, weighed against every other
/// technique for the same path.
fn connect(ctx: &PassContext, x: &CameraVertex, y: &LightVertex, stats: &mut RayStats) -> Rgb {
    let d = y.hit.p - x.hit.p;
    let dist2 = d.length_squared();
    if dist2 == 0.0 {
        return Rgb::ZERO;
    }
    let dist = dist2.sqrt();
    let w = d / dist;
    let wi_x = x.frame.to_local(w);
    let f_x = x.material.eval(x.wo_local, wi_x, TransportMode::Radiance);
    if f_x == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let mut lambda_y = y.lambda_in;
    let (material_y, frame_y) = ctx.scene.surface(&y.hit, y.wo, &mut lambda_y);
    let wo_y = frame_y.to_local(y.wo);
    let wi_y = frame_y.to_local(-w);
    let f_y = material_y.eval(wo_y, wi_y, TransportMode::Importance);
    if f_y == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let cos_x = w.dot(x.hit.ng).abs();
    let cos_y = w.dot(y.hit.ng).abs();
    // Each side's density of the other's position, per unit area.
    let camera_pdf_area = x.material.pdf(x.wo_local, wi_x) * x.continuation * cos_y / dist2;
    let light_pdf_area = material_y.pdf(wo_y, wi_y) * y.continuation * cos_x / dist2;
    let reverse_x = x.material.pdf(wi_x, x.wo_local) * x.continuation;
    let reverse_y = material_y.pdf(wi_y, wo_y) * y.continuation;
    let w_light = mis(camera_pdf_area) * (ctx.mis_vm + y.mis.vcm + y.mis.vc * mis(reverse_y));
    let w_camera = mis(light_pdf_area) * (ctx.mis_vm + x.mis.vcm + x.mis.vc * mis(reverse_x));
    let weight = 1.0 / (w_light + 1.0 + w_camera);
    let value = f_x
        * f_y
        * y.beta
        * (weight * wi_x.z.abs() * cos_y / dist2 * hero_tripled_once(x.hero_only, y.hero_only));
    if value == Rgb::ZERO || !value.is_finite() {
        return Rgb::ZERO;
    }
    stats.shadow += 1;
    let from = offset_origin(x.hit.p, x.hit.ng, w);
    let to = offset_origin(y.hit.p, y.hit.ng, -w);
    let span = to - from;
    let length = span.length();
    if length > 0.0 && ctx.scene.occluded(from, span / length, length) {
        return Rgb::ZERO;
    }
    value
}

/// The merges at a camera vertex: Σ f · β over the light vertices within the radius on the
/// same side of the same kind of surface, each weighed against the other techniques
/// (before the density estimate's 1 / (π r² N)).
fn merged(
    ctx: &PassContext,
    x: &CameraVertex,
    grid: &VertexGrid,
    scratch: &mut QueryScratch,
) -> Rgb {
    let mut sum = Rgb::ZERO;
    let ng = x.hit.ng_facing(x.frame.to_world(x.wo_local));
    grid.for_each_near(x.hit.p, scratch, |y| {
        if y.depth + x.depth > ctx.max_depth + 1 || y.ng.dot(ng) <= 0.0 {
            return;
        }
        let wi = x.frame.to_local(y.wo);
        let f = x.material.eval(x.wo_local, wi, TransportMode::Radiance);
        if f == Rgb::ZERO {
            return;
        }
        let camera_pdf = x.material.pdf(x.wo_local, wi) * x.continuation;
        let reverse = x.material.pdf(wi, x.wo_local) * y.continuation;
        let w_light = y.vcm * ctx.mis_vc + y.vm * mis(camera_pdf);
        let w_camera = x.mis.vcm * ctx.mis_vc + x.mis.vm * mis(reverse);
        let weight = 1.0 / (w_light + 1.0 + w_camera);
        sum += f * y.beta * (weight * hero_tripled_once(x.hero_only, y.hero_only));
    });
    sum
}
