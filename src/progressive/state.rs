use super::pixels::{Pixels, add_finite, sppm_update};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter};
use crate::integrator::vcm::VcmMode;
use crate::integrator::{RayStats, VisiblePoint, VolumePoint, trace_camera_path};
use crate::material::{Part, TransportMode};
use crate::math::{Rgb, Vec2, plane_tolerance};
use crate::photon::estimate::{EXACT_NORMAL_ERROR, disc_distance2};
use crate::photon::grid::{PhotonGrid, QueryScratch};
use crate::photon::{PassPhoton, VolumePhoton, trace_indirect_photons};
use crate::sampling::halton::{PassJitter, Prefixed};
use crate::sampling::{Rng, mix64};
use crate::scene::Scene;
use crate::spectrum::{Lambda, Wavelengths};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Sppm,
    Ppm,
    /// Vertex connection and merging, and its modes (see [`crate::integrator::vcm`]).
    Vcm,
    Bdpt,
    LightTrace,
}

impl Method {
    pub const ALL: [Method; 5] = [
        Method::Sppm,
        Method::Ppm,
        Method::Vcm,
        Method::Bdpt,
        Method::LightTrace,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Method::Sppm => "sppm",
            Method::Ppm => "ppm",
            Method::Vcm => "vcm",
            Method::Bdpt => "bdpt",
            Method::LightTrace => "lighttrace",
        }
    }

    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The techniques of a vertex connection and merging method.
    pub fn vcm_mode(self) -> Option<VcmMode> {
        match self {
            Method::Vcm => Some(VcmMode::Vcm),
            Method::Bdpt => Some(VcmMode::Bdpt),
            Method::LightTrace => Some(VcmMode::LightTrace),
            Method::Sppm | Method::Ppm => None,
        }
    }

    /// Whether each pass is independent of the others given its index, so that passes can
    /// be rendered apart and merged (every method but SPPM, whose pixels carry their radius
    /// from pass to pass).
    pub fn has_independent_passes(self) -> bool {
        self != Method::Sppm
    }

    /// Initial gather radius in pixel footprints at each visible point, when none is given.
    /// Chosen by measurement, in same-minute pairs at 10 s: SPPM shrinks each pixel's radius
    /// as its photons arrive, so it can start wider: 6 footprints lowered its relMSE by about
    /// 15% on `cornell` (0.0013–0.0014 against 0.0015–0.0017 at 4) and 30% on `seed` (0.0027
    /// against 0.0039–0.0041), the caustic crop unchanged within its noise. PPM shrinks every
    /// radius alike, and 4 stayed its best on `cornell` (3, 6 and 8 were worse).
    pub fn footprint_pixels(self) -> f32 {
        match self {
            Method::Sppm => 6.0,
            Method::Ppm => 4.0,
            Method::Vcm | Method::Bdpt | Method::LightTrace => {
                super::vcm_pass::VCM_FOOTPRINT_PIXELS
            }
        }
    }
}

/// Everything that determines the image (and so must match on resume and merge).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgressiveConfig {
    pub method: Method,
    pub width: u32,
    pub height: u32,
    pub seed: u64,
    /// Radius reduction parameter α in (0, 1).
    pub alpha: f64,
    pub photons_per_pass: u64,
    /// Initial gather radius in scene units; `None`: [`Method::footprint_pixels`] pixel
    /// footprints at each pixel's visible point.
    pub initial_radius: Option<f32>,
    pub max_depth: u32,
    pub light_samples: u32,
    /// Spectral rendering: each pass's camera paths and photons share three wavelengths
    /// (hero-wavelength sampling; the hero stratified over passes), as pbrt-v4's SPPM does.
    pub spectral: bool,
}

