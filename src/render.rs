//! Parallel, deterministic rendering of an image.
//!
//! The image is cut into tiles rendered by rayon in any order on any number of threads. Each
//! sample's random stream is keyed by (seed, pixel index, sample index), so the image is
//! bit-identical whatever the thread count.
//!
//! A render may also take only samples `a..b` of each pixel's `spp` ([`render_samples`]), for
//! a render split across machines. Its pixels are then sums ([`SampleSums`]) in 128-bit fixed
//! point, which add exactly in any order: the sums of any split, added, are the sums of the
//! whole render, and give its image bit for bit.

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter, SampleSum};
use crate::integrator::{Integrator, RayStats, Sample};
use crate::math::Rgb;
use crate::sampling::{PixelSampler, Rng, Sampler};
use crate::scene::Scene;
use crate::spectrum::Lambda;
use rayon::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

const TILE: u32 = 16;

/// The pixels of one finished tile, with the rays it traced.
type TileResult = (Vec<(u32, u32, PixelMean)>, RayStats);

#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u64,
    pub filter: PixelFilter,
    /// Each sample's radiance is scaled down to at most this in every channel.
    pub max_radiance: Option<f32>,
    /// Spectral rendering: each sample carries three wavelengths (hero-wavelength sampling)
    /// instead of the RGB channels.
    pub spectral: bool,
}

impl RenderSettings {
    /// `width`×`height` at `spp` samples per pixel, seed 0, a box filter, no clamp. no clamp.
    pub fn new(width: u32, height: u32, spp: u32) -> Self {
        Self {
            width,
            height,
            spp,
            seed: 0,
            filter: PixelFilter::Box,
            max_radiance: None,
            spectral: false,
        }
    }
}

/// Largest image side we accept: far beyond any real use, small enough that the pixel buffer
/// cannot exhaust memory.
pub const MAX_RESOLUTION: u32 = 32_768;

/// Most memory the per-pixel state of one render may take: 8 GiB. (An SPPM render of
/// 32768² asked for 68 GB and aborted while allocating.)
pub const MAX_PIXEL_BYTES: u64 = 8 << 30;

/// What a render keeps per pixel: the beauty and five AOV images of 3 × f32, and the
/// fixed-point sums of four components (3 × i128 and a count each).
pub const RENDER_BYTES_PER_PIXEL: u64 = 6 * 12 + 4 * 52;

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
    /// The fixed-point sums behind `image` (and the photon integrator's components).
    pub sums: SampleSums,
}

/// Render `scene` with `integrator`. `progress(done, total)` is called as tiles finish.
pub fn render(
    scene: &Scene,
    integrator: &Integrator,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput> {
    render_samples(scene, integrator, settings, 0..settings.spp, progress)
}

/// Render samples `range` of each pixel's `settings.spp` (stratified over all `spp`). The
/// output's `sums` added to those of the other ranges give [`render`]'s sums exactly.
pub fn render_samples(
    scene: &Scene,
    integrator: &Integrator,
    settings: &RenderSettings,
    range: Range<u32>,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput> {
    let never = AtomicBool::new(false);
    render_samples_cancellable(scene, integrator, settings, range, progress, &never)
}

/// [`render_samples`], stopped by `cancel` between tiles (then `Error::Cancelled`).
pub fn render_samples_cancellable(
    scene: &Scene,
    integrator: &Integrator,
    settings: &RenderSettings,
    range: Range<u32>,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> Result<RenderOutput> {
    settings.validate()?;
    if range.is_empty() || range.end > settings.spp {
        return Err(Error::InvalidSetting(format!(
            "samples {}..{} are not a part of 0..{}",
            range.start, range.end, settings.spp
        )));
    }
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
            if cancel.load(Ordering::Relaxed) {
                return (Vec::new(), stats);
            }
            let mut out = Vec::with_capacity((TILE * TILE) as usize);
            for y in ty * TILE..((ty + 1) * TILE).min(settings.height) {
                for x in tx * TILE..((tx + 1) * TILE).min(settings.width) {
                    let c = render_pixel(
                        scene,
                        integrator,
                        &camera,
                        settings,
                        range.clone(),
                        (x, y),
                        &mut stats,
                    );
                    out.push((x, y, c));
                }
            }
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            (out, stats)
        })
        .collect();
    if cancel.load(Ordering::Relaxed) {
        return Err(Error::Cancelled);
    }
    let blank = Image::new(settings.width, settings.height);
    let mut image = blank.clone();
    let mut aovs = Aovs {
        direct: blank.clone(),
        caustic: blank.clone(),
        indirect: blank.clone(),
        albedo: blank.clone(),
        normal: blank,
    };
    let splits = integrator.splits_components();
    let mut sums = SampleSums::new(settings, range.clone(), splits);
    let mut rays = RayStats::default();
    for (pixels, stats) in tiles {
        rays.add(&stats);
        for (x, y, mean) in pixels {
            sums.set(x, y, &mean);
            let s = mean.finish(splits);
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
        samples: u64::from(settings.width)
            * u64::from(settings.height)
            * u64::from(range.len() as u32),
        sums,
    })
}

fn render_pixel(
    scene: &Scene,
    integrator: &Integrator,
    camera: &Camera,
    s: &RenderSettings,
    range: Range<u32>,
    (x, y): (u32, u32),
    stats: &mut RayStats,
) -> PixelMean {
    let pixel = u64::from(y) * u64::from(s.width) + u64::from(x);
    let key = Rng::keyed(s.seed, &[pixel]).next_u64();
    let mut mean = PixelMean::default();
    for i in range {
        let mut rng = PixelSampler::new(key, i);
        let u = rng.next_2d();
        let ray = camera.ray(s.filter.sample_position(x, y, u));
        let mut lambda = Lambda::draw(s.spectral, &mut rng);
        let sample = integrator
            .sample(scene, &ray, &mut lambda, &mut rng, stats)
            .to_rgb(&lambda);
        mean.add(&match s.max_radiance {
            Some(max) => sample.clamped(max),
            None => sample,
        });
    }
    mean
}

/// Components kept in fixed point: beauty, direct, caustic, indirect.
const FIXED_COMPONENTS: usize = 4;

/// The mean of `count` samples whose fixed-point sum is `sum` (zero without any).
fn mean_of(sum: &SampleSum, count: u32) -> Rgb {
    if count == 0 {
        Rgb::ZERO
    } else {
        sum.mean(f64::from(count))
    }
}

/// Running per-component means of a pixel's samples. A NaN or infinity must not poison the
/// pixel, so a non-finite component of a sample is left out of that component's mean (and
/// not counted in it, which would darken the pixel), while the sample's other components,
/// say its direct light when a photon estimate overflowed, are kept. The light components are
/// summed in fixed point (see the module's note); the albedo and normal AOVs in floats.
#[derive(Default)]
struct PixelMean {
    fixed: [SampleSum; FIXED_COMPONENTS],
    floats: [Rgb; 2],
    counts: [u32; 6],
}

impl PixelMean {
    fn add(&mut self, l: &Sample) {
        let parts = [
            l.beauty, l.direct, l.caustic, l.indirect, l.albedo, l.normal,
        ];
        for (j, v) in parts.into_iter().enumerate() {
            if !v.is_finite() {
                continue;
            }
            self.counts[j] += 1;
            if j < FIXED_COMPONENTS {
                if v != Rgb::ZERO {
                    self.fixed[j].add_finite(v);
                }
            } else {
                self.floats[j - FIXED_COMPONENTS] += v;
            }
        }
    }

    fn finish(&self, splits_components: bool) -> Sample {
        let mean = |j: usize| mean_of(&self.fixed[j], self.counts[j]);
        let (direct, caustic, indirect) = (mean(1), mean(2), mean(3));
        let albedo = if self.counts[4] == 0 {
            Rgb::ZERO
        } else {
            self.floats[0] / self.counts[4] as f32
        };
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
            albedo,
            normal: self.floats[1].normalize_or_zero(),
        }
    }
}

