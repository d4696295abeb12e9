//! Photon tracing: emission from every light in proportion to its power, and physically based
//! scattering (Jensen 2001, ch. 5), in parallel and deterministic.

use super::map::{MapKind, PhotonMap};
use super::record::{Channel, PassPhoton, Photon, VolumePhoton};
use crate::error::{Error, Result};
use crate::material::{Part, TransportMode};
use crate::math::{Ray, Rgb, Vec2, Vec3, offset_origin};
use crate::medium::{MediumId, spectral_mis};
use crate::sampling::halton::ShiftedHalton;
use crate::sampling::{Distribution1D, Rng};
use crate::scene::{Interaction, Scene};
use crate::spectrum::Lambda;
use rayon::prelude::*;

/// Parameters of one photon trace.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonConfig {
    /// Photons emitted (per channel in per-channel mode). All of them feed the caustic map.
    pub photons: u64,
    /// Only the first this-many paths store into the global map (its photons then carry
    /// Φ / this count): caustics need many more photons than smooth indirect light, and one
    /// trace serves both. `None`: all paths.
    pub global_photons: Option<u64>,
    /// Maximum number of surface hits of a photon path.
    pub max_depth: u32,
    /// Fixed absorption probability at every hit (the original project's `k_a`); `None` for
    /// Russian roulette on the BSDF's albedo.
    pub absorption: Option<f32>,
    /// Three single-channel traces, each bouncing with that channel's reflectance, as the
    /// original project did; otherwise every photon carries RGB power.
    pub per_channel: bool,
    /// Spectral photons: each path carries three wavelengths of its own (one after a
    /// dispersive glass) and is stored with the RGB colour of its power.
    pub spectral: bool,
    pub seed: u64,
}

impl Default for PhotonConfig {
    fn default() -> Self {
        Self {
            photons: 1_000_000,
            global_photons: None,
            max_depth: 64,
            absorption: None,
            per_channel: false,
            spectral: false,
            seed: 0,
        }
    }
}

/// Largest photon count accepted: 4·10⁹ photons would need ~100 GB.
pub const MAX_PHOTONS: u64 = 1_000_000_000;

impl PhotonConfig {
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::InvalidSetting(m));
        if self.photons == 0 || self.photons > MAX_PHOTONS {
            return bad(format!(
                "photon count {} must be in 1..={MAX_PHOTONS}",
                self.photons
            ));
        }
        if let Some(g) = self.global_photons
            && (g == 0 || g > self.photons)
        {
            return bad(format!(
                "global photon count {g} must be in 1..={} (the photons traced)",
                self.photons
            ));
        }
        if self.max_depth == 0 || self.max_depth > 255 {
            return bad(format!(
                "maximum depth {} must be in 1..=255",
                self.max_depth
            ));
        }
        if self.per_channel && self.spectral {
            return bad(
                "per-channel photons are an RGB mode (one trace per channel); spectral photons carry wavelengths of their own".into(),
            );
        }
        if let Some(p) = self.absorption
            && !(0.0..1.0).contains(&p)
        {
            return bad(format!("absorption probability {p} must be in [0, 1)"));
        }
        Ok(())
    }
}

/// Counts gathered while tracing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TraceStats {
    /// Photon paths started (all channels).
    pub emitted: u64,
    /// Paths that stored into the global map (all channels).
    pub global_emitted: u64,
    /// Stored photons per depth (index = depth), both maps together.
    pub stored_by_depth: Vec<u64>,
}

/// The result of a trace: both maps and how they were made.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonMaps {
    pub scene_name: String,
    pub scene_hash: u64,
    pub config: PhotonConfig,
    pub caustic: PhotonMap,
    pub global: PhotonMap,
    /// The photons scattered in media (every scattering, the first from a light included),
    /// at the global map's power scale. Saved maps hold none: a scene with media renders its
    /// maps where it traces them.
    pub volume: Vec<VolumePhoton>,
    pub stats: TraceStats,
}