impl ProgressiveConfig {
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::InvalidSetting(m));
        if self.width == 0 || self.height == 0 || self.width > 32_768 || self.height > 32_768 {
            return bad(format!(
                "resolution {}×{} is out of range",
                self.width, self.height
            ));
        }
        // Per pixel: SPPM's state (r², N, τ, direct: 8 × f64) or PPM's sums (3 × i128), the
        // image, and the pass's visible-point slot.
        // Vertex connection and merging: the sums, the pass's image, and a light subpath's
        // vertices (about four of 176 bytes at the albedos of real scenes; Russian roulette
        // ends longer ones).
        let per_pixel = match self.method {
            Method::Sppm => 64 + 12 + SLOT_BYTES,
            Method::Ppm => 48 + 12 + SLOT_BYTES,
            Method::Vcm | Method::Bdpt | Method::LightTrace => 48 + 12 + 4 * 176,
        };
        let what = match self.method {
            Method::Sppm => "an SPPM render",
            Method::Ppm => "a PPM render",
            Method::Vcm | Method::Bdpt | Method::LightTrace => {
                "a vertex connection and merging render"
            }
        };
        crate::render::check_pixel_memory(self.width, self.height, per_pixel, what)?;
        if !(self.alpha > 0.0 && self.alpha < 1.0) {
            return bad(format!("alpha {} must be in (0, 1)", self.alpha));
        }
        if self.photons_per_pass == 0 || self.photons_per_pass > crate::photon::MAX_PHOTONS {
            return bad(format!(
                "photons per pass {} out of range",
                self.photons_per_pass
            ));
        }
        if let Some(r) = self.initial_radius
            && !(r > 0.0 && r.is_finite())
        {
            return bad(format!("initial radius {r} must be positive"));
        }
        Ok(())
    }
}

/// Accumulated state: what a checkpoint holds.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgressiveState {
    pub config: ProgressiveConfig,
    pub scene_name: String,
    pub scene_hash: u64,
    /// First pass of this state (0 except for PPM partial renders).
    pub first_pass: u64,
    /// Passes accumulated so far (from `first_pass`).
    pub passes: u64,
    /// Every pixel's accumulated light, in the method's form.
    pub pixels: Pixels,
    /// Memory each pass reuses; not part of the state.
    pub buffers: PassBuffers,
}

/// A pass's per-pixel visible points, kept between passes so that a pass neither allocates
/// nor page-faults its slot per pixel anew (it was a fifth of a 512² pass). Never saved,
/// compared or cloned: two states with different buffers are the same state.
#[derive(Default)]
pub struct PassBuffers {
    points: Vec<PassSlot>,
}

impl Clone for PassBuffers {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl PartialEq for PassBuffers {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for PassBuffers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PassBuffers")
    }
}

/// What one pass did.
#[derive(Clone, Copy, Debug, Default)]
pub struct PassStats {
    pub photons_emitted: u64,
    /// Photons kept for gathering (those that did not come straight from a light).
    pub photons_stored: u64,
    pub rays: RayStats,
    pub seconds: PassSeconds,
}

/// Where a pass's wall-clock time went (for benchmarks; never part of the image).
#[derive(Clone, Copy, Debug, Default)]
pub struct PassSeconds {
    /// Camera paths to the visible points, with their direct light.
    pub camera: f64,
    /// Photon tracing and the grid build.
    pub photons: f64,
    /// Every visible point's gather and the pixel updates.
    pub gather: f64,
}

impl ProgressiveState {
    pub fn new(scene: &Scene, config: ProgressiveConfig, first_pass: u64) -> Result<Self> {
        config.validate()?;
        let n = config.width as usize * config.height as usize;
        Ok(Self {
            scene_name: scene.name.clone(),
            scene_hash: scene.content_hash(),
            first_pass,
            passes: 0,
            pixels: Pixels::new(config.method, n),
            config,
            buffers: PassBuffers::default(),
        })
    }

    /// Index of the next pass to run.
    pub fn next_pass(&self) -> u64 {
        self.first_pass + self.passes
    }

    /// Run the next pass: every pixel's camera path to its visible point, then the pass's
    /// photons splatted into those points (see [`super::splat`]), then each pixel's update.
    pub fn run_pass(&mut self, scene: &Scene) -> Result<PassStats> {
        self.run_pass_cancellable(scene, &AtomicBool::new(false))
    }

