//! `photon render`.

use super::live::{Live, LiveOutputs};
use super::{progress, progressive};
use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use photon::description::builtin::DEFAULT_SCENE;
use photon::io::image::{
    ColorSpace, ImageFormat, WriteAs, aov_path, write_exr_layers, write_image,
};
use photon::io::phm;
use photon::render::RenderOutput;
use photon::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::setting_flags::SettingFlags;
use photon::render_job::{Phase, Progress, RenderJob};
use photon::settings::{Group, IntegratorKind, RenderOptions};
/// Largest `--exposure` magnitude in stops (2^±100 still fits an f32).
pub(super) const MAX_EXPOSURE: f32 = 100.0;

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

/// The `--help` groups the command line's own flags join, the settings' own.
pub const OUTPUT: &str = Group::SceneAndOutput.heading();
const PHOTON_MAPPING: &str = Group::PhotonMapping.heading();
const PROGRESSIVE: &str = Group::Progressive.heading();

/// `photon render`: the flags of the command line itself, and every render setting
/// (`photon::settings::SETTINGS`) as a flag.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// Built-in scene name (see `photon scenes`) or scene file: .toml (docs/scene-format.md),
    /// .gltf or .glb. Settings given here override the file's [render] table [default: seed].
    scene: Option<String>,
    /// Output image [default: render.png]; the extension picks the format (.png, .exr, .pfm,
    /// or .npy for one NumPy array per channel: NAME_r.npy, NAME_g.npy, NAME_b.npy). With
    /// --sample-range or --pass-range, the partial render file (.part).
    #[arg(short, long, help_heading = OUTPUT)]
    output: Option<PathBuf>,
    /// Exposure in stops, applied to PNG output only.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, help_heading = OUTPUT)]
    exposure: f32,
    /// Write the .exr in CIE 1931 XYZ (channels X, Y, Z) instead of linear sRGB (R, G, B):
    /// the same light, a linear map of it, without the negative values that colours outside
    /// the sRGB gamut (a spectral render's rainbow) take in RGB.
    #[arg(long, help_heading = OUTPUT)]
    xyz: bool,
    /// Show the image in a running tev viewer at HOST:PORT (tev listens on 127.0.0.1:14158):
    /// after each pass of sppm and ppm (at most four times a second), and when the render
    /// ends.
    #[arg(long, value_name = "HOST:PORT", help_heading = OUTPUT)]
    tev: Option<String>,
    /// Show the render in Photon's viewer, a page on 127.0.0.1 (the URL, with its token, is
    /// printed): exposure, tone mapping, zoom, pixel read-out; pause and stop. It stays up
    /// after the render until Ctrl-C or the page's Close.
    #[arg(long, help_heading = OUTPUT)]
    view: bool,
    /// The viewer's port [default: any free port].
    #[arg(long, requires = "view", help_heading = OUTPUT)]
    view_port: Option<u16>,
    /// An image of the same size for the viewer to compare with: A/B flip, relative-error
    /// heat map, relMSE against time.
    #[arg(long, requires = "view", help_heading = OUTPUT)]
    reference: Option<PathBuf>,
    /// Extra images: any of direct, caustic, indirect (photon), albedo, normal (photon,
    /// direct, path), comma-separated; layers of the EXR output, or files NAME.AOV.EXT for
    /// other formats.
    #[arg(long, value_enum, value_delimiter = ',', help_heading = OUTPUT)]
    aov: Vec<Aov>,
    /// Worker threads [default: one per core]; the image does not depend on it.
    #[arg(long, help_heading = OUTPUT)]
    threads: Option<usize>,
    /// No progress bar.
    #[arg(short, long, help_heading = OUTPUT)]
    quiet: bool,
    #[command(flatten)]
    env: super::EnvironmentArgs,
    #[command(flatten)]
    settings: SettingFlags,
    /// Render from a saved photon map (`photon photons trace`) instead of tracing anew.
    #[arg(long, help_heading = PHOTON_MAPPING)]
    photon_map: Option<PathBuf>,
    /// Use --photon-map even if it was traced for another scene.
    #[arg(long, help_heading = PHOTON_MAPPING)]
    force: bool,
    /// Write the image after passes 1, 2, 4, 8, … (and at least every minute) as
    /// NAME.passNNNNN.EXT.
    #[arg(long, help_heading = PROGRESSIVE)]
    snapshots: bool,
    /// Checkpoint file, kept after the render finishes [default: the output with extension
    /// .checkpoint, removed when the render finishes].
    #[arg(long, help_heading = PROGRESSIVE)]
    checkpoint: Option<PathBuf>,
    /// Keep the checkpoint when the render finishes, to extend it later with --resume.
    #[arg(long, help_heading = PROGRESSIVE)]
    keep_checkpoint: bool,
    /// Continue a progressive render from its checkpoint (with --passes or --time to extend it).
    #[arg(long, help_heading = PROGRESSIVE)]
    resume: Option<PathBuf>,
}

