//! Parallel, deterministic rendering of an image.
//!
//! The image is cut into tiles rendered by rayon in any order on any number of threads. Each
//! sample's random stream is keyed by (seed, pixel index, sample index), and each pixel's
//! samples are summed in sample order, so the image is bit-identical whatever the thread count.

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter, stratified_2d};
use crate::integrator::{Integrator, RayStats, Sample};
use crate::math::Rgb;
use crate::sampling::Rng;
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

const TILE: u32 = 16;

/// The pixels of one finished tile, with the rays it traced.
type TileResult = (Vec<(u32, u32, Sample)>, RayStats);

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

/// Most memory the per-pixel state of one render may take: 8 GiB. (An SPPM render of
/// 32768² asked for 68 GB and aborted while allocating.)
pub const MAX_PIXEL_BYTES: u64 = 8 << 30;

/// What a render keeps per pixel: the beauty and five AOV images of 3 × f32.
pub const RENDER_BYTES_PER_PIXEL: u64 = 6 * 12;

/// Refuse, with the estimate, a resolution whose per-pixel state would exceed
/// [`MAX_PIXEL_BYTES`].
pub fn check_pixel_memory(width: u32, height: u32, bytes_per_pixel: u64, what: &str) -> Result<()> {
    let bytes = u64::from(width) * u64::from(height) * bytes_per_pixel;
    if bytes > MAX_PIXEL_BYTES {
        return Err(Error::InvalidSetting(format!(
            "{what} of {width}×{height} would need {:.1} GB for its pixels ({bytes_per_pixel} bytes each), more than the {:.1} GB allowed; render smaller",
            bytes as f64 / 1e9,
            MAX_PIXEL_BYTES as f64 / 1e9
        )));
    }
    Ok(())
}

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
        check_pixel_memory(self.width, self.height, RENDER_BYTES_PER_PIXEL, "a render")?;
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

/// Images beside the beauty image: the photon integrator's split by light path, and the
/// albedo and normal of the first diffuse surface (as denoisers want them).
#[derive(Clone, Debug, PartialEq)]
pub struct Aovs {
    pub direct: Image,
    pub caustic: Image,
    pub indirect: Image,
    pub albedo: Image,
    pub normal: Image,
}

pub struct RenderOutput {
    pub image: Image,
    pub aovs: Aovs,
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
    let blank = Image::new(settings.width, settings.height);
    let mut image = blank.clone();
    let mut aovs = Aovs {
        direct: blank.clone(),
        caustic: blank.clone(),
        indirect: blank.clone(),
        albedo: blank.clone(),
        normal: blank,
    };
    let mut rays = RayStats::default();
    for (pixels, stats) in tiles {
        rays.add(&stats);
        for (x, y, s) in pixels {
            image.set(x, y, s.beauty);
            aovs.direct.set(x, y, s.direct);
            aovs.caustic.set(x, y, s.caustic);
            aovs.indirect.set(x, y, s.indirect);
            aovs.albedo.set(x, y, s.albedo);
            aovs.normal.set(x, y, s.normal);
        }
    }
    Ok(RenderOutput {
        image,
        aovs,
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
) -> Sample {
    let pixel = u64::from(y) * u64::from(s.width) + u64::from(x);
    let rotation = Rng::keyed(s.seed, &[pixel, u64::MAX]).next_2d();
    let mut mean = PixelMean::default();
    for i in 0..s.spp {
        let mut rng = Rng::keyed(s.seed, &[pixel, u64::from(i)]);
        let u = stratified_2d(i, s.spp, rotation, rng.next_2d());
        let ray = camera.ray(s.filter.sample_position(x, y, u));
        mean.add(&integrator.sample(scene, &ray, &mut rng, stats));
    }
    mean.finish(integrator.splits_components())
}

/// Running per-component means of a pixel's samples. A NaN or infinity must not poison the
/// pixel, so a non-finite component of a sample is left out of that component's mean (and
/// not counted in it, which would darken the pixel), while the sample's other components,
/// say its direct light when a photon estimate overflowed, are kept.
#[derive(Default)]
struct PixelMean {
    sums: [Rgb; 6],
    counts: [u32; 6],
}

impl PixelMean {
    fn add(&mut self, l: &Sample) {
        let parts = [
            l.beauty, l.direct, l.caustic, l.indirect, l.albedo, l.normal,
        ];
        for ((sum, count), v) in self.sums.iter_mut().zip(&mut self.counts).zip(parts) {
            if v.is_finite() {
                *sum += v;
                *count += 1;
            }
        }
    }

    fn finish(&self, splits_components: bool) -> Sample {
        let mean = |j: usize| {
            if self.counts[j] == 0 {
                Rgb::ZERO
            } else {
                self.sums[j] / self.counts[j] as f32
            }
        };
        let (direct, caustic, indirect) = (mean(1), mean(2), mean(3));
        Sample {
            // Keep direct + caustic + indirect = beauty when a component was dropped.
            beauty: if splits_components {
                direct + caustic + indirect
            } else {
                mean(0)
            },
            direct,
            caustic,
            indirect,
            albedo: mean(4),
            normal: self.sums[5].normalize_or_zero(),
        }
    }
}
