//! One library call that does what `photon render` does: [`RenderOptions`] (what a user may
//! set, all optional) resolved against a scene file's `[render]` table and the defaults, then
//! run by any integrator with a progress callback and a cancel flag. The command line, the
//! Python module and the Blender add-on all render through it, so they give the same image
//! for the same settings, bit for bit.
//!
//! Precedence, for every setting: the options given, then the scene's `[render]` table, then
//! the defaults below. Photon-integrator settings in a scene file apply only when the photon
//! integrator runs, so a scene written for photon mapping still renders with `path`.

use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter};
use crate::integrator::{DirectConfig, Integrator, PathConfig, PhotonIntegrator, PhotonSettings};
use crate::io::checkpoint::RunInfo;
use crate::io::sample_part::PartOrigin;
use crate::photon::{Kernel, PhotonConfig, PhotonMaps, SAVED_MAPS_AND_MEDIA, trace_photons};
use crate::progressive::{Method, ProgressiveConfig, ProgressiveState};
use crate::render::{RenderOutput, RenderSettings, render_samples_cancellable};
use crate::scene::Scene;
use crate::session::{Budget, Ending, Session};
use crate::settings::{
    DefaultValue, GatherMode, IntegratorKind, RenderOptions, SETTINGS, SettingError, defaults,
};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// What a render is doing, for progress reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Tracing the photon maps (photon integrator): `done` of `total` photons.
    Tracing,
    /// Rendering tiles: `done` of `total`.
    Rendering,
    /// Progressive passes: `done` of `total` (0 when the budget is a time).
    Passes,
}

/// A progress report: `phase`, and how far it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    pub phase: Phase,
    pub done: u64,
    pub total: u64,
}

/// Seconds spent in each part of a render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    pub trace: f64,
    pub build: f64,
    pub render: f64,
}

/// What a render made.
pub struct RenderResult {
    /// The beauty image (linear RGB).
    pub image: Image,
    /// The sample render's output (AOVs, sums, ray counts); `None` for progressive renders.
    pub output: Option<RenderOutput>,
    /// The progressive state after the last pass; `None` for the others.
    pub state: Option<ProgressiveState>,
    pub timings: Timings,
    /// Photons traced (photon integrator and progressive passes).
    pub photons: u64,
    /// Whether the cancel flag stopped it early (a progressive render keeps its passes).
    pub cancelled: bool,
}

/// A render of one scene with resolved settings. Build with [`RenderJob::new`].
pub struct RenderJob<'s> {
    scene: &'s Scene,
    /// Every setting: given, else the scene's, else the default where it has a value.
    options: RenderOptions,
    integrator: IntegratorKind,
    maps: Option<Arc<PhotonMaps>>,
}

/// `options` with every setting `kind` takes and has a default value for filled in.
fn with_defaults(mut options: RenderOptions, kind: IntegratorKind) -> RenderOptions {
    // With gather none and no k given, the maps keep their own k: read directly, the global
    // map's noise is seen as is, and it takes more photons per estimate than the caustic map.
    let own_k = options.gather == Some(GatherMode::None) && options.k.is_none();
    for s in SETTINGS
        .iter()
        .filter(|s| s.takes.includes(kind) && !(own_k && s.name == "k"))
    {
        if let DefaultValue::Value(of) = s.default
            && !options.given().iter().any(|(g, _)| g.name == s.name)
        {
            options
                .set_text(s.name, &of(kind))
                .expect("every default reads back as its setting");
        }
    }
    options.alpha = options
        .alpha
        .or(kind.is_progressive().then_some(defaults::ALPHA));
    options
}

fn setting_error(e: SettingError) -> Error {
    Error::Setting(e)
}