/// The fixed-point sums of a render's light per pixel: of the beauty alone, or of the
/// direct, caustic and indirect parts for an integrator that splits them.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleSums {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the whole render.
    pub spp: u32,
    /// How many of each pixel's `spp` samples these sums hold.
    pub samples: u32,
    /// The beauty is the sum of the direct, caustic and indirect means.
    pub splits_components: bool,
    /// Per pixel (row-major), per component: the sum and the count of finite samples.
    pub sums: Vec<(SampleSum, u32)>,
}

impl SampleSums {
    fn new(settings: &RenderSettings, range: Range<u32>, splits_components: bool) -> Self {
        let pixels = settings.width as usize * settings.height as usize;
        Self {
            width: settings.width,
            height: settings.height,
            spp: settings.spp,
            samples: range.end - range.start,
            splits_components,
            sums: vec![(SampleSum::default(), 0); pixels * Self::components_of(splits_components)],
        }
    }

    fn components_of(splits_components: bool) -> usize {
        if splits_components { 4 } else { 1 }
    }

    /// Light components kept per pixel.
    pub fn components(&self) -> usize {
        Self::components_of(self.splits_components)
    }

    fn set(&mut self, x: u32, y: u32, mean: &PixelMean) {
        let n = self.components();
        let at = (y as usize * self.width as usize + x as usize) * n;
        for (j, slot) in self.sums[at..at + n].iter_mut().enumerate() {
            *slot = (mean.fixed[j], mean.counts[j]);
        }
    }

    /// Add the sums of another part of the same render.
    pub fn add(&mut self, other: &SampleSums) -> Result<()> {
        if (self.width, self.height, self.spp, self.splits_components)
            != (
                other.width,
                other.height,
                other.spp,
                other.splits_components,
            )
            || self.sums.len() != other.sums.len()
        {
            return Err(Error::InvalidSetting(
                "the partial renders differ in resolution, samples per pixel or integrator".into(),
            ));
        }
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            a.0.add(&b.0);
            a.1 = a.1.saturating_add(b.1);
        }
        self.samples = self.samples.saturating_add(other.samples);
        Ok(())
    }

    /// The beauty image of the samples summed so far.
    pub fn image(&self) -> Image {
        let mut image = Image::new(self.width, self.height);
        let n = self.components();
        for (pixel, px) in image.pixels.iter_mut().zip(self.sums.chunks_exact(n)) {
            let mean = |j: usize| mean_of(&px[j].0, px[j].1);
            *pixel = if self.splits_components {
                mean(1) + mean(2) + mean(3)
            } else {
                mean(0)
            };
        }
        image
    }
}