    /// [`Self::run_pass`], abandoned when `cancel` is set (checked between rows and phases):
    /// then `Error::Cancelled`, and the state is that of the passes completed before. A pass
    /// changes the state only in its last step, which is not cancelled.
    pub fn run_pass_cancellable(
        &mut self,
        scene: &Scene,
        cancel: &AtomicBool,
    ) -> Result<PassStats> {
        let c = self.config.clone();
        let pass = self.next_pass();
        if let Some(mode) = c.method.vcm_mode() {
            let Pixels::Ppm(sums) = &mut self.pixels else {
                return Err(Error::InvalidSetting("pixels of another method".into()));
            };
            let stats = super::vcm_pass::run(scene, &c, mode, pass, sums, cancel)?;
            self.passes += 1;
            return Ok(stats);
        }
        let camera = Camera::new(&scene.camera, c.width, c.height)
            .ok_or_else(|| Error::InvalidScene("degenerate camera".into()))?;
        // Pixel footprint per unit distance, for the automatic radius.
        let footprint = 2.0 * (0.5 * scene.camera.fov_y_deg.to_radians()).tan() / c.height as f32;
        let width = c.width as usize;
        let initial_r = |vp: &VisiblePoint| {
            c.initial_radius
                .unwrap_or(c.method.footprint_pixels() * footprint * vp.distance)
        };
        let ppm_r_scale = ppm_radius_scale(pass, c.alpha);
        // Volume points gather in balls whose radius follows the PPM schedule in three
        // dimensions for either method (see `volume_radius_scale`).
        let volume_r_scale = volume_radius_scale(pass, c.alpha);
        let volume_r0 = |distance: f32| {
            VOLUME_RADIUS_FACTOR
                * c.initial_radius
                    .unwrap_or(c.method.footprint_pixels() * footprint * distance)
        };
        let jitter = PassJitter::new(c.seed, pass);
        let lambda = match c.spectral {
            true => Lambda::sampled(Wavelengths::sample_visible(jitter.wavelength())),
            false => Lambda::Rgb,
        };
        let stopped = || cancel.load(Ordering::Relaxed);
        let start = Instant::now();
        // 1. Every pixel's camera path: its direct light and visible point.
        let mut slots = std::mem::take(&mut self.buffers.points);
        slots.resize(width * c.height as usize, PassSlot::default());
        let sppm = match &self.pixels {
            Pixels::Sppm(px) => px.as_slice(),
            Pixels::Ppm(_) => &[],
        };
        let rays = camera_paths(&mut slots, width, &stopped, |x, y, stats| {
            let ray = camera_ray(&camera, &c, &jitter, x, y);
            let pixel = y * width + x;
            let mut rng = Rng::keyed(c.seed, &[pass, pixel as u64, 0x9a55]);
            let mut sampler = Prefixed::new(jitter.light(pixel as u64), &mut rng);
            let path = trace_camera_path(
                scene,
                &ray,
                lambda,
                c.max_depth,
                c.light_samples,
                &mut sampler,
                stats,
            );
            let volume = path.volume.map(|vp| VolumeSlot {
                r: volume_r0(vp.distance) * volume_r_scale,
                vp,
            });
            let point = path.visible.map(|vp| {
                let r2 = match c.method {
                    Method::Sppm if sppm[pixel].r2 > 0.0 => sppm[pixel].r2 as f32,
                    Method::Sppm => f64::from(initial_r(&vp)).powi(2) as f32,
                    // (The vcm family's passes run in `vcm_pass`.)
                    _ => {
                        let r = f64::from(initial_r(&vp)) * f64::from(ppm_r_scale);
                        (r * r) as f32
                    }
                };
                PassPoint { vp, r2 }
            });
            PassSlot {
                direct: path.direct,
                point,
                volume,
                ..PassSlot::default()
            }
        });
        let camera_done = start.elapsed();
        // 2 and 3. The pass's photons, and each visible point's gather.
        let (photons_stored, photons_done) =
            photons_and_gather(scene, &c, pass, lambda, &mut slots, &stopped, start)?;
        if stopped() {
            self.buffers.points = slots;
            return Err(Error::Cancelled);
        }
        // 4. Each pixel takes its direct light and its gather (in RGB).
        if lambda.is_spectral() {
            slots_to_rgb(&mut slots, &lambda);
        }
        self.apply(&slots, &initial_r);
        self.buffers.points = slots;
        self.passes += 1;
        Ok(PassStats {
            photons_emitted: c.photons_per_pass,
            photons_stored,
            rays,
            seconds: PassSeconds {
                camera: camera_done.as_secs_f64(),
                photons: (photons_done - camera_done).as_secs_f64(),
                gather: (start.elapsed() - photons_done).as_secs_f64(),
            },
        })
    }