impl PhotonMaps {
    pub fn map(&self, kind: MapKind) -> &PhotonMap {
        match kind {
            MapKind::Caustic => &self.caustic,
            MapKind::Global => &self.global,
        }
    }
}

/// Which light emits a photon of `channel`: each in proportion to its power in that channel
/// (all three for RGB photons); `None` if no light emits in it.
pub fn light_choice(scene: &Scene, channel: Channel) -> Option<Distribution1D> {
    let weights: Vec<f64> = scene
        .lights()
        .iter()
        .map(|l| {
            let p = l.power();
            f64::from(channel.index().map_or(p.x + p.y + p.z, |c| p[c]))
        })
        .collect();
    Distribution1D::new(&weights)
}

/// What a progressive pass gathers: the photons that did not come straight from a light (its
/// direct light is next-event estimated) on surfaces and in media, in photon order, and the
/// scale that turns their relative powers into watts (Φ_max / N).
#[derive(Clone, Debug, Default)]
pub struct PassPhotons {
    pub surface: Vec<PassPhoton>,
    pub volume: Vec<VolumePhoton>,
    pub scale: f32,
}

/// Trace `photons` photon paths with the random streams of [`trace_photons`] (photon `i`
/// keyed by (seed, 0, i)) and keep what a progressive pass gathers ([`PassPhotons`]). Every
/// path carries the channels of `lambda` (a pass's wavelengths in spectral rendering), and
/// so do the photons' powers.
pub fn trace_indirect_photons(
    scene: &Scene,
    photons: u64,
    seed: u64,
    max_depth: u32,
    lambda: Lambda,
) -> Result<PassPhotons> {
    let total_max = scene.total_power().max_element();
    let choice = light_choice(scene, Channel::Rgb).filter(|_| total_max > 0.0);
    let Some(choice) = choice else {
        return Err(Error::InvalidScene(NO_LIGHT.into()));
    };
    let ctx = PathContext {
        scene,
        max_depth,
        absorption: None,
        channel: Channel::Rgb,
        choice: &choice,
        total_max,
    };
    let emission = emission_points(seed, 0);
    let chunks: Vec<(Vec<PassPhoton>, Vec<VolumePhoton>)> = (0..photons.div_ceil(CHUNK))
        .into_par_iter()
        .map(|k| {
            let (mut surface, mut volume) = (Vec::new(), Vec::new());
            for i in k * CHUNK..((k + 1) * CHUNK).min(photons) {
                let mut rng = Rng::keyed(seed, &[0, i]);
                trace_path(&ctx, emission.point(i), lambda, &mut rng, &mut |v| {
                    if v.depth <= 1 {
                        return;
                    }
                    match v.medium {
                        Some(medium) => volume.push(volume_photon(scene, v, medium)),
                        None => surface.push(PassPhoton {
                            position: v.p,
                            normal: v.n,
                            incoming: v.wo,
                            power: v.power,
                            hero_only: v.lambda.is_hero_only(),
                        }),
                    }
                });
            }
            (surface, volume)
        })
        .collect();
    let (surface, volume): (Vec<_>, Vec<_>) = chunks.into_iter().unzip();
    Ok(PassPhotons {
        surface: surface.concat(),
        volume: volume.concat(),
        scale: total_max / photons as f32,
    })
}

/// The emission points of a progressive pass's photons: photon `i` leaves its light at
/// point `i` of a randomly shifted Halton sequence (direction 2D, position 2D, light choice,
/// the light's own pick). Each photon is still uniformly placed, so the maps stay unbiased, but
/// the photons of a trace cover each light's surface and directions evenly: fewer clumps and
/// holes in the first bounce and in caustics than independent random photons leave. The later
/// bounces use the photon's own random stream.
///
/// Only progressive passes emit this way: their fixed-radius estimates (photons in a disc over
/// its area) are unbiased for any placement of the photons, but a k-nearest estimate's bias
/// depends on how photons are spread (at k = 1 in a closed sphere, evenly spread photons read
/// 0.92 where random ones read 1.00), so the saved maps keep independent random photons.
fn emission_points(seed: u64, channel: u64) -> ShiftedHalton {
    ShiftedHalton::new(&mut Rng::keyed(seed, &[channel, 0x4a17_0e5f]))
}

