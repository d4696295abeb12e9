use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter};
use crate::integrator::{RayStats, VisiblePoint, trace_camera_path};
use crate::material::{Part, TransportMode};
use crate::math::{Rgb, Vec2, surface_epsilon};
use crate::photon::estimate::{EXACT_NORMAL_ERROR, disc_distance2};
use crate::photon::grid::{PhotonGrid, QueryScratch};
use crate::photon::{PassPhoton, trace_indirect_photons};
use crate::sampling::halton::{PassJitter, Prefixed};
use crate::sampling::{Rng, mix64};
use crate::scene::Scene;
use rayon::prelude::*;
use std::f64::consts::PI;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Sppm,
    Ppm,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Sppm => "sppm",
            Method::Ppm => "ppm",
        }
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
}

/// Fixed-point scale of the PPM pass sums (2⁻²⁴ W·m⁻²·sr⁻¹ resolution).
const FIXED: f64 = 16_777_216.0;

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
        let per_pixel = match self.method {
            Method::Sppm => 64 + 12 + SLOT_BYTES,
            Method::Ppm => 48 + 12 + SLOT_BYTES,
        };
        let what = match self.method {
            Method::Sppm => "an SPPM render",
            Method::Ppm => "a PPM render",
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

/// One SPPM pixel (pbrt-v4's SPPMPixel in spirit): radius², photon count N, flux τ, and the
/// sum of the direct light of all passes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SppmPixel {
    pub r2: f64,
    pub n: f64,
    pub tau: [f64; 3],
    pub direct: [f64; 3],
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
    pub sppm: Vec<SppmPixel>,
    /// PPM: per pixel, the sum over passes of the radiance in fixed point (128 bits: 64 wrapped
    /// to negative pixels for a light of radiance 3·10¹¹ at 2 passes; saturating, never
    /// wrapping, even for the largest f32).
    pub ppm: Vec<[i128; 3]>,
    /// Memory each pass reuses; not part of the state.
    pub buffers: PassBuffers,
}

/// A pass's per-pixel visible points, kept between passes so that a pass neither allocates
/// nor page-faults 128 bytes per pixel anew (it was a fifth of a 512² pass). Never saved,
/// compared or cloned: two states with different buffers are the same state.
#[derive(Default)]
pub struct PassBuffers {
    points: Vec<Option<PassPoint>>,
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
            sppm: if config.method == Method::Sppm {
                vec![SppmPixel::default(); n]
            } else {
                Vec::new()
            },
            ppm: if config.method == Method::Ppm {
                vec![[0; 3]; n]
            } else {
                Vec::new()
            },
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
        let c = self.config.clone();
        let pass = self.next_pass();
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
        let jitter = PassJitter::new(c.seed, pass);
        let trace = |x: usize, y: usize, stats: &mut RayStats| {
            let (ray, mut rng) = camera_ray(&camera, &c, &jitter, pass, x, y);
            let pixel = (y * width + x) as u64;
            let mut sampler = Prefixed::new(jitter.light(pixel), &mut rng);
            trace_camera_path(
                scene,
                &ray,
                c.max_depth,
                c.light_samples,
                &mut sampler,
                stats,
            )
        };
        let start = Instant::now();
        // 1. Visible points, with the direct light added to each pixel as it is found.
        let mut slots = std::mem::take(&mut self.buffers.points);
        slots.resize(
            self.config.width as usize * self.config.height as usize,
            None,
        );
        let rays = match c.method {
            Method::Sppm => visible_points(&mut self.sppm, &mut slots, width, |x, y, px, stats| {
                let path = trace(x, y, stats);
                add_finite(&mut px.direct, path.direct);
                let vp = path.visible?;
                if px.r2 == 0.0 {
                    px.r2 = f64::from(initial_r(&vp)).powi(2);
                }
                Some((vp, px.r2 as f32))
            }),
            Method::Ppm => visible_points(&mut self.ppm, &mut slots, width, |x, y, px, stats| {
                let path = trace(x, y, stats);
                add_fixed(px, path.direct);
                let vp = path.visible?;
                let r = f64::from(initial_r(&vp)) * f64::from(ppm_r_scale);
                Some((vp, (r * r) as f32))
            }),
        };
        let camera_done = start.elapsed();
        // 2. Photons, in a grid whose cells suit the median gather radius.
        let seed = mix64(c.seed ^ mix64(pass.wrapping_add(0x5eed)));
        let (photons, scale) =
            trace_indirect_photons(scene, c.photons_per_pass, seed, PHOTON_MAX_DEPTH)?;
        let photons_stored = photons.len() as u64;
        let grid = PhotonGrid::build(photons, GRID_CELL_RADII * median_radius(&slots));
        let photons_done = start.elapsed();
        // 3. Each visible point gathers, and its pixel takes the result.
        let (alpha, w) = (c.alpha, width);
        match c.method {
            Method::Sppm => {
                gather_into(&mut self.sppm, &slots, w, &grid, scale, |px, _, phi, m| {
                    sppm_update(px, alpha, phi, m);
                })
            }
            Method::Ppm => gather_into(&mut self.ppm, &slots, w, &grid, scale, |px, r2, phi, m| {
                if m > 0 {
                    // In f64: π r² underflows f32 for tiny radii.
                    let inv_area = 1.0 / (PI * f64::from(r2));
                    add_fixed(px, Rgb::from_array(phi.map(|x| (x * inv_area) as f32)));
                }
            }),
        }
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