    /// The last step of a pass: every pixel adds its slot's direct light, then its photons
    /// (SPPM: the α rule on the radius the pixel had, or the initial one).
    fn apply(&mut self, slots: &[PassSlot], initial_r: &(impl Fn(&VisiblePoint) -> f32 + Sync)) {
        let alpha = self.config.alpha;
        match &mut self.pixels {
            Pixels::Sppm(pixels) => pixels.par_iter_mut().zip(slots).for_each(|(px, slot)| {
                add_finite(&mut px.direct, slot.direct);
                if let Some(v) = &slot.point {
                    if px.r2 == 0.0 {
                        px.r2 = f64::from(initial_r(&v.vp)).powi(2);
                    }
                    sppm_update(px, alpha, slot.phi, slot.m);
                }
            }),
            Pixels::Ppm(pixels) => pixels.par_iter_mut().zip(slots).for_each(|(px, slot)| {
                px.add_finite(slot.direct);
                if let Some(v) = &slot.point
                    && slot.m > 0
                {
                    // In f64: π r² underflows f32 for tiny radii.
                    let inv_area = 1.0 / (PI * f64::from(v.r2));
                    px.add_finite(Rgb::from_array(slot.phi.map(|x| (x * inv_area) as f32)));
                }
            }),
        }
    }

    /// The image after the passes so far.
    pub fn image(&self) -> Image {
        let c = &self.config;
        let mut img = Image::new(c.width, c.height);
        let passes = self.passes.max(1) as f64;
        match &self.pixels {
            Pixels::Sppm(pixels) => {
                for (i, px) in pixels.iter().enumerate() {
                    let mut l = [0.0f32; 3];
                    for (k, v) in l.iter_mut().enumerate() {
                        let photons = if px.r2 > 0.0 {
                            px.tau[k] / (PI * px.r2)
                        } else {
                            0.0
                        };
                        *v = ((px.direct[k] + photons) / passes) as f32;
                    }
                    img.pixels[i] = Rgb::from_array(l);
                }
            }
            Pixels::Ppm(pixels) => {
                for (i, px) in pixels.iter().enumerate() {
                    img.pixels[i] = px.mean(passes);
                }
            }
        }
        img
    }

    /// Add the passes of another PPM state of the same scene and settings: the one rule by
    /// which partial renders combine, exactly (the sums are fixed point). The caller decides
    /// which ranges may be combined; the state then starts at the earlier first pass.
    pub fn add_passes(&mut self, other: &ProgressiveState) -> Result<()> {
        let bad = |m: &str| Err(Error::InvalidSetting(m.into()));
        let (Pixels::Ppm(sum), Pixels::Ppm(add)) = (&mut self.pixels, &other.pixels) else {
            return bad(NOT_MERGEABLE);
        };
        if other.config != self.config || other.scene_hash != self.scene_hash {
            return bad("the parts differ in scene or settings");
        }
        for (a, b) in sum.iter_mut().zip(add) {
            a.add(b);
        }
        self.passes += other.passes;
        self.first_pass = self.first_pass.min(other.first_pass);
        Ok(())
    }

    /// Combine PPM partial renders (any order) into one state of one pass range: they must
    /// cover contiguous, non-overlapping ranges, and combine by [`Self::add_passes`].
    pub fn merge(mut parts: Vec<ProgressiveState>) -> Result<ProgressiveState> {
        if parts.is_empty() {
            return Err(Error::InvalidSetting("nothing to merge".into()));
        }
        parts.sort_by_key(|p| p.first_pass);
        let mut rest = parts.into_iter();
        let mut out = rest.next().expect("one part at least");
        if !out.config.method.has_independent_passes() {
            return Err(Error::InvalidSetting(NOT_MERGEABLE.into()));
        }
        for p in rest {
            if p.first_pass != out.next_pass() {
                return Err(Error::InvalidSetting(format!(
                    "pass ranges do not join: {}..{} then {}..{}",
                    out.first_pass,
                    out.next_pass(),
                    p.first_pass,
                    p.next_pass()
                )));
            }
            out.add_passes(&p)?;
        }
        Ok(out)
    }
}