/// The emission numbers of a photon from its own random stream, in [`trace_path`]'s order.
fn random_emission(rng: &mut Rng) -> [f32; 6] {
    let (u_light, u_pick) = (rng.next_f32(), rng.next_f32());
    let (u_pos, u_dir) = (rng.next_2d(), rng.next_2d());
    [u_dir.x, u_dir.y, u_pos.x, u_pos.y, u_light, u_pick]
}

/// Why saved photon maps and media do not go together.
pub const SAVED_MAPS_AND_MEDIA: &str = "the scene has participating media, whose photons saved photon maps do not hold: render it with --integrator photon (which traces its own maps), sppm or ppm";

const NO_LIGHT: &str = "the scene emits no light, so there are no photons to trace (light it with a sky: --env R,G,B or --env FILE.exr, or a [[lights]] table)";

/// Photons per parallel work item: small enough to balance, large enough to amortise.
const CHUNK: u64 = 4096;

struct ChunkOut {
    caustic: Vec<Photon>,
    global: Vec<Photon>,
    volume: Vec<VolumePhoton>,
    by_depth: Vec<u64>,
}

/// Trace photons through `scene`. Photon `i` of channel `c` uses the random stream keyed by
/// (seed, c, i), and chunks are concatenated in order: the maps do not depend on thread count.
/// `progress(done, total)` is called as chunks finish.
pub fn trace_photons(
    scene: &Scene,
    config: &PhotonConfig,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<PhotonMaps> {
    config.validate()?;
    let lights = scene.lights();
    let channels: Vec<Channel> = if config.per_channel {
        vec![Channel::Red, Channel::Green, Channel::Blue]
    } else {
        vec![Channel::Rgb]
    };
    // Relative powers are stored against the brightest channel of the total power, so they
    // stay near 1; each map's scale divides by the paths that fed it.
    let total_max = scene.total_power().max_element();
    let global_photons = config.global_photons.unwrap_or(config.photons);
    if lights.is_empty() || total_max.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(Error::InvalidScene(NO_LIGHT.into()));
    }
    let chunks_per_channel = config.photons.div_ceil(CHUNK);
    let total_chunks = chunks_per_channel * channels.len() as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let mut outs: Vec<ChunkOut> = Vec::new();
    for (ci, &channel) in channels.iter().enumerate() {
        let Some(choice) = light_choice(scene, channel) else {
            // This channel emits nothing: no photons for it.
            continue;
        };
        let ctx = PathContext {
            scene,
            max_depth: config.max_depth,
            absorption: config.absorption,
            channel,
            choice: &choice,
            total_max,
        };
        let chunk_outs: Vec<ChunkOut> = (0..chunks_per_channel)
            .into_par_iter()
            .map(|k| {
                let start = k * CHUNK;
                let end = (start + CHUNK).min(config.photons);
                let mut out = ChunkOut {
                    caustic: Vec::new(),
                    global: Vec::new(),
                    volume: Vec::new(),
                    by_depth: vec![0; config.max_depth as usize + 1],
                };
                for i in start..end {
                    let mut rng = Rng::keyed(config.seed, &[ci as u64, i]);
                    let store_global = i < global_photons;
                    let emission = random_emission(&mut rng);
                    let lambda = Lambda::draw(config.spectral, &mut rng);
                    trace_path(&ctx, emission, lambda, &mut rng, &mut |v| match v.medium {
                        None => store(v, channel, store_global, &mut out),
                        Some(m) if store_global => {
                            out.volume
                                .push(volume_photon(scene, v, m).to_rgb(&v.lambda));
                        }
                        Some(_) => {}
                    });
                }
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress(n, total_chunks);
                out
            })
            .collect();
        outs.extend(chunk_outs);
    }
    let mut caustic = Vec::new();
    let mut global = Vec::new();
    let mut volume = Vec::new();
    let mut stored_by_depth = vec![0u64; config.max_depth as usize + 1];
    for o in outs {
        caustic.extend_from_slice(&o.caustic);
        global.extend_from_slice(&o.global);
        volume.extend_from_slice(&o.volume);
        for (a, b) in stored_by_depth.iter_mut().zip(&o.by_depth) {
            *a += b;
        }
    }
    let (caustic, global) = rayon::join(
        || PhotonMap::build(MapKind::Caustic, caustic, total_max / config.photons as f32),
        || PhotonMap::build(MapKind::Global, global, total_max / global_photons as f32),
    );
    Ok(PhotonMaps {
        scene_name: scene.name.clone(),
        scene_hash: scene.content_hash(),
        config: config.clone(),
        caustic,
        global,
        volume,
        stats: TraceStats {
            emitted: config.photons * channels.len() as u64,
            global_emitted: global_photons * channels.len() as u64,
            stored_by_depth,
        },
    })
}

