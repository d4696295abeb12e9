//! `photon render`.

use super::{progress, progressive};
use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use photon::description::RenderSpec;
use photon::description::builtin::DEFAULT_SCENE;
use photon::film::PixelFilter;
use photon::integrator::{DirectConfig, Integrator, PathConfig, PhotonIntegrator, PhotonSettings};
use photon::io::image::{ImageFormat, aov_path, check_writable, write_exr_layers, write_image};
use photon::io::phm;
use photon::io::sample_part::PartOrigin as SampleOrigin;
use photon::photon::{Kernel, PhotonConfig, PhotonMaps, trace_photons};
use photon::progressive::{Method, ProgressiveConfig, ProgressiveState};
use photon::render::{RenderOutput, RenderSettings, render_samples};
use photon::scene::Scene;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// Largest `--k`: the scene files' limit; each estimate keeps k + 1 candidates.
const MAX_K: usize = 1 << 16;
/// Largest `--indirect-scale` (a debugging knob; 1 is correct): larger overflowed to Inf.
const MAX_INDIRECT_SCALE: f32 = 1e6;
/// Largest `--exposure` magnitude in stops (2^±100 still fits an f32).
const MAX_EXPOSURE: f32 = 100.0;

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum IntegratorName {
    /// Two-pass photon mapping: direct light, caustic map, final gathering of the global map.
    Photon,
    /// Ray-traced direct light with mirror and glass recursion; no indirect diffuse light.
    Direct,
    /// Unidirectional path tracing with NEE and MIS: the reference.
    Path,
    /// Stochastic progressive photon mapping (Hachisuka & Jensen 2009): converges to the exact image.
    Sppm,
    /// Probabilistic progressive photon mapping (Knaus & Zwicker 2011): independent passes.
    Ppm,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum GatherMode {
    /// Final gathering: rays from each diffuse point read precomputed irradiance.
    Final,
    /// Read the global photon map directly (the original project's rendering, done right).
    None,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum KernelName {
    Box,
    Cone,
    Gaussian,
    Epanechnikov,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Aov {
    Direct,
    Caustic,
    Indirect,
    Albedo,
    Normal,
}

impl Aov {
    fn name(self) -> &'static str {
        match self {
            Aov::Direct => "direct",
            Aov::Caustic => "caustic",
            Aov::Indirect => "indirect",
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
        }
    }
}

#[derive(clap::Args)]
pub struct RenderArgs {
    /// Built-in scene name (see `photon scenes`) or scene file: .toml (docs/scene-format.md),
    /// .gltf or .glb. Settings given here override the file's [render] table.
    #[arg(default_value = DEFAULT_SCENE)]
    scene: String,
    /// Output image [default: render.png]; the extension picks the format (.png, .exr, .pfm,
    /// or .npy for one NumPy array per channel: NAME_r.npy, NAME_g.npy, NAME_b.npy). With
    /// --pass-range, the partial render file (.part).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Rendering algorithm [default: the scene file's, else photon].
    #[arg(long, value_enum)]
    integrator: Option<IntegratorName>,
    /// Samples per pixel [default: 8 for photon, 16 for direct, 64 for path].
    #[arg(long)]
    spp: Option<u32>,
    /// Image width in pixels [default: the scene's].
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels [default: the scene's].
    #[arg(long)]
    height: Option<u32>,
    /// Seed of every random stream; the same seed gives the same image [default: 0].
    #[arg(long)]
    seed: Option<u64>,
    /// Worker threads [default: one per core]; the image does not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Maximum number of bounces [default: 16 for direct and photon, 256 for path].
    #[arg(long)]
    max_depth: Option<u32>,
    /// Samples per area light at each diffuse hit (direct and photon) [default: 4].
    #[arg(long)]
    light_samples: Option<u32>,
    /// Pixel filter: `box`, or `gaussian:SIGMA` (SIGMA in pixels; the original used 0.5)
    /// [default: box].
    #[arg(long, value_parser = parse_filter)]
    filter: Option<PixelFilter>,
    /// Exposure in stops, applied to PNG output only.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    /// Extra images: any of direct, caustic, indirect, albedo, normal (comma-separated); layers
    /// of the EXR output, or files NAME.AOV.EXT for other formats.
    #[arg(long, value_enum, value_delimiter = ',')]
    aov: Vec<Aov>,
    /// Photons for the global map (photon integrator) [default: 250000].
    #[arg(long)]
    photons: Option<u64>,
    /// Photons traced for the caustic map [default: 2000000, at least --photons].
    #[arg(long)]
    caustic_photons: Option<u64>,
    /// Maximum gather radius in scene units [default: 1% (caustic) and 5% (global) of the
    /// scene's diagonal].
    #[arg(long)]
    radius: Option<f32>,
    /// Photons per estimate [default: 32, or 256 for the global map with --gather none]; 0
    /// gathers at a fixed radius.
    #[arg(long)]
    k: Option<usize>,
    /// Density-estimation kernel [default: epanechnikov].
    #[arg(long, value_enum)]
    kernel: Option<KernelName>,
    /// How indirect light is found: final gathering, or the global map read directly
    /// [default: final].
    #[arg(long, value_enum)]
    gather: Option<GatherMode>,
    /// Final-gather rays per camera sample [default: 4, so 32 per pixel at 8 spp].
    #[arg(long)]
    gather_rays: Option<u32>,
    /// Weight on the indirect part (1 is physically correct).
    #[arg(long, default_value_t = 1.0)]
    indirect_scale: f32,
    /// Trace red, green and blue photons separately, as the original project did.
    #[arg(long)]
    per_channel: bool,
    /// Fixed photon absorption probability instead of Russian roulette on albedo.
    #[arg(long)]
    absorption: Option<f32>,
    /// Render from a saved photon map (`photon photons trace`) instead of tracing anew.
    #[arg(long)]
    photon_map: Option<PathBuf>,
    /// Use --photon-map even if it was traced for another scene.
    #[arg(long)]
    force: bool,
    /// Progressive (sppm, ppm): stop after this many passes.
    #[arg(long)]
    passes: Option<u64>,
    /// Progressive: stop after this many seconds (the image of the passes done by then).
    #[arg(long)]
    time: Option<f64>,
    /// Progressive: photons traced per pass [default: 100000].
    #[arg(long)]
    photons_per_pass: Option<u64>,
    /// Progressive: radius reduction α in (0, 1) [default: 2/3].
    #[arg(long)]
    alpha: Option<f64>,
    /// Progressive: write the image after passes 1, 2, 4, 8, … (and at least every minute) as
    /// NAME.passNNNNN.EXT.
    #[arg(long)]
    snapshots: bool,
    /// Progressive: checkpoint file [default: the output with extension .checkpoint].
    #[arg(long)]
    checkpoint: Option<PathBuf>,
    /// Continue a progressive render from its checkpoint (with --passes or --time to extend it).
    #[arg(long)]
    resume: Option<PathBuf>,
    /// ppm: render only passes a..b (end exclusive) into a partial file for `photon merge`.
    #[arg(long, value_parser = parse_range)]
    pass_range: Option<(u64, u64)>,
    /// path, direct, photon: render only samples a..b (end exclusive) of each pixel's --spp
    /// into a partial file (.part) for `photon merge`.
    #[arg(long, value_parser = parse_range)]
    sample_range: Option<(u64, u64)>,
    #[command(flatten)]
    env: super::EnvironmentArgs,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

impl RenderArgs {
    fn integrator(&self) -> IntegratorName {
        self.integrator.unwrap_or(IntegratorName::Photon)
    }

    fn seed(&self) -> u64 {
        self.seed.unwrap_or(0)
    }

    fn light_samples(&self) -> u32 {
        self.light_samples.unwrap_or(4)
    }

    fn gather(&self) -> GatherMode {
        self.gather.unwrap_or(GatherMode::Final)
    }

    /// Fill every setting not given on the command line from the scene file's [render] table.
    fn apply_scene_settings(&mut self, r: &RenderSpec) -> Result<()> {
        if self.integrator.is_none()
            && let Some(name) = &r.integrator
        {
            self.integrator =
                Some(IntegratorName::from_str(name, true).map_err(|_| {
                    anyhow::anyhow!("the scene names an unknown integrator '{name}'")
                })?);
        }
        if self.filter.is_none()
            && let Some(f) = &r.filter
        {
            self.filter = Some(f.parse().map_err(|e: String| anyhow::anyhow!(e))?);
        }
        self.spp = self.spp.or(r.spp);
        self.seed = self.seed.or(r.seed);
        self.max_depth = self.max_depth.or(r.max_depth);
        self.light_samples = self.light_samples.or(r.light_samples);
        self.radius = self.radius.or(r.radius);
        if matches!(
            self.integrator(),
            IntegratorName::Sppm | IntegratorName::Ppm
        ) {
            self.passes = self.passes.or(r.passes);
            self.time = self.time.or(r.time);
            self.alpha = self.alpha.or(r.alpha);
            self.photons_per_pass = self.photons_per_pass.or(r.photons_per_pass);
        }
        // Photon-integrator settings apply only when that integrator runs, so that a scene
        // written for photon mapping can still be rendered with --integrator path.
        if self.integrator() == IntegratorName::Photon {
            if self.kernel.is_none()
                && let Some(k) = &r.kernel
            {
                self.kernel = Some(value_enum(k, "kernel")?);
            }
            if self.gather.is_none()
                && let Some(g) = &r.gather
            {
                self.gather = Some(value_enum(g, "gather")?);
            }
            self.k = self.k.or(r.k.map(|k| k as usize));
            self.photons = self.photons.or(r.photons);
            self.caustic_photons = self.caustic_photons.or(r.caustic_photons);
            self.gather_rays = self.gather_rays.or(r.gather_rays);
        }
        Ok(())
    }
}

/// A command-line enum value named in a scene file (already checked against the same list).
fn value_enum<T: ValueEnum>(name: &str, what: &str) -> Result<T> {
    T::from_str(name, true)
        .map_err(|_| anyhow::anyhow!("the scene names an unknown {what} '{name}'"))
}

fn parse_range(s: &str) -> Result<(u64, u64), String> {
    let (a, b) = s
        .split_once("..")
        .ok_or_else(|| format!("'{s}' is not a range; expected a..b such as 0..64"))?;
    let parse = |t: &str| {
        t.trim()
            .parse::<u64>()
            .map_err(|_| format!("'{t}' in '{s}' is not a pass number"))
    };
    let (a, b) = (parse(a)?, parse(b)?);
    if a >= b {
        return Err(format!("the range {a}..{b} is empty"));
    }
    Ok((a, b))
}

fn parse_filter(s: &str) -> Result<PixelFilter, String> {
    s.parse()
}

/// Time spent in each phase, for the summary line.
#[derive(Default)]
struct Phases {
    load: f64,
    trace: f64,
    build: f64,
}

pub fn run(a: RenderArgs) -> Result<()> {
    let budget = progressive::Budget {
        passes: a.passes,
        seconds: a.time,
    };
    if let Some(s) = a.time
        && !(s > 0.0 && s.is_finite())
    {
        bail!("--time {s} must be a positive number of seconds");
    }
    if let Some(cp) = &a.resume {
        let pool = super::thread_pool(a.threads)?;
        return progressive::resume(cp, budget, a.output.as_deref(), a.exposure, a.quiet, &pool);
    }
    let (scene, spec, load_seconds) = super::scene_with(&a.scene, &a.env)?;
    let mut a = a;
    a.apply_scene_settings(&spec)?;
    let a = a;
    if a.integrator() != IntegratorName::Photon {
        let photon_only = [
            (a.photon_map.is_some(), "--photon-map"),
            (a.per_channel, "--per-channel"),
            (a.absorption.is_some(), "--absorption"),
            (a.gather_rays.is_some(), "--gather-rays"),
            (a.caustic_photons.is_some(), "--caustic-photons"),
        ];
        if let Some((_, flag)) = photon_only.iter().find(|(given, _)| *given) {
            bail!("{flag} is for --integrator photon");
        }
    }
    if matches!(a.integrator(), IntegratorName::Sppm | IntegratorName::Ppm) {
        if a.sample_range.is_some() {
            bail!(
                "--sample-range is for --integrator path, direct or photon (ppm has --pass-range)"
            );
        }
        return run_progressive(&a, &scene, budget);
    }
    let progressive_only = [
        (a.pass_range.is_some(), "--pass-range"),
        (a.passes.is_some(), "--passes"),
        (a.time.is_some(), "--time"),
        (a.checkpoint.is_some(), "--checkpoint"),
        (a.snapshots, "--snapshots"),
        (a.alpha.is_some(), "--alpha"),
        (a.photons_per_pass.is_some(), "--photons-per-pass"),
    ];
    if let Some((_, flag)) = progressive_only.iter().find(|(given, _)| *given) {
        // Accepted and ignored, it let a user believe a checkpoint was being written.
        bail!("{flag} is for --integrator sppm or ppm");
    }
    let partial = a.sample_range.is_some();
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(if partial { "render.part" } else { "render.png" }));
    let format = if partial {
        if output.extension().and_then(|e| e.to_str()) != Some("part") {
            bail!(
                "'{}': a partial render is written to a .part file",
                output.display()
            );
        }
        if !a.aov.is_empty() {
            bail!("--aov cannot be split: a partial render holds the beauty image only");
        }
        photon::io::image::check_writable_path(&output)?;
        None
    } else {
        Some(check_writable(&output)?)
    };
    if a.light_samples() == 0 {
        bail!("--light-samples must be at least 1");
    }
    if !(0.0..=MAX_INDIRECT_SCALE).contains(&a.indirect_scale) {
        bail!(
            "--indirect-scale {} must be between 0 and {MAX_INDIRECT_SCALE} (1 is physically correct)",
            a.indirect_scale
        );
    }
    if !(-MAX_EXPOSURE..=MAX_EXPOSURE).contains(&a.exposure) {
        bail!(
            "--exposure {} must be between -{MAX_EXPOSURE} and {MAX_EXPOSURE} stops",
            a.exposure
        );
    }
    if let Some(k) = a.k
        && k > MAX_K
    {
        bail!("--k {k}: at most {MAX_K} photons per estimate (as in scene files)");
    }
    let component_aovs = a
        .aov
        .iter()
        .any(|x| matches!(x, Aov::Direct | Aov::Caustic | Aov::Indirect));
    if component_aovs && a.integrator() != IntegratorName::Photon {
        bail!("the direct, caustic and indirect AOVs need --integrator photon");
    }
    let (default_w, default_h) = scene.default_resolution;
    let settings = RenderSettings {
        width: a.width.unwrap_or(default_w),
        height: a.height.unwrap_or(default_h),
        spp: a.spp.unwrap_or(match a.integrator() {
            IntegratorName::Photon => 8,
            IntegratorName::Direct => 16,
            IntegratorName::Path => 64,
            IntegratorName::Sppm | IntegratorName::Ppm => 1,
        }),
        seed: a.seed(),
        filter: a.filter.unwrap_or(PixelFilter::Box),
    };
    settings.validate()?;
    let samples = match a.sample_range {
        None => 0..settings.spp,
        Some((start, end)) if end <= u64::from(settings.spp) => start as u32..end as u32,
        Some((start, end)) => bail!(
            "--sample-range {start}..{end} goes past the {} samples per pixel (--spp)",
            settings.spp
        ),
    };
    let pool = super::thread_pool(a.threads)?;
    let mut phases = Phases {
        load: load_seconds,
        ..Phases::default()
    };
    let integrator = pool.install(|| integrator(&a, &scene, &mut phases))?;
    let bar = progress::bar("rendering", a.quiet);
    let start = Instant::now();
    let out = pool.install(|| {
        render_samples(
            &scene,
            &integrator,
            &settings,
            samples.clone(),
            &progress::callback(&bar),
        )
    })?;
    let secs = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    match format {
        Some(format) => write_outputs(&a, &output, format, &out)?,
        None => {
            let origin = SampleOrigin {
                scene: scene.name.clone(),
                scene_hash: format!("{:016x}", scene.content_hash()),
                settings: sample_settings(&a, &settings),
                first_sample: samples.start,
            };
            photon::io::sample_part::save(&out.sums, &origin, &output)?;
        }
    }
    let m = |x: u64| x as f64 / secs / 1e6;
    let photon_phases = if let Integrator::Photon(_) = integrator {
        format!("trace {:.2} s, build {:.2} s, ", phases.trace, phases.build)
    } else {
        String::new()
    };
    eprintln!(
        "photon: {} {}×{} {} spp ({}) on {} threads: load {:.2} s ({} primitives), {photon_phases}render {secs:.2} s, total {:.2} s; {:.2} M samples/s, {:.2} M rays/s (camera {:.2}, bounce {:.2}, shadow {:.2}) → {}",
        scene.name,
        settings.width,
        settings.height,
        settings.spp,
        integrator.name(),
        pool.current_num_threads(),
        phases.load,
        scene.primitive_count(),
        phases.load + phases.trace + phases.build + secs,
        m(out.samples),
        m(out.rays.total()),
        m(out.rays.camera),
        m(out.rays.bounce),
        m(out.rays.shadow),
        output.display()
    );
    Ok(())
}

/// Every setting that changes a sample of a path, direct or photon render, in one string:
/// partial renders merge only when theirs are equal.
fn sample_settings(a: &RenderArgs, s: &RenderSettings) -> String {
    let name = a
        .integrator()
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_owned());
    format!(
        "{name} {}x{} spp={} seed={} filter={:?} max_depth={:?} light_samples={} photons={:?} caustic_photons={:?} radius={:?} k={:?} kernel={:?} gather={:?} gather_rays={:?} indirect_scale={} per_channel={} absorption={:?}",
        s.width,
        s.height,
        s.spp,
        s.seed,
        s.filter,
        a.max_depth,
        a.light_samples(),
        a.photons,
        a.caustic_photons,
        a.radius,
        a.k,
        a.kernel
            .and_then(|k| k.to_possible_value().map(|v| v.get_name().to_owned())),
        a.gather
            .and_then(|g| g.to_possible_value().map(|v| v.get_name().to_owned())),
        a.gather_rays,
        a.indirect_scale,
        a.per_channel,
        a.absorption,
    )
}

fn run_progressive(a: &RenderArgs, scene: &Scene, budget: progressive::Budget) -> Result<()> {
    let method = match a.integrator() {
        IntegratorName::Sppm => Method::Sppm,
        _ => Method::Ppm,
    };
    if !a.aov.is_empty() {
        bail!("--aov is for --integrator photon");
    }
    let (w, h) = scene.default_resolution;
    let config = ProgressiveConfig {
        method,
        width: a.width.unwrap_or(w),
        height: a.height.unwrap_or(h),
        seed: a.seed(),
        alpha: a.alpha.unwrap_or(2.0 / 3.0),
        photons_per_pass: a.photons_per_pass.unwrap_or(100_000),
        initial_radius: a.radius,
        max_depth: a.max_depth.unwrap_or(16),
        light_samples: a.light_samples(),
    };
    let (first, budget, partial) = match a.pass_range {
        Some(_) if method != Method::Ppm => {
            bail!("--pass-range needs --integrator ppm (sppm passes depend on each other)")
        }
        Some((start, end)) => (
            start,
            progressive::Budget {
                passes: Some(end),
                seconds: None,
            },
            true,
        ),
        None => (0, budget, false),
    };
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(if partial { "render.part" } else { "render.png" }));
    if partial {
        if output.extension().and_then(|e| e.to_str()) != Some("part") {
            bail!(
                "'{}': a partial render is written to a .part file",
                output.display()
            );
        }
        photon::io::image::check_writable_path(&output)?;
    } else {
        check_writable(&output)?;
    }
    let checkpoint = a
        .checkpoint
        .clone()
        .unwrap_or_else(|| progressive::default_checkpoint(&output));
    // A checkpoint written over the scene file or the image destroyed what the user had.
    let same = |x: &std::path::Path, y: &std::path::Path| {
        std::path::absolute(x).ok() == std::path::absolute(y).ok()
    };
    if same(&checkpoint, &output) {
        bail!(
            "--checkpoint {} is the output image too; give them different names",
            checkpoint.display()
        );
    }
    if same(&checkpoint, std::path::Path::new(&a.scene)) {
        bail!(
            "--checkpoint {} is the scene file; it would be overwritten",
            checkpoint.display()
        );
    }
    if checkpoint.extension().is_some_and(|e| {
        ["toml", "gltf", "glb", "obj", "ply"].contains(&e.to_string_lossy().as_ref())
    }) {
        bail!(
            "--checkpoint {}: a checkpoint is not a scene file; name it NAME.checkpoint",
            checkpoint.display()
        );
    }
    // A new render must not replace the checkpoint of another (an interrupted re-run replaced
    // an 80-pass checkpoint and its image with one pass).
    if !partial
        && let Ok((old, _)) = photon::io::checkpoint::load_with(&checkpoint)
        && old.passes > 0
    {
        bail!(
            "{} holds {} passes of a render: continue it with --resume {}, or delete it to start again",
            checkpoint.display(),
            old.passes,
            checkpoint.display()
        );
    }
    let state = ProgressiveState::new(scene, config, first)?;
    let pool = super::thread_pool(a.threads)?;
    let outputs = progressive::Outputs {
        checkpoint,
        image: output,
        snapshots: a.snapshots,
        exposure: a.exposure,
        quiet: a.quiet,
        partial,
    };
    progressive::run(scene, state, budget, &outputs, &pool)
}

fn integrator(a: &RenderArgs, scene: &Scene, phases: &mut Phases) -> Result<Integrator> {
    Ok(match a.integrator() {
        IntegratorName::Direct => Integrator::Direct(DirectConfig {
            max_depth: a.max_depth.unwrap_or(DirectConfig::default().max_depth),
            light_samples: a.light_samples(),
            ..DirectConfig::default()
        }),
        IntegratorName::Path => Integrator::Path(PathConfig {
            max_depth: a.max_depth.unwrap_or(PathConfig::default().max_depth),
            ..PathConfig::default()
        }),
        IntegratorName::Sppm | IntegratorName::Ppm => {
            unreachable!("progressive integrators run apart")
        }
        IntegratorName::Photon => {
            let maps = photon_maps(a, scene, phases)?;
            let mut s = PhotonSettings::for_scene(scene);
            if let Some(d) = a.max_depth {
                s.max_depth = d;
            }
            s.light_samples = a.light_samples();
            if let Some(r) = a.radius {
                if !(r > 0.0 && r.is_finite()) {
                    bail!("--radius {r} must be a positive length");
                }
                s.caustic.max_radius = r;
                s.global.max_radius = r;
                s.cache_radius = r;
            }
            if a.gather() == GatherMode::None {
                s.global.k = PhotonSettings::DIRECT_VISUALISATION_K;
            }
            if let Some(k) = a.k {
                s.caustic.k = k;
                s.global.k = k;
            }
            let kernel = match a.kernel.unwrap_or(KernelName::Epanechnikov) {
                KernelName::Box => Kernel::Box,
                KernelName::Cone => Kernel::Cone,
                KernelName::Gaussian => Kernel::Gaussian,
                KernelName::Epanechnikov => Kernel::Epanechnikov,
            };
            s.caustic.kernel = kernel;
            s.global.kernel = kernel;
            s.gather_rays = match a.gather() {
                GatherMode::None => 0,
                GatherMode::Final => a.gather_rays.unwrap_or(s.gather_rays),
            };
            if a.gather() == GatherMode::Final && s.gather_rays == 0 {
                bail!("--gather-rays must be at least 1 (or use --gather none)");
            }
            s.indirect_scale = a.indirect_scale;
            let start = Instant::now();
            let p = PhotonIntegrator::new(s, Arc::new(maps));
            phases.build += start.elapsed().as_secs_f64();
            Integrator::Photon(Box::new(p))
        }
    })
}

fn photon_maps(a: &RenderArgs, scene: &Scene, phases: &mut Phases) -> Result<PhotonMaps> {
    let start = Instant::now();
    if let Some(path) = &a.photon_map {
        let maps = phm::load(path)?;
        phm::check_scene(&maps, path, &scene.name, scene.content_hash(), a.force)?;
        phases.build += start.elapsed().as_secs_f64();
        return Ok(maps);
    }
    let global = a.photons.unwrap_or(250_000);
    let caustic = a.caustic_photons.unwrap_or(2_000_000).max(global);
    let config = PhotonConfig {
        photons: caustic,
        global_photons: Some(global),
        absorption: a.absorption,
        per_channel: a.per_channel,
        seed: a.seed(),
        ..PhotonConfig::default()
    };
    config.validate()?;
    let bar = progress::bar("tracing photons", a.quiet);
    let maps = trace_photons(scene, &config, &progress::callback(&bar))?;
    bar.finish_and_clear();
    phases.trace = start.elapsed().as_secs_f64();
    Ok(maps)
}

fn write_outputs(
    a: &RenderArgs,
    output: &std::path::Path,
    format: ImageFormat,
    out: &RenderOutput,
) -> Result<()> {
    let aov_image = |x: Aov| match x {
        Aov::Direct => &out.aovs.direct,
        Aov::Caustic => &out.aovs.caustic,
        Aov::Indirect => &out.aovs.indirect,
        Aov::Albedo => &out.aovs.albedo,
        Aov::Normal => &out.aovs.normal,
    };
    if format == ImageFormat::Exr && !a.aov.is_empty() {
        let mut layers = vec![("beauty", &out.image)];
        layers.extend(a.aov.iter().map(|&x| (x.name(), aov_image(x))));
        write_exr_layers(output, &layers)?;
        return Ok(());
    }
    write_image(&out.image, output, a.exposure)?;
    for &x in &a.aov {
        write_image(aov_image(x), &aov_path(output, x.name()), a.exposure)?;
    }
    Ok(())
}

/// A `photon render` command line on its own, as job manifests keep it.
#[derive(clap::Parser)]
#[command(name = "photon render", no_binary_name = true)]
struct RenderCommand {
    #[command(flatten)]
    args: RenderArgs,
}

/// Parse `SCENE [FLAGS...]` as `photon render` would.
fn parse_render(scene_and_flags: &[String]) -> Result<RenderArgs> {
    use clap::Parser;
    RenderCommand::try_parse_from(scene_and_flags)
        .map(|c| c.args)
        .map_err(|e| anyhow::anyhow!("{}", e.render().to_string().trim_end()))
}

/// How a render splits into the tasks of a job.
pub struct JobPlan {
    pub integrator: &'static str,
    pub unit: photon::job::Unit,
    pub total: u64,
    pub scene: Scene,
    /// Every file the scene read, absolute.
    pub files: Vec<PathBuf>,
}

/// Check that the render `scene_and_flags` describes can be split into tasks, load its scene
/// (recording the files it reads) and say what the tasks count.
pub fn plan_job(scene_and_flags: &[String]) -> Result<JobPlan> {
    let mut a = parse_render(scene_and_flags)?;
    let per_run = [
        (
            a.output.is_some(),
            "-o (the job folder holds the parts; `photon job merge` writes the image)",
        ),
        (
            a.pass_range.is_some(),
            "--pass-range (the job sets each task's)",
        ),
        (
            a.sample_range.is_some(),
            "--sample-range (the job sets each task's)",
        ),
        (a.checkpoint.is_some(), "--checkpoint"),
        (a.resume.is_some(), "--resume"),
        (a.snapshots, "--snapshots"),
        (
            a.time.is_some(),
            "--time (a time budget is not the same work on every machine; give --passes or --spp)",
        ),
        (
            !a.aov.is_empty(),
            "--aov (parts hold the beauty image only)",
        ),
        (a.photon_map.is_some(), "--photon-map"),
        (
            a.threads.is_some(),
            "--threads (give it to `photon job run`)",
        ),
    ];
    if let Some((_, flag)) = per_run.iter().find(|(given, _)| *given) {
        bail!("a job cannot take {flag}");
    }
    if let Some(env) = &a.env.env
        && std::path::Path::new(env).exists()
    {
        bail!(
            "a job cannot take --env FILE: put the sky in the scene file ([[lights]] type = \"environment\") so that the job carries it"
        );
    }
    let (loaded, files) = photon::io::input::recording(|| super::scene_with(&a.scene, &a.env));
    let (scene, spec, _) = loaded?;
    a.apply_scene_settings(&spec)?;
    let (integrator, unit, total) = match a.integrator() {
        IntegratorName::Sppm => bail!(
            "sppm cannot be split into tasks: each pass shrinks the radii the last one left, so passes depend on each other; use --integrator ppm, whose passes are independent"
        ),
        IntegratorName::Ppm => {
            let passes = a
                .passes
                .context("give --passes: a ppm job splits its passes into tasks")?;
            ("ppm", photon::job::Unit::Passes, passes)
        }
        other => {
            let name = match other {
                IntegratorName::Path => "path",
                IntegratorName::Direct => "direct",
                _ => "photon",
            };
            let spp = a.spp.unwrap_or(match other {
                IntegratorName::Path => 64,
                IntegratorName::Direct => 16,
                _ => 8,
            });
            (name, photon::job::Unit::Samples, u64::from(spp))
        }
    };
    Ok(JobPlan {
        integrator,
        unit,
        total,
        scene,
        files,
    })
}

/// Render one task of a job: the job's render command line, restricted to `range` of its
/// passes or samples, into the part file `output`.
pub fn render_task(
    scene_and_flags: &[String],
    unit: photon::job::Unit,
    range: (u64, u64),
    output: PathBuf,
    threads: Option<usize>,
) -> Result<()> {
    let mut a = parse_render(scene_and_flags)?;
    match unit {
        photon::job::Unit::Passes => a.pass_range = Some(range),
        photon::job::Unit::Samples => a.sample_range = Some(range),
    }
    a.output = Some(output);
    a.quiet = true;
    a.threads = threads;
    run(a)
}