const NOT_MERGEABLE: &str = "sppm partial renders cannot be merged (its passes depend on each other); ppm, vcm, bdpt and lighttrace can";

/// Bytes of a pixel's slot, for the memory check.
const SLOT_BYTES: u64 = 240;
const _: () = assert!(std::mem::size_of::<PassSlot>() as u64 <= SLOT_BYTES);

/// A pixel's point in a medium in this pass and its gather radius.
#[derive(Clone, Copy, Debug)]
struct VolumeSlot {
    vp: VolumePoint,
    r: f32,
}

/// A pixel's visible point in this pass and its squared gather radius.
#[derive(Clone, Copy, Debug)]
struct PassPoint {
    vp: VisiblePoint,
    r2: f32,
}

/// What a pass found for one pixel, kept apart from the pixel until the pass completes.
#[derive(Clone, Copy, Debug, Default)]
struct PassSlot {
    /// The camera path's light (emission seen, next-event estimation).
    direct: Rgb,
    point: Option<PassPoint>,
    /// Where the camera path stopped in a medium instead; its gather is added to `direct`.
    volume: Option<VolumeSlot>,
    /// The gather at `point`: Σ f·ΔΦ in watts and the photon count.
    phi: [f64; 3],
    m: u32,
}

/// Fill every pixel's slot with `f(x, y, stats)`, rows in parallel; rows not started when
/// `stopped()` are skipped. Pixels are independent, so the result does not depend on the
/// thread count.
fn camera_paths(
    slots: &mut [PassSlot],
    width: usize,
    stopped: &(impl Fn() -> bool + Sync),
    f: impl Fn(usize, usize, &mut RayStats) -> PassSlot + Sync,
) -> RayStats {
    slots
        .par_chunks_mut(width)
        .enumerate()
        .map(|(y, row)| {
            let mut stats = RayStats::default();
            if stopped() {
                return stats;
            }
            for (x, slot) in row.iter_mut().enumerate() {
                *slot = f(x, y, &mut stats);
            }
            stats
        })
        .reduce(RayStats::default, |mut a, b| {
            a.add(&b);
            a
        })
}

/// A pass's photons, in a grid whose cells suit the median gather radius, then each slot's
/// gather; skipped once `stopped()`. Returns the photons stored and when the grid was built.
fn photons_and_gather(
    scene: &Scene,
    c: &ProgressiveConfig,
    pass: u64,
    lambda: Lambda,
    slots: &mut [PassSlot],
    stopped: &(impl Fn() -> bool + Sync),
    start: Instant,
) -> Result<(u64, std::time::Duration)> {
    if stopped() {
        return Ok((0, start.elapsed()));
    }
    let seed = mix64(c.seed ^ mix64(pass.wrapping_add(0x5eed)));
    let photons =
        trace_indirect_photons(scene, c.photons_per_pass, seed, PHOTON_MAX_DEPTH, lambda)?;
    if stopped() {
        return Ok((0, start.elapsed()));
    }
    let stored = (photons.surface.len() + photons.volume.len()) as u64;
    let grid = PhotonGrid::build(photons.surface, GRID_CELL_RADII * median_radius(slots));
    let volume_grid = (!photons.volume.is_empty()).then(|| {
        PhotonGrid::build(
            photons.volume,
            GRID_CELL_RADII * median_volume_radius(slots),
        )
    });
    let done = start.elapsed();
    gather(slots, c.width as usize, &grid, photons.scale, stopped);
    if let Some(volume_grid) = &volume_grid {
        gather_volume(
            scene,
            slots,
            c.width as usize,
            volume_grid,
            photons.scale,
            stopped,
        );
    }
    Ok((stored, done))
}