/// Where a photon path met a rough surface: what a photon map stores, or a splat deposits.
#[derive(Clone, Copy, Debug)]
struct PathVertex {
    p: Vec3,
    /// Geometric normal on the side the photon arrived from: which surface it is on.
    n: Vec3,
    /// Direction back toward where the photon came from.
    wo: Vec3,
    /// Power relative to Φ_max / N (see [`PhotonMaps`]); times `total_max / N` gives watts.
    /// Scaled by |wo·ns| / |wo·ng| (see [`ShadingCosines`]), so that Σ power / area is the
    /// irradiance the shading normal sees and every estimate may weigh it by f alone.
    power: Rgb,
    /// Surface hits so far, this one included (1: straight from a light).
    depth: u32,
    /// Every scattering before this hit was by a smooth lobe (the path is L S* so far).
    specular_only: bool,
    /// The last scattering before this hit was by a smooth lobe (false for direct photons).
    smooth_last: bool,
    /// The medium of a scattering point in a medium (then `n` is zero); `None` on surfaces.
    medium: Option<MediumId>,
    /// The path's wavelengths at this point (`power` is at them).
    lambda: Lambda,
}

/// The largest probability with which a photon goes on after scattering in a medium (the
/// path tracer's Russian roulette keeps the same ceiling).
const MEDIUM_SURVIVAL: f32 = 0.95;

/// What a photon path depends on besides its random numbers.
struct PathContext<'a> {
    scene: &'a Scene,
    max_depth: u32,
    absorption: Option<f32>,
    channel: Channel,
    /// Which light emits, in proportion to its power in `channel`.
    choice: &'a Distribution1D,
    /// Brightest channel of the scene's total power: relative powers are stored against it.
    total_max: f32,
}

/// A volume photon's power over σs where it scattered, per channel (zero where σs is): the
/// fluence it stands for. The photons of a ball then estimate the in-scattered radiance at its
/// centre as Σ p Φ/σs over the ball's volume, which stays right where the density varies
/// within the ball; dividing the sum by σs at the centre instead weights the photons by the
/// centre's density (Jensen and Christensen 1998 write it for homogeneous media).
fn volume_photon(scene: &Scene, v: &PathVertex, medium: MediumId) -> VolumePhoton {
    let sigma_s = scene.medium(medium).at(&v.lambda).sigma_s_at(v.p);
    let channel = |p: f32, s: f32| if s > 0.0 { p / s } else { 0.0 };
    VolumePhoton {
        position: v.p,
        incoming: v.wo,
        power: Rgb::new(
            channel(v.power.x, sigma_s.x),
            channel(v.power.y, sigma_s.y),
            channel(v.power.z, sigma_s.z),
        ),
        medium,
        hero_only: v.lambda.is_hero_only(),
    }
}