    /// The image after the passes so far.
    pub fn image(&self) -> Image {
        let c = &self.config;
        let mut img = Image::new(c.width, c.height);
        let passes = self.passes.max(1) as f64;
        match c.method {
            Method::Sppm => {
                for (i, px) in self.sppm.iter().enumerate() {
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
            Method::Ppm => {
                for (i, px) in self.ppm.iter().enumerate() {
                    img.pixels[i] = Rgb::from_array(px.map(|v| (v as f64 / FIXED / passes) as f32));
                }
            }
        }
        img
    }

    /// Combine PPM partial renders (any order) into one state; they must share the
    /// configuration and scene and cover contiguous, non-overlapping pass ranges.
    pub fn merge(mut parts: Vec<ProgressiveState>) -> Result<ProgressiveState> {
        let bad = |m: String| Err(Error::InvalidSetting(m));
        if parts.is_empty() {
            return bad("nothing to merge".into());
        }
        parts.sort_by_key(|p| p.first_pass);
        let mut out = parts[0].clone();
        if out.config.method != Method::Ppm {
            return bad(
                "only ppm partial renders can be merged (sppm passes depend on each other)".into(),
            );
        }
        for p in &parts[1..] {
            if p.config != out.config || p.scene_hash != out.scene_hash {
                return bad("the partial renders differ in scene or settings".into());
            }
            if p.first_pass != out.next_pass() {
                return bad(format!(
                    "pass ranges do not join: {}..{} then {}..{}",
                    out.first_pass,
                    out.next_pass(),
                    p.first_pass,
                    p.next_pass()
                ));
            }
            for (a, b) in out.ppm.iter_mut().zip(&p.ppm) {
                for k in 0..3 {
                    a[k] = a[k].saturating_add(b[k]);
                }
            }
            out.passes += p.passes;
        }
        Ok(out)
    }
}

/// Bytes of a pixel's visible-point slot, for the memory check.
const SLOT_BYTES: u64 = 136;
const _: () = assert!(std::mem::size_of::<Option<PassPoint>>() as u64 <= SLOT_BYTES);

/// A pixel's visible point in this pass and its squared gather radius.
#[derive(Clone, Copy, Debug)]
struct PassPoint {
    vp: VisiblePoint,
    r2: f32,
}

/// Run `f(x, y, pixel, stats)` on every pixel, rows in parallel, and put the visible point it
/// returns in the pixel's slot; pixels are independent, so the result does not depend on the
/// thread count.
fn visible_points<P: Send>(
    pixels: &mut [P],
    slots: &mut [Option<PassPoint>],
    width: usize,
    f: impl Fn(usize, usize, &mut P, &mut RayStats) -> Option<(VisiblePoint, f32)> + Sync,
) -> RayStats {
    pixels
        .par_chunks_mut(width)
        .zip(slots.par_chunks_mut(width))
        .enumerate()
        .map(|(y, (row, row_slots))| {
            let mut stats = RayStats::default();
            for (x, (px, slot)) in row.iter_mut().zip(row_slots).enumerate() {
                *slot = f(x, y, px, &mut stats).map(|(vp, r2)| PassPoint { vp, r2 });
            }
            stats
        })
        .reduce(RayStats::default, |mut a, b| {
            a.add(&b);
            a
        })
}

/// Grid cells are this many median gather radii wide: a query then visits about (1 + 2/3)³ ≈ 5
/// cells. Cells of 2 radii (always 8 cells, each nearly empty) gathered 25% slower on
/// `cornell`: the time goes to reaching buckets, not to testing photons.
const GRID_CELL_RADII: f32 = 3.0;

/// Gather at every pixel's visible point, rows in parallel, and hand the pixel, its radius²,
/// Σ f·ΔΦ in watts weighted by the camera path's throughput (a channel that overflows is
/// dropped) and the photon count to `update`.
fn gather_into<P: Send>(
    pixels: &mut [P],
    slots: &[Option<PassPoint>],
    width: usize,
    grid: &PhotonGrid<PassPhoton>,
    scale: f32,
    update: impl Fn(&mut P, f32, [f64; 3], u32) + Sync,
) {
    pixels
        .par_chunks_mut(width)
        .zip(slots.par_chunks(width))
        .for_each_init(QueryScratch::default, |scratch, (row, row_slots)| {
            for (px, slot) in row.iter_mut().zip(row_slots) {
                let Some(v) = slot else {
                    continue;
                };
                let (flux, m) = photon_flux(grid, &v.vp, v.r2, scratch);
                let phi = (flux * scale * v.vp.beta)
                    .to_array()
                    .map(|x| if x.is_finite() { f64::from(x) } else { 0.0 });
                update(px, v.r2, phi, m);
            }
        });
}

/// Median gather radius of a pass's points (0 with none).
fn median_radius(slots: &[Option<PassPoint>]) -> f32 {
    let mut r2: Vec<f32> = slots.iter().flatten().map(|p| p.r2).collect();
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
    let tolerance = surface_epsilon(vp.p);
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
            sum += vp
                .material
                .eval_part(vp.wo_local, wi, TransportMode::Radiance, Part::Rough)
                * ph.power;
            count += 1;
        }
    });
    (sum, count)
}

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