/// Grid cells are this many median gather radii wide: a query then visits about (1 + 2/3)³ ≈ 5
/// cells. Cells of 2 radii (always 8 cells, each nearly empty) gathered 25% slower on
/// `cornell`: the time goes to reaching buckets, not to testing photons.
const GRID_CELL_RADII: f32 = 3.0;

/// Gather at every slot's visible point, rows in parallel, into the slot: Σ f·ΔΦ in watts
/// weighted by the camera path's throughput (a channel that overflows is dropped) and the
/// photon count. Rows not started when `stopped()` are skipped.
fn gather(
    slots: &mut [PassSlot],
    width: usize,
    grid: &PhotonGrid<PassPhoton>,
    scale: f32,
    stopped: &(impl Fn() -> bool + Sync),
) {
    for_each_slot(slots, width, stopped, |slot, scratch| {
        let Some(v) = &slot.point else {
            return;
        };
        let (flux, m) = photon_flux(grid, &v.vp, v.r2, scratch);
        slot.phi = (flux * scale * v.vp.beta)
            .to_array()
            .map(|x| if x.is_finite() { f64::from(x) } else { 0.0 });
        slot.m = m;
    });
}

/// `f(slot, scratch)` for every slot, rows in parallel with a query scratch per thread; rows
/// not started when `stopped()` are skipped.
fn for_each_slot(
    slots: &mut [PassSlot],
    width: usize,
    stopped: &(impl Fn() -> bool + Sync),
    f: impl Fn(&mut PassSlot, &mut QueryScratch) + Sync,
) {
    slots
        .par_chunks_mut(width)
        .for_each_init(QueryScratch::default, |scratch, row| {
            if stopped() {
                return;
            }
            for slot in row {
                f(slot, scratch);
            }
        });
}

/// Add every slot's in-scattered light from the photons in the ball of its volume point: the
/// volume radiance estimate (Jensen and Christensen 1998), Σ p(wo, wi) ΔΦ/σs / (4/3 π r³)
/// over the photons of the point's medium, each divided by σs where it scattered (see
/// `photon::trace`), times the path's throughput, which carries σs at the point. Rows not
/// started when `stopped()` are skipped.
fn gather_volume(
    scene: &Scene,
    slots: &mut [PassSlot],
    width: usize,
    grid: &PhotonGrid<VolumePhoton>,
    scale: f32,
    stopped: &(impl Fn() -> bool + Sync),
) {
    for_each_slot(slots, width, stopped, |slot, scratch| {
        let Some(v) = &slot.volume else {
            return;
        };
        let medium = scene.medium(v.vp.medium);
        let mut sum = Rgb::ZERO;
        grid.for_each_within(v.vp.p, v.r, scratch, &mut |ph, _| {
            if ph.medium == v.vp.medium {
                let once = hero_tripled_once(v.vp.hero_only, ph.hero_only);
                sum += ph.power * (medium.phase().eval(v.vp.wo, ph.incoming) * once);
            }
        });
        let volume = 4.0 / 3.0 * PI * f64::from(v.r).powi(3);
        let estimate = sum * (f64::from(scale) / volume) as f32;
        let l = v.vp.beta * estimate;
        if l.is_finite() {
            slot.direct += l;
        }
    });
}