impl<'s> RenderJob<'s> {
    /// Resolve `options` against the scene's `[render]` table `scene_settings` and the
    /// defaults, and check them. A setting given in `options` that the integrator does not
    /// take is an error; the scene's apply only where they are taken.
    pub fn new(
        scene: &'s Scene,
        scene_settings: &RenderOptions,
        options: RenderOptions,
    ) -> Result<Self> {
        let integrator = options
            .integrator
            .or(scene_settings.integrator)
            .unwrap_or(defaults::INTEGRATOR);
        options.check_each(integrator).map_err(setting_error)?;
        let mut options = options;
        options.fill_from_scene(scene_settings, integrator);
        options.check_values().map_err(setting_error)?;
        let needs = |name: &'static str, value: Option<String>, problem: &str| {
            Err(setting_error(SettingError {
                name,
                value,
                problem: problem.into(),
            }))
        };
        if options.gather_rays == Some(0) && options.gather != Some(GatherMode::None) {
            return needs(
                "gather_rays",
                Some("0".into()),
                "must be at least 1 (or gather none)",
            );
        }
        if options.spectral == Some(true) && options.per_channel == Some(true) {
            return needs(
                "spectral",
                None,
                "per_channel photons are an RGB mode; leave one of them out",
            );
        }
        let (w, h) = scene.default_resolution;
        options.width = options.width.or(Some(w));
        options.height = options.height.or(Some(h));
        let options = with_defaults(options, integrator);
        let job = Self {
            scene,
            options,
            integrator,
            maps: None,
        };
        if integrator.is_progressive() {
            job.budget().check()?;
            job.progressive_config().validate()?;
        } else {
            let spp = job.settings().spp;
            job.settings().validate()?;
            if let Some(r) = job.options.sample_range
                && r.end > u64::from(spp)
            {
                return needs(
                    "sample_range",
                    Some(format!("{}..{}", r.start, r.end)),
                    &format!("goes past the {spp} samples per pixel (spp)"),
                );
            }
        }
        Ok(job)
    }

    /// Render from photon maps traced earlier (`photon photons trace`) instead of tracing.
    pub fn with_photon_maps(mut self, maps: Arc<PhotonMaps>) -> Self {
        self.maps = Some(maps);
        self
    }

    pub fn integrator(&self) -> IntegratorKind {
        self.integrator
    }

    /// Every setting after resolution: given, the scene's, or the default.
    pub fn options(&self) -> &RenderOptions {
        &self.options
    }

    fn filter(&self) -> PixelFilter {
        self.options.filter.unwrap_or(defaults::FILTER)
    }

    fn kernel(&self) -> Kernel {
        self.options.kernel.unwrap_or(defaults::KERNEL)
    }

    /// The image settings of a path, direct or photon render.
    pub fn settings(&self) -> RenderSettings {
        let o = &self.options;
        RenderSettings {
            width: o.width.unwrap_or(self.scene.default_resolution.0),
            height: o.height.unwrap_or(self.scene.default_resolution.1),
            spp: o.spp.unwrap_or(defaults::spp(self.integrator)),
            seed: o.seed.unwrap_or(defaults::SEED),
            filter: self.filter(),
            max_radiance: o.max_radiance,
            spectral: o.spectral.unwrap_or(false),
        }
    }

    /// The configuration of an sppm or ppm render.
    pub fn progressive_config(&self) -> ProgressiveConfig {
        let s = self.settings();
        let o = &self.options;
        ProgressiveConfig {
            method: Method::from_name(self.integrator.name())
                .expect("every progressive integrator is a method"),
            width: s.width,
            height: s.height,
            seed: s.seed,
            alpha: o.alpha.unwrap_or(defaults::ALPHA),
            photons_per_pass: o.photons_per_pass.unwrap_or(defaults::PHOTONS_PER_PASS),
            initial_radius: o.radius,
            max_depth: o.max_depth.unwrap_or(defaults::max_depth(self.integrator)),
            light_samples: o
                .light_samples
                .unwrap_or(defaults::light_samples(self.integrator)),
            spectral: s.spectral,
        }
    }

    /// A fresh progressive state (starting at the pass range's first pass), for callers that
    /// run passes themselves (checkpoints, snapshots, an iterator of images).
    pub fn progressive_state(&self) -> Result<ProgressiveState> {
        let first = self.options.pass_range.map_or(0, |r| r.start);
        ProgressiveState::new(self.scene, self.progressive_config(), first)
    }

    /// The pass to stop before: the range's end, or the passes asked for.
    pub fn target_passes(&self) -> Option<u64> {
        self.options
            .pass_range
            .map(|r| r.end)
            .or(self.options.passes)
    }

    /// Every setting that decides the samples of a path, direct or photon render, resolved:
    /// partial renders merge only when theirs are equal.
    pub fn sample_identity(&self) -> RenderOptions {
        RenderOptions {
            sample_range: None,
            ..self.options.clone()
        }
    }

    /// Write a partial render (`sample_range` or `pass_range`) to the `.part` file `path`:
    /// the fixed-point sums of its samples with the settings they were rendered with, or
    /// the state of its ppm passes.
    pub fn write_part(&self, result: &RenderResult, path: &Path) -> Result<()> {
        if let Some(state) = &result.state {
            return crate::io::checkpoint::save_with(state, &RunInfo::default(), path);
        }
        let out = result.output.as_ref().ok_or_else(|| {
            Error::InvalidSetting("a partial render needs its samples or passes".into())
        })?;
        let origin = PartOrigin {
            scene: self.scene.name.clone(),
            scene_hash: format!("{:016x}", self.scene.content_hash()),
            settings: self.sample_identity(),
            first_sample: self.options.sample_range.map_or(0, |r| r.start as u32),
        };
        crate::io::sample_part::save(&out.sums, &origin, path)
    }

    /// The integrator of a path, direct or photon render, tracing photon maps if it needs
    /// them.
    pub fn integrator_for_samples(
        &self,
        progress: &(dyn Fn(Progress) + Sync),
        timings: &mut Timings,
    ) -> Result<(Integrator, u64)> {
        let o = &self.options;
        let kind = self.integrator;
        let max_depth = o.max_depth.unwrap_or(defaults::max_depth(kind));
        Ok(match kind {
            IntegratorKind::Direct => (
                Integrator::Direct(DirectConfig {
                    max_depth,
                    light_samples: o.light_samples.unwrap_or(defaults::light_samples(kind)),
                    ..DirectConfig::default()
                }),
                0,
            ),
            IntegratorKind::Path => (
                Integrator::Path(PathConfig {
                    max_depth,
                    ..PathConfig::default()
                }),
                0,
            ),
            IntegratorKind::Sppm
            | IntegratorKind::Ppm
            | IntegratorKind::Vcm
            | IntegratorKind::Bdpt
            | IntegratorKind::LightTrace => {
                return Err(Error::InvalidSetting(format!(
                    "{} renders in passes, not samples",
                    self.integrator.name()
                )));
            }
            IntegratorKind::Photon => {
                let start = Instant::now();
                let (maps, photons) = match &self.maps {
                    // Saved maps hold no volume photons (`--force` may pair any map with any
                    // scene); media that only absorb need none.
                    Some(m)
                        if m.volume.is_empty()
                            && self.scene.media().iter().any(|m| m.scatters()) =>
                    {
                        return Err(Error::InvalidScene(SAVED_MAPS_AND_MEDIA.into()));
                    }
                    Some(m) => (m.clone(), 0),
                    None => {
                        let global = o.photons.unwrap_or(defaults::PHOTONS);
                        let caustic = o
                            .caustic_photons
                            .unwrap_or(defaults::CAUSTIC_PHOTONS)
                            .max(global);
                        let config = PhotonConfig {
                            photons: caustic,
                            global_photons: Some(global),
                            absorption: o.absorption,
                            per_channel: o.per_channel.unwrap_or(false),
                            spectral: self.settings().spectral,
                            seed: self.settings().seed,
                            ..PhotonConfig::default()
                        };
                        config.validate()?;
                        let report = |done: u64, total: u64| {
                            progress(Progress {
                                phase: Phase::Tracing,
                                done,
                                total,
                            })
                        };
                        let maps = trace_photons(self.scene, &config, &report)?;
                        timings.trace = start.elapsed().as_secs_f64();
                        (Arc::new(maps), caustic)
                    }
                };
                let start = Instant::now();
                let s = self.photon_settings();
                let p = PhotonIntegrator::new(s, maps);
                timings.build = start.elapsed().as_secs_f64();
                (Integrator::Photon(Box::new(p)), photons)
            }
        })
    }

    fn photon_settings(&self) -> PhotonSettings {
        let o = &self.options;
        let kind = self.integrator;
        let mut s = PhotonSettings::for_scene(self.scene);
        s.max_depth = o.max_depth.unwrap_or(defaults::max_depth(kind));
        s.light_samples = o.light_samples.unwrap_or(defaults::light_samples(kind));
        if let Some(r) = o.radius {
            s.caustic.max_radius = r;
            s.global.max_radius = r;
            s.cache_radius = r;
        }
        let gather = o.gather.unwrap_or(defaults::GATHER);
        if gather == GatherMode::None {
            s.global.k = PhotonSettings::DIRECT_VISUALISATION_K;
        }
        if let Some(k) = o.k {
            s.caustic.k = k;
            s.global.k = k;
        }
        s.caustic.kernel = self.kernel();
        s.global.kernel = self.kernel();
        s.gather_rays = match gather {
            GatherMode::None => 0,
            GatherMode::Final => o.gather_rays.unwrap_or(defaults::GATHER_RAYS),
        };
        s.indirect_scale = o.indirect_scale.unwrap_or(defaults::INDIRECT_SCALE);
        s
    }

    /// Render to the end, or until `cancel` is set. Call it inside a rayon pool to choose
    /// the threads; the image does not depend on their number.
    pub fn render(
        &self,
        progress: &(dyn Fn(Progress) + Sync),
        cancel: &AtomicBool,
    ) -> Result<RenderResult> {
        if self.integrator.is_progressive() {
            return self.render_passes(progress, cancel);
        }
        let mut timings = Timings::default();
        let (integrator, photons) = self.integrator_for_samples(progress, &mut timings)?;
        let settings = self.settings();
        let range = self
            .options
            .sample_range
            .map_or(0..settings.spp, |r| r.start as u32..r.end as u32);
        let start = Instant::now();
        let report = |done: u64, total: u64| {
            progress(Progress {
                phase: Phase::Rendering,
                done,
                total,
            })
        };
        let out =
            render_samples_cancellable(self.scene, &integrator, &settings, range, &report, cancel)?;
        timings.render = start.elapsed().as_secs_f64();
        Ok(RenderResult {
            image: out.image.clone(),
            output: Some(out),
            state: None,
            timings,
            photons,
            cancelled: false,
        })
    }

    /// The budget of a progressive render: the pass range's end or the passes asked for, and
    /// the time (not for a pass range, which is the same work on every machine).
    pub fn budget(&self) -> Budget {
        Budget {
            passes: self.target_passes(),
            seconds: self
                .options
                .time
                .filter(|_| self.options.pass_range.is_none()),
        }
    }

    /// A progressive render's session, for callers that drive passes themselves (to
    /// checkpoint, show snapshots, or iterate over images).
    pub fn session(&self) -> Result<Session> {
        Session::new(self.progressive_state()?, self.budget())
    }

    /// Progressive passes until the budget is spent or `cancel` is set, which abandons the
    /// pass in flight.
    fn render_passes(
        &self,
        progress: &(dyn Fn(Progress) + Sync),
        cancel: &AtomicBool,
    ) -> Result<RenderResult> {
        let mut session = self.session()?;
        let total = session
            .budget()
            .passes
            .map_or(0, |t| t - session.state().first_pass);
        let never = AtomicBool::new(false);
        let ending = session.run(self.scene, &never, cancel, |s, _| {
            progress(Progress {
                phase: Phase::Passes,
                done: s.state().passes,
                total,
            });
            Ok(())
        })?;
        let (photons, seconds) = (session.totals().photons, session.elapsed());
        let state = session.finish(ending)?;
        Ok(RenderResult {
            image: state.image(),
            output: None,
            state: Some(state),
            timings: Timings {
                render: seconds,
                ..Timings::default()
            },
            photons,
            cancelled: ending == Ending::Interrupted,
        })
    }
}
