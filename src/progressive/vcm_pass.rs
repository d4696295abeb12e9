//! A pass of vertex connection and merging (or of its modes, bidirectional path tracing
//! and light tracing): one light subpath and one camera subpath per pixel (see
//! [`crate::integrator::vcm`]). Passes are independent given their index, like PPM's: the
//! merging radius of pass p is r_0 · [`ppm_radius_scale`], and each pass's image is added to
//! the pixels' fixed-point sums, so that any split of the passes merges to the same bits.

use super::state::{PassSeconds, PassStats, ProgressiveConfig, camera_ray, ppm_radius_scale};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::film::PassSum;
use crate::integrator::RayStats;
use crate::integrator::vcm::{
    PassContext, VcmMode, VertexGrid, camera_sample, trace_light_subpaths,
};
use crate::math::{Rgb, Vec2};
use crate::photon::grid::QueryScratch;
use crate::sampling::halton::PassJitter;
use crate::sampling::{PixelSampler, Rng};
use crate::scene::Scene;
use crate::spectrum::{Lambda, Wavelengths};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// The merging radius when none is given, in pixel footprints at the median distance of
/// what the camera sees.
pub const VCM_FOOTPRINT_PIXELS: f32 = 2.0;

/// Run pass `pass` of `mode` and add its image to `sums`.
pub(super) fn run(
    scene: &Scene,
    c: &ProgressiveConfig,
    mode: VcmMode,
    pass: u64,
    sums: &mut [PassSum],
    cancel: &AtomicBool,
) -> Result<PassStats> {
    let camera = Camera::new(&scene.camera, c.width, c.height)
        .ok_or_else(|| Error::InvalidScene("degenerate camera".into()))?;
    let jitter = PassJitter::new(c.seed, pass);
    let lambda = match c.spectral {
        true => Lambda::sampled(Wavelengths::sample_visible(jitter.wavelength())),
        false => Lambda::Rgb,
    };
    let r0 = c
        .initial_radius
        .unwrap_or_else(|| automatic_radius(scene, &camera));
    let radius = (r0 * ppm_radius_scale(pass, c.alpha)).max(f32::MIN_POSITIVE);
    let hero = hero_channel(scene, c.seed, pass);
    let ctx = PassContext::new(scene, &camera, mode, c.max_depth, lambda, radius, hero);
    let stopped = || cancel.load(Ordering::Relaxed);
    let start = Instant::now();
    let light = trace_light_subpaths(&ctx, c.seed, pass, &stopped);
    let grid = mode
        .merges()
        .then(|| VertexGrid::new(&ctx, &light.vertices, radius));
    let lights_done = start.elapsed();
    let width = c.width as usize;
    let mut image = vec![Rgb::ZERO; width * c.height as usize];
    let camera_rays = image
        .par_chunks_mut(width)
        .enumerate()
        .map(|(y, row)| {
            let mut stats = RayStats::default();
            if stopped() {
                return stats;
            }
            let mut scratch = QueryScratch::default();
            for (x, px) in row.iter_mut().enumerate() {
                let ray = camera_ray(&camera, c, &jitter, x, y);
                // The pixel's numbers over the passes are Sobol points, as a pixel's samples are
                // in a render (see `PixelSampler`).
                let pixel = (y * width + x) as u64;
                let key = Rng::keyed(c.seed, &[pixel, 0x9a55]).next_u64();
                let mut rng = PixelSampler::new(key, pass as u32);
                let path = light.of((y * width + x) % ctx.light_paths as usize);
                let merge = grid.as_ref();
                *px = camera_sample(&ctx, ray, path, merge, &mut scratch, &mut rng, &mut stats);
            }
            stats
        })
        .reduce(RayStats::default, |mut a, b| {
            a.add(&b);
            a
        });
    if stopped() {
        return Err(Error::Cancelled);
    }
    for &(pixel, value) in &light.splats {
        image[pixel as usize] += value;
    }
    sums.par_iter_mut().zip(&image).for_each(|(sum, &l)| {
        sum.add_finite(lambda.to_rgb(l));
    });
    let mut rays = light.rays;
    rays.add(&camera_rays);
    Ok(PassStats {
        photons_emitted: u64::from(ctx.light_paths),
        photons_stored: light.vertices.len() as u64,
        rays,
        seconds: PassSeconds {
            camera: (start.elapsed() - lights_done).as_secs_f64(),
            photons: lights_done.as_secs_f64(),
            gather: 0.0,
        },
    })
}

/// The channel pass `pass` draws distances in media with (see [`crate::medium`]): one for
/// the whole pass, since a merge joins any two subpaths. Passes take the channels in turn
/// from one drawn for the seed, so that each pass's channel is uniform and every three
/// passes hold each channel once (a channel drawn anew each pass left a coloured furnace
/// 3% off in its colours after 1024 passes).
fn hero_channel(scene: &Scene, seed: u64, pass: u64) -> usize {
    if !scene.has_media() {
        return 0;
    }
    let first = scene.draw_hero_channel(&mut Rng::keyed(seed, &[0x4e20]));
    ((first as u64 + pass) % 3) as usize
}

/// The merging radius `vcm` takes by default for an image of `width` × `height` (see
/// [`automatic_radius`]); `None` for a degenerate camera.
pub fn default_radius(scene: &Scene, width: u32, height: u32) -> Option<f32> {
    Camera::new(&scene.camera, width, height).map(|camera| automatic_radius(scene, &camera))
}

/// [`VCM_FOOTPRINT_PIXELS`] pixel footprints at the median distance of the surfaces seen
/// through a 16×16 grid of the image (the whole scene's diagonal / 1000 where it sees
/// nothing): a radius that depends on the scene and camera alone, so every pass, part and
/// resume agrees on it.
fn automatic_radius(scene: &Scene, camera: &Camera) -> f32 {
    let n = 16;
    let mut distances: Vec<f32> = (0..n * n)
        .filter_map(|i| {
            let film = Vec2::new(
                ((i % n) as f32 + 0.5) / n as f32 * camera.width as f32,
                ((i / n) as f32 + 0.5) / n as f32 * camera.height as f32,
            );
            scene
                .intersect(&camera.ray(film), f32::INFINITY)
                .map(|h| h.t)
        })
        .collect();
    if distances.is_empty() {
        return scene.bounds().extent().length() * 1e-3;
    }
    let mid = distances.len() / 2;
    let median = *distances.select_nth_unstable_by(mid, f32::total_cmp).1;
    VCM_FOOTPRINT_PIXELS * median / camera.image_plane_distance()
}
