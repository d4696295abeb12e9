//! `photon render`.

use super::{progress, progressive};
use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use photon::description::builtin::DEFAULT_SCENE;
use photon::film::PixelFilter;
use photon::io::image::{ImageFormat, aov_path, check_writable, write_exr_layers, write_image};
use photon::io::phm;
use photon::io::sample_part::PartOrigin as SampleOrigin;
use photon::render::RenderOutput;
use photon::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use photon::render_job::{
    IntegratorKind, MAX_INDIRECT_SCALE, MAX_K, Phase, Progress, RenderJob, RenderOptions,
};
/// Largest `--exposure` magnitude in stops (2^±100 still fits an f32).
pub(super) const MAX_EXPOSURE: f32 = 100.0;

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
    /// Samples per area light at each diffuse hit [default: 4; 1 per pass for sppm and ppm].
    #[arg(long)]
    light_samples: Option<u32>,
    /// Pixel filter: `box`, or `gaussian:SIGMA` (SIGMA in pixels; the original used 0.5)
    /// [default: box].
    #[arg(long, value_parser = parse_filter)]
    filter: Option<String>,
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
    /// The library's options: what was given here; the library fills in the scene's
    /// `[render]` table and the defaults.
    fn options(&self) -> RenderOptions {
        let name = |v: Option<clap::builder::PossibleValue>| v.map(|v| v.get_name().to_owned());
        RenderOptions {
            integrator: self.integrator.map(|i| match i {
                IntegratorName::Photon => IntegratorKind::Photon,
                IntegratorName::Direct => IntegratorKind::Direct,
                IntegratorName::Path => IntegratorKind::Path,
                IntegratorName::Sppm => IntegratorKind::Sppm,
                IntegratorName::Ppm => IntegratorKind::Ppm,
            }),
            spp: self.spp,
            width: self.width,
            height: self.height,
            seed: self.seed,
            max_depth: self.max_depth,
            light_samples: self.light_samples,
            filter: self.filter.clone(),
            photons: self.photons,
            caustic_photons: self.caustic_photons,
            radius: self.radius,
            k: self.k,
            kernel: self.kernel.and_then(|k| name(k.to_possible_value())),
            gather: self.gather.map(|g| match g {
                GatherMode::Final => photon::render_job::GatherMode::Final,
                GatherMode::None => photon::render_job::GatherMode::None,
            }),
            gather_rays: self.gather_rays,
            indirect_scale: (self.indirect_scale != 1.0).then_some(self.indirect_scale),
            per_channel: self.per_channel,
            absorption: self.absorption,
            passes: self.passes,
            time: self.time,
            photons_per_pass: self.photons_per_pass,
            alpha: self.alpha,
            sample_range: self.sample_range.map(|(a, b)| {
                (
                    u32::try_from(a).unwrap_or(u32::MAX),
                    u32::try_from(b).unwrap_or(u32::MAX),
                )
            }),
            pass_range: self.pass_range,
        }
    }
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

/// A pixel filter, checked here and kept as written for the library.
fn parse_filter(s: &str) -> Result<String, String> {
    s.parse::<PixelFilter>().map(|_| s.to_owned())
}

/// Checks of flags that only the command line has, or whose messages should name the flag.
fn check_flags(a: &RenderArgs) -> Result<()> {
    if !(-MAX_EXPOSURE..=MAX_EXPOSURE).contains(&a.exposure) {
        bail!(
            "--exposure {} must be between -{MAX_EXPOSURE} and {MAX_EXPOSURE} stops",
            a.exposure
        );
    }
    if !(0.0..=MAX_INDIRECT_SCALE).contains(&a.indirect_scale) {
        bail!(
            "--indirect-scale {} must be between 0 and {MAX_INDIRECT_SCALE} (1 is physically correct)",
            a.indirect_scale
        );
    }
    if let Some(k) = a.k
        && k > MAX_K
    {
        bail!("--k {k}: at most {MAX_K} photons per estimate (as in scene files)");
    }
    if let Some(s) = a.time
        && !(s > 0.0 && s.is_finite())
    {
        bail!("--time {s} must be a positive number of seconds");
    }
    if a.passes == Some(0) {
        bail!("--passes 0: a render needs at least one pass");
    }
    if let Some(r) = a.radius
        && !(r > 0.0 && r.is_finite())
    {
        bail!("--radius {r} must be a positive length");
    }
    if a.gather_rays == Some(0) && a.gather != Some(GatherMode::None) {
        bail!("--gather-rays must be at least 1 (or use --gather none)");
    }
    Ok(())
}