impl RenderArgs {
    /// The library's options: what was given here; the library fills in the scene's
    /// `[render]` table and the defaults.
    /// The scene given, or the default one.
    fn scene(&self) -> &str {
        self.scene.as_deref().unwrap_or(DEFAULT_SCENE)
    }

    fn options(&self) -> RenderOptions {
        self.settings.0.clone()
    }

    fn color_space(&self) -> ColorSpace {
        if self.xyz {
            ColorSpace::Xyz
        } else {
            ColorSpace::LinearSrgb
        }
    }

    fn live(&self) -> LiveOutputs {
        LiveOutputs {
            tev: self.tev.clone(),
            view: self.view.then(|| self.view_port.unwrap_or(0)),
            reference: self.reference.clone(),
        }
    }

    fn write_as(&self) -> WriteAs {
        WriteAs {
            exposure: self.exposure,
            space: self.color_space(),
        }
    }
}

/// Checks of the flags only the command line has; the settings are the library's to check.
fn check_flags(a: &RenderArgs) -> Result<()> {
    if !(-MAX_EXPOSURE..=MAX_EXPOSURE).contains(&a.exposure) {
        bail!(
            "--exposure {} must be between -{MAX_EXPOSURE} and {MAX_EXPOSURE} stops",
            a.exposure
        );
    }
    Ok(())
}

pub fn run(a: RenderArgs) -> Result<()> {
    check_flags(&a)?;
    if let Some(cp) = &a.resume {
        let o = a.options();
        let settings = o
            .given()
            .into_iter()
            .filter(|(s, _)| !["passes", "time"].contains(&s.name))
            .map(|(s, _)| s.flag());
        let run_flags = [
            (a.scene.is_some(), "a scene (the checkpoint names its own)"),
            (a.snapshots, "--snapshots"),
            (a.checkpoint.is_some(), "--checkpoint"),
            (a.keep_checkpoint, "--keep-checkpoint"),
            (!a.aov.is_empty(), "--aov"),
            (a.photon_map.is_some(), "--photon-map"),
            (a.force, "--force"),
        ];
        let run_flags = run_flags
            .iter()
            .filter(|(given, _)| *given)
            .map(|(_, f)| (*f).to_owned());
        if let Some(flag) = settings.chain(run_flags).next() {
            bail!(
                "--resume goes on with the checkpoint's own settings: it takes --passes, --time, -o, --exposure, --xyz, --tev, --threads, -q and the environment flags, not {flag}"
            );
        }
        let pool = super::thread_pool(a.threads)?;
        let args = progressive::ResumeArgs {
            budget: progressive::Budget {
                passes: o.passes,
                seconds: o.time,
            },
            output: a.output.as_deref(),
            exposure: a.exposure,
            space: a.color_space(),
            live: &a.live(),
            quiet: a.quiet,
            env: &a.env,
        };
        return progressive::resume(cp, &args, &pool);
    }
    let (loaded, inputs) = photon::io::input::recording(|| super::scene_with(a.scene(), &a.env));
    let (scene, spec, load_seconds) = loaded?;
    let mut job = RenderJob::new(&scene, &spec, a.options())?;
    let kind = job.integrator();
    if kind != IntegratorKind::Photon && a.photon_map.is_some() {
        bail!("--photon-map is for --integrator photon");
    }
    let component_aovs = a
        .aov
        .iter()
        .any(|x| matches!(x, Aov::Direct | Aov::Caustic | Aov::Indirect));
    if component_aovs && kind != IntegratorKind::Photon {
        bail!("the direct, caustic and indirect AOVs need --integrator photon");
    }
    if kind.is_progressive() {
        if !a.aov.is_empty() {
            bail!(
                "--aov is for --integrator photon, direct or path (sppm and ppm keep no per-sample layers)"
            );
        }
        return run_progressive(&a, &scene, &job, &inputs);
    }
    let progressive_only = [
        (a.checkpoint.is_some(), "--checkpoint"),
        (a.keep_checkpoint, "--keep-checkpoint"),
        (a.snapshots, "--snapshots"),
    ];
    if let Some((_, flag)) = progressive_only.iter().find(|(given, _)| *given) {
        // Accepted and ignored, it let a user believe a checkpoint was being written.
        bail!("{flag} is for --integrator sppm or ppm");
    }
    let partial = job.options().sample_range.is_some();
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
        Some(a.write_as().check(&output)?)
    };
    let aovs: Vec<&str> = if format == Some(ImageFormat::Exr) {
        Vec::new()
    } else {
        a.aov.iter().map(|x| x.name()).collect()
    };
    refuse_inputs(&output, None, &aovs, false, &inputs)?;
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
    let mut live = Live::start(
        &a.live(),
        &output,
        super::progressive::interrupts().stop,
        || photon::film::Image::new(settings.width, settings.height),
    )?;
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
        None => job.write_part(&result, &output)?,
    }
    let layers = a
        .aov
        .iter()
        .map(|&x| (x.name().to_owned(), aov_layer(out, x).clone()))
        .collect();
    live.finish_with_layers(out.image.clone(), 0, layers);
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
    live.linger();
    Ok(())
}