fn camera_ray(
    camera: &Camera,
    c: &ProgressiveConfig,
    jitter: &PassJitter,
    pass: u64,
    x: usize,
    y: usize,
) -> (crate::math::Ray, Rng) {
    let pixel = (y * c.width as usize + x) as u64;
    let rng = Rng::keyed(c.seed, &[pass, pixel, 0x9a55]);
    let u = Vec2::from_array(jitter.position(pixel));
    let pos = PixelFilter::Box.sample_position(x as u32, y as u32, u);
    (camera.ray(pos), rng)
}

/// Adds the finite channels of `l` to `sum`: a NaN or infinity from one sample must not poison
/// a pixel for good, and dropping only the bad channel keeps the rest of the light.
fn add_finite(sum: &mut [f64; 3], l: Rgb) {
    for (s, v) in sum.iter_mut().zip(l.to_array()) {
        if v.is_finite() {
            *s += f64::from(v);
        }
    }
}

/// Add the finite channels of `l` to a PPM pixel's fixed-point sums (`as` saturates, and so
/// does the sum).
fn add_fixed(px: &mut [i128; 3], l: Rgb) {
    for (s, v) in px.iter_mut().zip(l.to_array()) {
        if v.is_finite() {
            *s = s.saturating_add((f64::from(v) * FIXED).round() as i128);
        }
    }
}

/// SPPM's update of a pixel by the `m` photons of a pass (Hachisuka & Jensen 2009, eq. 6–7):
/// N ← N + αM, r² ← r² (N + αM)/(N + M), τ ← (τ + Φ) r²_new / r²_old.
fn sppm_update(px: &mut SppmPixel, alpha: f64, phi: [f64; 3], m: u32) {
    if m == 0 {
        return;
    }
    let m = f64::from(m);
    let n_new = px.n + alpha * m;
    let r2_new = px.r2 * n_new / (px.n + m);
    for (tau, phi) in px.tau.iter_mut().zip(phi) {
        *tau = (*tau + phi) * (r2_new / px.r2);
    }
    px.n = n_new;
    px.r2 = r2_new;
}
