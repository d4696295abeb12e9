//! Parallel, deterministic rendering of an image.
//!
//! The image is cut into tiles rendered by rayon in any order on any number of threads. Each
//! sample's random stream is keyed by (seed, pixel index, sample index), and each pixel's
//! samples are summed in sample order, so the image is bit-identical whatever the thread count.

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter};
use crate::integrator::{Integrator, RayStats};
use crate::math::Rgb;
use crate::sampling::Rng;
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

const TILE: u32 = 16;

/// The pixels of one finished tile, with the rays it traced.
type TileResult = (Vec<(u32, u32, Rgb)>, RayStats);

#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u64,
    pub filter: PixelFilter,
}

/// Largest image side we accept: far beyond any real use, small enough that the pixel buffer
/// cannot exhaust memory.
pub const MAX_RESOLUTION: u32 = 32_768;

impl RenderSettings {
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::InvalidSetting(m));
        if self.width == 0 || self.height == 0 {
            return bad(format!(
                "resolution {}×{} has no pixels",
                self.width, self.height
            ));
        }
        if self.width > MAX_RESOLUTION || self.height > MAX_RESOLUTION {
            return bad(format!(
                "resolution {}×{} is too large (at most {MAX_RESOLUTION} per side)",
                self.width, self.height
            ));
        }
        if self.spp == 0 {
            return bad("samples per pixel must be at least 1".into());
        }
        if let PixelFilter::Gaussian { sigma } = self.filter
            && !(sigma > 0.0 && sigma <= 16.0)
        {
            return bad(format!(
                "Gaussian filter width {sigma} must be in (0, 16] pixels"
            ));
        }
        Ok(())
    }
}

pub struct RenderOutput {
    pub image: Image,
    pub rays: RayStats,
    pub samples: u64,
}

/// Render `scene` with `integrator`. `progress(done, total)` is called as tiles finish.
pub fn render(
    scene: &Scene,
    integrator: &Integrator,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput> {
    settings.validate()?;
    let camera = Camera::new(&scene.camera, settings.width, settings.height)
        .ok_or_else(|| Error::InvalidScene("degenerate camera".into()))?;
    let tiles_x = settings.width.div_ceil(TILE);
    let tiles_y = settings.height.div_ceil(TILE);
    let total = u64::from(tiles_x * tiles_y);
    let done = AtomicU64::new(0);
    let tiles: Vec<TileResult> = (0..tiles_x * tiles_y)
        .into_par_iter()
        .map(|t| {
            let (tx, ty) = (t % tiles_x, t / tiles_x);
            let mut stats = RayStats::default();
            let mut out = Vec::with_capacity((TILE * TILE) as usize);
            for y in ty * TILE..((ty + 1) * TILE).min(settings.height) {
                for x in tx * TILE..((tx + 1) * TILE).min(settings.width) {
                    let c = render_pixel(scene, integrator, &camera, settings, x, y, &mut stats);
                    out.push((x, y, c));
                }
            }
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            (out, stats)
        })
        .collect();
    let mut image = Image::new(settings.width, settings.height);
    let mut rays = RayStats::default();
    for (pixels, stats) in tiles {
        rays.add(&stats);
        for (x, y, c) in pixels {
            image.set(x, y, c);
        }
    }
    Ok(RenderOutput {
        image,
        rays,
        samples: u64::from(settings.width) * u64::from(settings.height) * u64::from(settings.spp),
    })
}

fn render_pixel(
    scene: &Scene,
    integrator: &Integrator,
    camera: &Camera,
    s: &RenderSettings,
    x: u32,
    y: u32,
    stats: &mut RayStats,
) -> Rgb {
    let pixel = u64::from(y) * u64::from(s.width) + u64::from(x);
    let mut sum = Rgb::ZERO;
    for i in 0..s.spp {
        let mut rng = Rng::keyed(s.seed, &[pixel, u64::from(i)]);
        let ray = camera.ray(s.filter.sample_position(x, y, &mut rng));
        let l = integrator.radiance(scene, &ray, &mut rng, stats);
        // A NaN or infinity from one sample must not poison the pixel.
        if l.is_finite() {
            sum += l;
        }
    }
    sum / s.spp as f32
}