pub fn run(a: RenderArgs) -> Result<()> {
    check_flags(&a)?;
    let budget = progressive::Budget {
        passes: a.passes,
        seconds: a.time,
    };
    if let Some(cp) = &a.resume {
        let pool = super::thread_pool(a.threads)?;
        let args = progressive::ResumeArgs {
            budget,
            output: a.output.as_deref(),
            exposure: a.exposure,
            quiet: a.quiet,
            env: &a.env,
        };
        return progressive::resume(cp, &args, &pool);
    }
    let (loaded, inputs) = photon::io::input::recording(|| super::scene_with(&a.scene, &a.env));
    let (scene, spec, load_seconds) = loaded?;
    let mut resolved = a.options();
    resolved.apply_scene_settings(&spec)?;
    let kind = resolved.integrator.unwrap_or(IntegratorKind::Photon);
    if kind.is_progressive()
        && resolved.passes.is_none()
        && resolved.time.is_none()
        && a.pass_range.is_none()
    {
        bail!("give --passes or --time for a progressive render");
    }
    if kind != IntegratorKind::Photon {
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
    if kind.is_progressive() {
        if a.sample_range.is_some() {
            bail!(
                "--sample-range is for --integrator path, direct or photon (ppm has --pass-range)"
            );
        }
        if !a.aov.is_empty() {
            bail!("--aov is for --integrator photon");
        }
        if a.pass_range.is_some() && kind != IntegratorKind::Ppm {
            bail!("--pass-range needs --integrator ppm (sppm passes depend on each other)");
        }
        let job = RenderJob::new(&scene, &spec, a.options())?;
        return run_progressive(&a, &scene, &job, &inputs);
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
        photon::io::atomic::check_writable_path(&output)?;
        None
    } else {
        Some(check_writable(&output)?)
    };
    let aovs: Vec<&str> = if format == Some(ImageFormat::Exr) {
        Vec::new()
    } else {
        a.aov.iter().map(|x| x.name()).collect()
    };
    refuse_inputs(&output, None, &aovs, false, &inputs)?;
    if let Some((_, end)) = a.sample_range {
        let spp = a.spp.or(spec.spp).unwrap_or(kind.default_spp());
        if end > u64::from(spp) {
            bail!(
                "--sample-range {}..{end} goes past the {spp} samples per pixel (--spp)",
                a.sample_range.map_or(0, |r| r.0)
            );
        }
    }
    let component_aovs = a
        .aov
        .iter()
        .any(|x| matches!(x, Aov::Direct | Aov::Caustic | Aov::Indirect));
    if component_aovs && kind != IntegratorKind::Photon {
        bail!("the direct, caustic and indirect AOVs need --integrator photon");
    }
    if a.light_samples == Some(0) {
        bail!("--light-samples must be at least 1");
    }
    let mut job = RenderJob::new(&scene, &spec, a.options())?;
    if let Some(path) = &a.photon_map {
        let start = Instant::now();
        let maps = phm::load(path)?;
        phm::check_scene(&maps, path, &scene.name, scene.content_hash(), a.force)?;
        eprintln!(
            "photon: read {} in {:.2} s",
            path.display(),
            start.elapsed().as_secs_f64()
        );
        job = job.with_photon_maps(Arc::new(maps));
    }
    let settings = job.settings();
    let pool = super::thread_pool(a.threads)?;
    let tracing = progress::bar("tracing photons", a.quiet || kind != IntegratorKind::Photon);
    let rendering = progress::bar("rendering", a.quiet);
    let report = |p: Progress| {
        let bar = if p.phase == Phase::Tracing {
            &tracing
        } else {
            &rendering
        };
        bar.set_length(p.total);
        bar.set_position(p.done);
    };
    let never = AtomicBool::new(false);
    let result = pool.install(|| job.render(&report, &never))?;
    tracing.finish_and_clear();
    rendering.finish_and_clear();
    let out = result
        .output
        .as_ref()
        .context("a sample render has an output")?;
    match format {
        Some(format) => write_outputs(&a, &output, format, out)?,
        None => {
            let origin = SampleOrigin {
                scene: scene.name.clone(),
                scene_hash: format!("{:016x}", scene.content_hash()),
                settings: job.sample_label(),
                first_sample: a.sample_range.map_or(0, |r| r.0 as u32),
            };
            photon::io::sample_part::save(&out.sums, &origin, &output)?;
        }
    }
    let t = result.timings;
    let secs = t.render;
    let m = |x: u64| x as f64 / secs / 1e6;
    let photon_phases = if kind == IntegratorKind::Photon {
        format!("trace {:.2} s, build {:.2} s, ", t.trace, t.build)
    } else {
        String::new()
    };
    eprintln!(
        "photon: {} {}×{} {} spp ({}) on {} threads: load {:.2} s ({} primitives), {photon_phases}render {secs:.2} s, total {:.2} s; {:.2} M samples/s, {:.2} M rays/s (camera {:.2}, bounce {:.2}, shadow {:.2}) → {}",
        scene.name,
        settings.width,
        settings.height,
        settings.spp,
        kind.name(),
        pool.current_num_threads(),
        load_seconds,
        scene.primitive_count(),
        load_seconds + t.trace + t.build + secs,
        m(out.samples),
        m(out.rays.total()),
        m(out.rays.camera),
        m(out.rays.bounce),
        m(out.rays.shadow),
        output.display()
    );
    Ok(())
}

fn run_progressive(
    a: &RenderArgs,
    scene: &Scene,
    job: &RenderJob,
    inputs: &[PathBuf],
) -> Result<()> {
    let partial = a.pass_range.is_some();
    let budget = progressive::Budget {
        passes: job.target_passes(),
        seconds: if partial { None } else { job.options().time },
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
        photon::io::atomic::check_writable_path(&output)?;
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
    refuse_inputs(
        &output,
        (!partial).then_some(&checkpoint),
        &[],
        a.snapshots,
        inputs,
    )?;
    let state = job.progressive_state()?;
    let pool = super::thread_pool(a.threads)?;
    let outputs = progressive::Outputs {
        checkpoint,
        image: output,
        snapshots: a.snapshots,
        exposure: a.exposure,
        quiet: a.quiet,
        partial,
        env: progressive::env_settings(&a.env),
    };
    progressive::run(scene, state, budget, &outputs, &pool)
}

/// `path` resolved through symbolic links, as far as it exists (an output may not yet).
fn canonical(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let parent = path.parent().filter(|d| !d.as_os_str().is_empty());
    match (
        parent.map_or(std::fs::canonicalize("."), std::fs::canonicalize),
        path.file_name(),
    ) {
        (Ok(dir), Some(name)) => dir.join(name),
        _ => std::path::absolute(path).unwrap_or_else(|_| path.to_owned()),
    }
}

/// The files an image output writes: `.npy` is one file per channel.
fn image_files(path: &Path) -> Vec<PathBuf> {
    if path.extension().and_then(|e| e.to_str()) == Some("npy") {
        ["r", "g", "b"]
            .map(|c| photon::io::image::npy_channel_path(path, c))
            .to_vec()
    } else {
        vec![path.to_owned()]
    }
}

/// Refuse a render whose output, checkpoint, AOV files or snapshots (`NAME.passNNNNN.EXT`)
/// would replace one of the files its scene reads (`inputs`), compared as canonical paths.
pub fn refuse_inputs(
    output: &Path,
    checkpoint: Option<&Path>,
    aovs: &[&str],
    snapshots: bool,
    inputs: &[PathBuf],
) -> Result<()> {
    let inputs: Vec<PathBuf> = inputs.iter().map(|p| canonical(p)).collect();
    let mut written = image_files(output);
    for aov in aovs {
        written.extend(image_files(&aov_path(output, aov)));
    }
    written.extend(checkpoint.map(Path::to_path_buf));
    for w in &written {
        if inputs.contains(&canonical(w)) {
            bail!(
                "'{}' is a file the scene reads; writing the render there would replace it: give another -o (or --checkpoint)",
                w.display()
            );
        }
    }
    if !snapshots {
        return Ok(());
    }
    let out = canonical(output);
    let (stem, ext) = (
        out.file_stem().map(|s| s.to_string_lossy().into_owned()),
        out.extension().map(|e| e.to_string_lossy().into_owned()),
    );
    let snapshot = inputs.iter().find(|i| {
        let name = i.file_name().map(|n| n.to_string_lossy().into_owned());
        i.parent() == out.parent()
            && name.zip(stem.as_ref()).is_some_and(|(n, s)| {
                n.strip_prefix(&format!("{s}.pass"))
                    .and_then(|r| r.strip_suffix(&format!(".{}", ext.as_deref().unwrap_or("exr"))))
                    .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
            })
    });
    if let Some(s) = snapshot {
        bail!(
            "'{}' is a file the scene reads, and a snapshot of -o {} would replace it: give another -o",
            s.display(),
            output.display()
        );
    }
    Ok(())
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

/// Refuse the flags a job sets itself or cannot carry: checked when the job is made and
/// again by each worker, whose manifest may have been edited.
fn refuse_per_run_flags(a: &RenderArgs) -> Result<()> {
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
    Ok(())
}

/// Check that the render `scene_and_flags` describes can be split into tasks, load its scene
/// (recording the files it reads) and say what the tasks count.
pub fn plan_job(scene_and_flags: &[String]) -> Result<JobPlan> {
    let a = parse_render(scene_and_flags)?;
    refuse_per_run_flags(&a)?;
    let (loaded, files) = photon::io::input::recording(|| super::scene_with(&a.scene, &a.env));
    let (scene, spec, _) = loaded?;
    let mut options = a.options();
    options.apply_scene_settings(&spec)?;
    let kind = options.integrator.unwrap_or(IntegratorKind::Photon);
    let (integrator, unit, total) = match kind {
        IntegratorKind::Sppm => bail!(
            "sppm cannot be split into tasks: each pass shrinks the radii the last one left, so passes depend on each other; use --integrator ppm, whose passes are independent"
        ),
        IntegratorKind::Ppm => {
            let passes = options
                .passes
                .context("give --passes: a ppm job splits its passes into tasks")?;
            ("ppm", photon::job::Unit::Passes, passes)
        }
        other => {
            let spp = options.spp.unwrap_or(other.default_spp());
            (other.name(), photon::job::Unit::Samples, u64::from(spp))
        }
    };
    // The whole render must be valid before it is split.
    RenderJob::new(&scene, &spec, a.options())?;
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
    refuse_per_run_flags(&a)?;
    match unit {
        photon::job::Unit::Passes => a.pass_range = Some(range),
        photon::job::Unit::Samples => a.sample_range = Some(range),
    }
    a.output = Some(output);
    a.quiet = true;
    a.threads = threads;
    run(a)
}