/// Follow one photon from its light until it is absorbed, escapes or reaches the maximum depth,
/// calling `visit` at every rough surface it meets. `emission` holds the numbers that place it
/// on its light (see [`emission_points`]); `rng` gives the rest.
fn trace_path(
    ctx: &PathContext,
    emission: [f32; 6],
    lambda: Lambda,
    rng: &mut Rng,
    visit: &mut impl FnMut(&PathVertex),
) {
    let scene = ctx.scene;
    let [u_dir_x, u_dir_y, u_pos_x, u_pos_y, u_light, u_pick] = emission;
    let (light_index, _) = ctx.choice.sample(u_light);
    let pmf = ctx.choice.pmf(light_index);
    let (u_pos, u_dir) = (Vec2::new(u_pos_x, u_pos_y), Vec2::new(u_dir_x, u_dir_y));
    let mut lambda = lambda;
    let Some(e) = scene.lights()[light_index].emit(u_pick, u_pos, u_dir, &lambda) else {
        return;
    };
    // The photon carries Φ_light / (pmf · N); stored relative to Φ_max / N.
    let mut power = e.flux / (pmf * ctx.total_max);
    if let Some(c) = ctx.channel.index() {
        let mut only = Rgb::ZERO;
        only[c] = power[c];
        power = only;
    }
    let origin = if e.normal == Rgb::ZERO {
        e.origin
    } else {
        offset_origin(e.origin, e.error, e.normal, e.dir)
    };
    let mut ray = Ray::new(origin, e.dir);
    let mut specular_only = true;
    let mut smooth_last = false;
    let mut medium = scene.light_medium(light_index);
    // Spectral MIS in media (see `crate::medium`): an RGB photon draws its distances with a
    // hero channel; a photon of one channel with its own.
    let hero = match ctx.channel.index() {
        Some(c) => c,
        None => scene.draw_hero_channel(rng),
    };
    let mut ratio = Rgb::ONE;
    for depth in 1..=ctx.max_depth {
        let step = scene.next_interaction(&ray, medium, (hero, &lambda), rng);
        power *= step.weight;
        ratio *= step.ratio;
        let mis = match ctx.channel.index() {
            Some(_) => 1.0,
            None => spectral_mis(ratio),
        };
        let (hit, reached_through) = match step.interaction {
            Interaction::Escaped => return,
            Interaction::Scatter { p, medium: m } => {
                let wo = -ray.dir;
                visit(&PathVertex {
                    p,
                    n: Vec3::ZERO,
                    wo,
                    power: power * mis,
                    depth,
                    specular_only,
                    smooth_last,
                    medium: Some(m),
                    lambda,
                });
                // The free flight's weight (σs·Tr over its density) is in `power`; the
                // photon goes on with the probability of its largest channel's share, at most
                // MEDIUM_SURVIVAL: in a medium that does not absorb, a photon would otherwise
                // wander to the depth limit (an infinite atmosphere of fog cost 64 events per
                // photon).
                let survive = (step.weight.max_element() * mis).min(MEDIUM_SURVIVAL);
                if depth == ctx.max_depth || survive <= 0.0 || rng.next_f32() >= survive {
                    return;
                }
                power /= survive;
                let s = scene.medium(m).phase().sample(wo, rng.next_2d());
                specular_only = false;
                smooth_last = false;
                medium = Some(m);
                ray = Ray::new(p, s.wi);
                continue;
            }
            Interaction::Surface { hit, medium } => (hit, medium),
        };
        let wo = -ray.dir;
        let (material, frame) = scene.surface(&hit, wo, &mut lambda);
        let ng = hit.ng_facing(wo);
        let arrival = ShadingCosines::new(wo, ng, frame.n);
        if material.has(Part::Rough) {
            visit(&PathVertex {
                p: hit.p,
                n: ng,
                wo,
                power: power * mis * arrival.reflected_ratio(),
                depth,
                specular_only,
                smooth_last,
                medium: None,
                lambda,
            });
        }
        if depth == ctx.max_depth {
            return;
        }
        let u_lobe = rng.next_f32();
        let Some(s) = material.sample(
            frame.to_local(wo),
            u_lobe,
            rng.next_2d(),
            TransportMode::Importance,
        ) else {
            return;
        };
        // Survival probability: fixed, or the scattered fraction in the channel(s) carried.
        let survive = match (ctx.absorption, ctx.channel.index()) {
            (Some(p), _) => 1.0 - p,
            (None, Some(c)) => s.weight[c].min(1.0),
            (None, None) => s.weight.max_element().min(1.0),
        };
        if survive <= 0.0 || rng.next_f32() >= survive {
            return;
        }
        let wi = frame.to_world(s.wi);
        let departure = ShadingCosines::new(wi, ng, frame.n);
        // The adjoint BSDF under shading normals (Veach 1997, §5.3):
        // f*(wo → wi) = f(wi → wo) |wo·ns| |wi·ng| / (|wo·ng| |wi·ns|).
        power *= s.weight * arrival.ratio() / departure.ratio() / survive;
        if !power.is_finite() {
            return;
        }
        smooth_last = material.is_smooth_lobe(s.lobe);
        specular_only &= smooth_last;
        medium = scene.medium_after(&hit, reached_through, wi);
        ray = Ray::new(hit.offset_origin(wi), wi);
    }
}