/// Median gather radius of a pass's volume points (0 with none).
fn median_volume_radius(slots: &[PassSlot]) -> f32 {
    let mut r: Vec<f32> = slots.iter().filter_map(|s| s.volume).map(|v| v.r).collect();
    if r.is_empty() {
        return 0.0;
    }
    let mid = r.len() / 2;
    *r.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// Median gather radius of a pass's points (0 with none).
fn median_radius(slots: &[PassSlot]) -> f32 {
    let mut r2: Vec<f32> = slots.iter().filter_map(|s| s.point).map(|p| p.r2).collect();
    if r2.is_empty() {
        return 0.0;
    }
    let mid = r2.len() / 2;
    r2.select_nth_unstable_by(mid, f32::total_cmp).1.sqrt()
}

/// Σ f·ΔΦ (relative powers) at a visible point over the photons within its disc of radius²
/// `r2`, and the number of photons used.
fn photon_flux(
    grid: &PhotonGrid<PassPhoton>,
    vp: &VisiblePoint,
    r2: f32,
    scratch: &mut QueryScratch,
) -> (Rgb, u32) {
    let mut sum = Rgb::ZERO;
    let mut count = 0;
    let tolerance = plane_tolerance(vp.p);
    grid.for_each_within(vp.p, r2.sqrt(), scratch, &mut |ph, d2| {
        if let Some(m) = disc_distance2(
            ph.position - vp.p,
            d2,
            vp.ng,
            ph.normal,
            tolerance,
            EXACT_NORMAL_ERROR,
        ) && m <= r2
        {
            let wi = vp.frame.to_local(ph.incoming);
            let f = vp
                .material
                .eval_part(vp.wo_local, wi, TransportMode::Radiance, Part::Rough);
            sum += f * ph.power * hero_tripled_once(vp.hero_only, ph.hero_only);
            count += 1;
        }
    });
    (sum, count)
}

/// The factor for the product of a camera path's and a photon's values: 1/3 where both went
/// on with their hero alone, whose value each side tripled (see `Lambda::keep_hero_only`),
/// once too many.
fn hero_tripled_once(camera_hero_only: bool, photon_hero_only: bool) -> f32 {
    if camera_hero_only && photon_hero_only {
        1.0 / 3.0
    } else {
        1.0
    }
}

/// The pass's light at its wavelengths, as RGB: every slot's direct light and gathered
/// flux (a linear map, so sums of the pass's values convert as wholes).
fn slots_to_rgb(slots: &mut [PassSlot], lambda: &Lambda) {
    slots.par_iter_mut().for_each(|slot| {
        slot.direct = lambda.to_rgb(slot.direct);
        let phi = Rgb::from_array(slot.phi.map(|x| x as f32));
        slot.phi = lambda.to_rgb(phi).to_array().map(f64::from);
    });
}

/// A volume point's first ball is this many times the radius a surface point starts with.
/// A ball gathers the photons of a volume, a disc those of a surface, so a ball as wide as a
/// disc holds few: on `fog-spot` at 128² with 10 s of `sppm`, relMSE 0.118 at 1× (fireflies),
/// 0.133 at 2×, 0.027 at 4×, 0.041 at 8× (the gathers of the larger balls took 8 s of the 10);
/// at `photon validate --quick`'s radius, 1.01, 0.020 and 0.0092 at 1×, 4× and 8×.
const VOLUME_RADIUS_FACTOR: f32 = 4.0;

/// Maximum depth of a progressive pass's photon paths.
const PHOTON_MAX_DEPTH: u32 = 64;

/// r_p / r_0 for PPM pass p (0-based): r_{i+1}² = r_i² (i + α)/(i + 1), with r_1 = r_0.
pub fn ppm_radius_scale(pass: u64, alpha: f64) -> f32 {
    let mut r2 = 1.0f64;
    for i in 1..=pass {
        r2 *= (i as f64 + alpha) / (i as f64 + 1.0);
    }
    r2.sqrt() as f32
}

/// r_p / r_0 of a volume point's ball for pass p (0-based): r_{i+1}³ = r_i³ (i + α)/(i + 1),
/// the radius sequence of progressive photon mapping for three-dimensional kernels (Knaus and
/// Zwicker 2011, §4.3: the kernel's volume shrinks as the disc's area does on surfaces).
pub fn volume_radius_scale(pass: u64, alpha: f64) -> f32 {
    let mut r3 = 1.0f64;
    for i in 1..=pass {
        r3 *= (i as f64 + alpha) / (i as f64 + 1.0);
    }
    r3.cbrt() as f32
}

pub(super) fn camera_ray(
    camera: &Camera,
    c: &ProgressiveConfig,
    jitter: &PassJitter,
    x: usize,
    y: usize,
) -> crate::math::Ray {
    let pixel = (y * c.width as usize + x) as u64;
    let u = Vec2::from_array(jitter.position(pixel));
    let pos = PixelFilter::Box.sample_position(x as u32, y as u32, u);
    camera.ray(pos)
}