fn run_progressive(
    a: &RenderArgs,
    scene: &Scene,
    job: &RenderJob,
    inputs: &[PathBuf],
) -> Result<()> {
    let partial = job.options().pass_range.is_some();
    let budget = job.budget();
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
        a.write_as().check(&output)?;
    }
    // A checkpoint named is asked for: it is kept.
    let keep_checkpoint = a.keep_checkpoint || a.checkpoint.is_some();
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
    if same(&checkpoint, std::path::Path::new(a.scene())) {
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
        keep_checkpoint,
        image: output,
        snapshots: a.snapshots,
        write_as: a.write_as(),
        live: a.live(),
        quiet: a.quiet,
        partial,
        env: progressive::env_settings(&a.env),
        target_passes: None,
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

/// The image of one AOV.
fn aov_layer(out: &RenderOutput, x: Aov) -> &photon::film::Image {
    match x {
        Aov::Direct => &out.aovs.direct,
        Aov::Caustic => &out.aovs.caustic,
        Aov::Indirect => &out.aovs.indirect,
        Aov::Albedo => &out.aovs.albedo,
        Aov::Normal => &out.aovs.normal,
    }
}

fn write_outputs(
    a: &RenderArgs,
    output: &std::path::Path,
    format: ImageFormat,
    out: &RenderOutput,
) -> Result<()> {
    let aov_image = |x: Aov| aov_layer(out, x);
    if format == ImageFormat::Exr && !a.aov.is_empty() {
        let mut layers = vec![("beauty", &out.image)];
        layers.extend(a.aov.iter().map(|&x| (x.name(), aov_image(x))));
        write_exr_layers(output, &layers, a.color_space())?;
        return Ok(());
    }
    write_image(&out.image, output, a.write_as())?;
    for &x in &a.aov {
        write_image(aov_image(x), &aov_path(output, x.name()), a.write_as())?;
    }
    Ok(())
}

/// A `photon render` command line on its own, as `photon job create` takes it.
#[derive(clap::Parser)]
#[command(name = "photon render", no_binary_name = true)]
struct RenderCommand {
    #[command(flatten)]
    args: RenderArgs,
}

/// Refuse the flags a job sets itself or cannot carry (the settings a job cannot take are
/// refused by the library's `job::plan`).
fn refuse_per_run_flags(a: &RenderArgs) -> Result<()> {
    let per_run = [
        (
            a.output.is_some(),
            "-o (the job folder holds the parts; `photon job merge` writes the image)",
        ),
        (a.checkpoint.is_some(), "--checkpoint"),
        (a.keep_checkpoint, "--keep-checkpoint"),
        (a.resume.is_some(), "--resume"),
        (a.snapshots, "--snapshots"),
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
    Ok(())
}

/// The scene, settings and environment of `SCENE [FLAGS...]`, as `photon job create` takes
/// them.
pub fn job_request(
    scene_and_flags: &[String],
) -> Result<(String, RenderOptions, photon::io::checkpoint::EnvSettings)> {
    use clap::Parser;
    let a = RenderCommand::try_parse_from(scene_and_flags)
        .map(|c| c.args)
        .map_err(|e| anyhow::anyhow!("{}", e.render().to_string().trim_end()))?;
    refuse_per_run_flags(&a)?;
    let options = a.options();
    Ok((a.scene().to_owned(), options, a.env.settings()))
}
