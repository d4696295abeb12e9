use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter, stratified_2d};
use crate::integrator::{RayStats, VisiblePoint, trace_camera_path};
use crate::math::{Rgb, Vec2};
use crate::photon::estimate::reflected_flux_within;
use crate::photon::{PhotonConfig, PhotonMaps, trace_photons};
use crate::sampling::{Rng, mix64};
use crate::scene::Scene;
use rayon::prelude::*;
use std::f64::consts::PI;

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
    /// Initial gather radius in scene units; `None`: `FOOTPRINT_PIXELS` pixel footprints at each
    /// pixel's visible point.
    pub initial_radius: Option<f32>,
    pub max_depth: u32,
    pub light_samples: u32,
}

/// Initial radius in pixel footprints when none is given.
pub const FOOTPRINT_PIXELS: f32 = 4.0;
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
        // Per pixel: SPPM's state (r², N, τ, direct: 8 × f64) or PPM's sums (3 × i128),
        // plus the image.
        let per_pixel = match self.method {
            Method::Sppm => 64 + 12,
            Method::Ppm => 48 + 12,
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
}

/// What one pass did.
#[derive(Clone, Copy, Debug, Default)]
pub struct PassStats {
    pub photons_emitted: u64,
    pub photons_stored: u64,
    pub rays: RayStats,
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
        })
    }

    /// Index of the next pass to run.
    pub fn next_pass(&self) -> u64 {
        self.first_pass + self.passes
    }

    /// Run the next pass.
    pub fn run_pass(&mut self, scene: &Scene) -> Result<PassStats> {
        let c = self.config.clone();
        let pass = self.next_pass();
        let photon_config = PhotonConfig {
            photons: c.photons_per_pass,
            seed: mix64(c.seed ^ mix64(pass.wrapping_add(0x5eed))),
            ..PhotonConfig::default()
        };
        let maps = trace_photons(scene, &photon_config, &|_, _| {})?;
        let camera = Camera::new(&scene.camera, c.width, c.height)
            .ok_or_else(|| Error::InvalidScene("degenerate camera".into()))?;
        // Pixel footprint per unit distance, for the automatic radius.
        let footprint = 2.0 * (0.5 * scene.camera.fov_y_deg.to_radians()).tan() / c.height as f32;
        let width = c.width as usize;
        let ppm_r_scale = ppm_radius_scale(pass, c.alpha);
        let rays = match c.method {
            Method::Sppm => for_each_pixel(&mut self.sppm, width, |x, y, px, stats| {
                sppm_pixel(scene, &maps, &camera, &c, pass, footprint, x, y, px, stats);
            }),
            Method::Ppm => for_each_pixel(&mut self.ppm, width, |x, y, px, stats| {
                let l = ppm_pixel(
                    scene,
                    &maps,
                    &camera,
                    &c,
                    pass,
                    footprint,
                    ppm_r_scale,
                    x,
                    y,
                    stats,
                );
                for k in 0..3 {
                    // `as` saturates; the sum saturates too.
                    px[k] = px[k].saturating_add((f64::from(l[k]) * FIXED).round() as i128);
                }
            }),
        };
        self.passes += 1;
        Ok(PassStats {
            photons_emitted: maps.stats.emitted,
            photons_stored: (maps.caustic.len() + maps.global.len()) as u64,
            rays,
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

/// Run `f(x, y, pixel, stats)` on every pixel, rows in parallel; pixels are independent, so
/// the result does not depend on the thread count.
fn for_each_pixel<P: Send>(
    pixels: &mut [P],
    width: usize,
    f: impl Fn(usize, usize, &mut P, &mut RayStats) + Sync,
) -> RayStats {
    pixels
        .par_chunks_mut(width)
        .enumerate()
        .map(|(y, row)| {
            let mut stats = RayStats::default();
            for (x, px) in row.iter_mut().enumerate() {
                f(x, y, px, &mut stats);
            }
            stats
        })
        .reduce(RayStats::default, |mut a, b| {
            a.add(&b);
            a
        })
}

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
    seed: u64,
    pass: u64,
    x: usize,
    y: usize,
    width: usize,
) -> (crate::math::Ray, Rng) {
    let pixel = (y * width + x) as u64;
    let mut rng = Rng::keyed(seed, &[pass, pixel, 0x9a55]);
    let u = stratified_2d(0, 1, Vec2::ZERO, rng.next_2d());
    let pos = PixelFilter::Box.sample_position(x as u32, y as u32, u);
    (camera.ray(pos), rng)
}

/// Σ f·ΔΦ at a visible point over both maps within radius `r` (direct photons left out: direct
/// light comes from next-event estimation), and the number of photons used.
fn photon_flux(maps: &PhotonMaps, vp: &VisiblePoint, r: f32) -> (Rgb, u32) {
    let within = |map, skip_direct| {
        reflected_flux_within(
            map,
            vp.p,
            &vp.frame,
            vp.wo_local,
            &vp.material,
            r,
            skip_direct,
        )
    };
    let (fc, mc) = within(&maps.caustic, false);
    let (fg, mg) = within(&maps.global, true);
    (fc + fg, mc + mg)
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

#[expect(clippy::too_many_arguments, reason = "per-pixel kernel of a pass")]
fn sppm_pixel(
    scene: &Scene,
    maps: &PhotonMaps,
    camera: &Camera,
    c: &ProgressiveConfig,
    pass: u64,
    footprint: f32,
    x: usize,
    y: usize,
    px: &mut SppmPixel,
    stats: &mut RayStats,
) {
    let (ray, mut rng) = camera_ray(camera, c.seed, pass, x, y, c.width as usize);
    let path = trace_camera_path(scene, &ray, c.max_depth, c.light_samples, &mut rng, stats);
    add_finite(&mut px.direct, path.direct);
    let Some(vp) = path.visible else {
        return;
    };
    if px.r2 == 0.0 {
        let r0 = c
            .initial_radius
            .unwrap_or(FOOTPRINT_PIXELS * footprint * vp.distance);
        px.r2 = f64::from(r0) * f64::from(r0);
    }
    let (flux, m) = photon_flux(maps, &vp, px.r2.sqrt() as f32);
    let m = f64::from(m);
    // Σ f·Φ weighted by the specular chain; a non-finite channel is dropped.
    let phi = (flux * vp.beta)
        .to_array()
        .map(|v| if v.is_finite() { v } else { 0.0 });
    if m == 0.0 {
        return;
    }
    let n_new = px.n + c.alpha * m;
    let r2_new = px.r2 * n_new / (px.n + m);
    for (tau, phi) in px.tau.iter_mut().zip(phi) {
        *tau = (*tau + f64::from(phi)) * (r2_new / px.r2);
    }
    px.n = n_new;
    px.r2 = r2_new;
}

#[expect(clippy::too_many_arguments, reason = "per-pixel kernel of a pass")]
fn ppm_pixel(
    scene: &Scene,
    maps: &PhotonMaps,
    camera: &Camera,
    c: &ProgressiveConfig,
    pass: u64,
    footprint: f32,
    radius_scale: f32,
    x: usize,
    y: usize,
    stats: &mut RayStats,
) -> Rgb {
    let (ray, mut rng) = camera_ray(camera, c.seed, pass, x, y, c.width as usize);
    let path = trace_camera_path(scene, &ray, c.max_depth, c.light_samples, &mut rng, stats);
    let Some(vp) = path.visible else {
        return path.direct;
    };
    let r0 = c
        .initial_radius
        .unwrap_or(FOOTPRINT_PIXELS * footprint * vp.distance);
    let r = f64::from(r0) * f64::from(radius_scale);
    let (flux, m) = photon_flux(maps, &vp, r as f32);
    let photons = if m == 0 {
        Rgb::ZERO
    } else {
        // In f64: π r² underflows f32 for tiny radii; a channel that still overflows is dropped.
        let inv_area = 1.0 / (PI * r * r);
        let l = (flux * vp.beta)
            .to_array()
            .map(|v| (f64::from(v) * inv_area) as f32);
        Rgb::from_array(l)
    };
    let finite =
        |v: Rgb| Rgb::from_array(v.to_array().map(|x| if x.is_finite() { x } else { 0.0 }));
    finite(path.direct) + finite(photons)
}