/// |w·ns| and |w·ng| of one direction at a photon's hit. Photon flux lands on the geometric
/// surface, while the BSDF weighs incident light by the shading cosine: the ratio converts
/// one into the other (Veach 1997, §5.3). Where the shading and geometric normals agree it is
/// exactly 1.
#[derive(Clone, Copy, Debug)]
struct ShadingCosines {
    shading: f32,
    geometric: f32,
    /// `w` is on the side of the shading plane that faces the geometric side of `ng`.
    shading_above: bool,
}

impl ShadingCosines {
    /// `ng` is the geometric normal on the side `w` or the photon came from.
    fn new(w: Vec3, ng: Vec3, ns: Vec3) -> Self {
        let s = w.dot(ns);
        Self {
            shading: s.abs(),
            geometric: w.dot(ng).abs(),
            shading_above: (s > 0.0) == (ns.dot(ng) > 0.0),
        }
    }

    /// The share of a photon arriving along `w` that rough parts (reflection only) can send on,
    /// per unit of its geometric flux: |w·ns| / |w·ng| where `w` is above the shading plane on
    /// the geometric side it came from, zero where it is below it. Reflection needs both
    /// directions above the shading plane, so such a photon is never reflected (Lambertian and
    /// microfacet reflection are zero there, as they are for a camera path).
    fn reflected_ratio(self) -> f32 {
        if self.shading_above {
            self.ratio()
        } else {
            0.0
        }
    }

    /// |w·ns| / |w·ng|: a photon arriving along `w` brings this much shading irradiance per
    /// unit of its geometric flux density; zero at a grazing geometric angle.
    fn ratio(self) -> f32 {
        if self.geometric > 0.0 {
            self.shading / self.geometric
        } else {
            0.0
        }
    }
}

/// Store a path's photons: caustic (L S+ D) or, for the first `global_photons` paths, global.
/// A spectral photon is stored with the RGB colour of its power.
fn store(v: &PathVertex, channel: Channel, store_global: bool, out: &mut ChunkOut) {
    let power = v.lambda.to_rgb(v.power);
    let photon = Photon::new(v.p, v.n, v.wo, power, v.depth, channel)
        .with_smooth_last_scattering(v.smooth_last);
    if v.depth > 1 && v.specular_only {
        out.caustic.push(photon);
        out.by_depth[v.depth as usize] += 1;
    } else if store_global {
        out.global.push(photon);
        out.by_depth[v.depth as usize] += 1;
    }
}
