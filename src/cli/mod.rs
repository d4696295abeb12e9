//! Subcommands of the `photon` binary, one file each.

/// `println!` that ends the program quietly when the reader of standard output has gone
/// (`photon compare a.pfm b.pfm | head -1`): a closed pipe is the reader's choice, not an
/// error, and `println!` panics on it.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout().lock(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("error: writing to standard output: {e}");
            std::process::exit(2);
        }
    }};
}

mod bench;
mod compare;
mod job;
mod job_submit;
mod live;
mod model;
mod photons;
mod progress;
mod progressive;
mod render;
mod setting_flags;
mod validate;
mod view;
mod view_photons;

use anyhow::Result;
use clap::{Parser, Subcommand};
use photon::description::builtin::BUILTINS;
use photon::io::checkpoint::EnvSettings;
use photon::scene::Scene;
use photon::settings::RenderOptions;
pub use setting_flags::describe as describe_setting_error;

#[derive(Parser)]
#[command(
    name = "photon",
    version,
    about = "Photon: a photon-mapping global-illumination renderer"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image (.png, .exr or .pfm, chosen by the extension).
    Render(Box<render::RenderArgs>),
    /// Print how far one image is from a reference: RMSE, relMSE and mean ratio per channel.
    Compare(compare::CompareArgs),
    /// Show an image (.exr, .pfm, .png) in Photon's viewer, a page on 127.0.0.1: exposure,
    /// tone mapping, zoom, pixel read-out, and with --reference an A/B flip and error map.
    View(view::ViewArgs),
    /// Photon maps: trace and save them, describe a saved file, export it as a PLY point cloud.
    Photons {
        #[command(subcommand)]
        command: photons::PhotonsCommand,
    },
    /// Merge partial progressive renders (`--integrator ppm --pass-range a..b`) into one image.
    Merge(progressive::MergeArgs),
    /// Render jobs for clusters: a job folder split into tasks (Slurm arrays, GNU parallel,
    /// Kubernetes Indexed Jobs), merged bit for bit as the parts arrive.
    Job {
        #[command(subcommand)]
        command: job::JobCommand,
    },
    /// Write a procedural model (the plant pot) as OBJ or PLY.
    Model(model::ModelArgs),
    /// List the built-in scenes, or write one (or any scene file) as a TOML scene.
    Scenes(ScenesArgs),
    /// The standard benchmark: error against time for each integrator on `cornell` and `seed`
    /// (budgets 1, 4, 12, 40 s), and rays/s, photons/s and queries/s, as JSON and an SVG plot.
    Bench(bench::BenchArgs),
    /// Render the validation scenes with every integrator and compare them with their
    /// references: time, relMSE, mean ratios and the worst region, as a table.
    Validate(validate::ValidateArgs),
}

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(*args),
        Command::Compare(args) => compare::run(&args),
        Command::View(args) => view::view(&args),
        Command::Photons { command } => photons::run(command),
        Command::Model(args) => model::run(&args),
        Command::Merge(args) => progressive::merge(&args),
        Command::Job { command } => job::run(command),
        Command::Scenes(args) => scenes(&args),
        Command::Validate(args) => validate::run_suite(&args),
        Command::Bench(args) => bench::run(&args),
    }
}

/// Worker pool with `threads` threads (0 or `None`: one per core).
/// Most worker threads `--threads` may ask for: beyond the cores nothing is gained, and
/// starting ten thousand threads for a small image took minutes.
pub const MAX_THREADS: usize = 256;

pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    use anyhow::Context;
    if let Some(n) = threads
        && n > MAX_THREADS
    {
        anyhow::bail!("--threads {n}: at most {MAX_THREADS} (the image is the same for any count)");
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .context("cannot start worker threads")
}

#[derive(clap::Args)]
pub struct ScenesArgs {
    /// Write this scene (a built-in name or a scene file) as a .toml scene file.
    #[arg(long, value_name = "SCENE", requires = "output")]
    export: Option<String>,
    /// The .toml file to write with --export.
    #[arg(short, long)]
    output: Option<std::path::PathBuf>,
}

fn scenes(a: &ScenesArgs) -> Result<()> {
    let (Some(name), Some(out)) = (&a.export, &a.output) else {
        for b in BUILTINS {
            outln!("{:<14} {}", b.name, b.description);
        }
        outln!("\nor a scene file: SCENE.toml (docs/scene-format.md), SCENE.gltf or SCENE.glb");
        return Ok(());
    };
    if out.extension().and_then(|e| e.to_str()) != Some("toml") {
        anyhow::bail!("'{}': --export writes a .toml file", out.display());
    }
    if std::path::Path::new(name).is_file()
        && std::path::absolute(name).ok() == std::path::absolute(out).ok()
    {
        anyhow::bail!(
            "'{}': --export would write over the scene it reads (and drop its comments); give another -o",
            out.display()
        );
    }
    let loaded = photon::description::load(name)?;
    print_warnings(&loaded.warnings);
    let dir = out.parent().filter(|d| !d.as_os_str().is_empty());
    let dir = std::path::absolute(dir.unwrap_or(std::path::Path::new(".")))?;
    let mut desc = loaded.desc;
    desc.base_dir = if desc.base_dir.as_os_str().is_empty() {
        // Built-ins name no files; a scene file's names are relative to its directory.
        dir.clone()
    } else {
        std::path::absolute(&desc.base_dir)?
    };
    let text = photon::description::toml_write::to_toml(&desc, &dir)?;
    photon::io::atomic::write_file(out, &text)?;
    eprintln!("photon: wrote scene '{}' to {}", desc.name, out.display());
    Ok(())
}

/// `--env FILE|R,G,B`, `--env-rotate DEG`, `--env-intensity S`.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct EnvironmentArgs {
    /// Light the scene with a sky: an equirectangular image (.exr, .hdr, .pfm) or a uniform
    /// radiance R,G,B (or one number); replaces the scene's own environment light.
    #[arg(
        long,
        value_name = "FILE|R,G,B",
        allow_hyphen_values = true,
        help_heading = render::OUTPUT
    )]
    pub env: Option<String>,
    /// Turn the sky about +y by this many degrees (the scene's own sky without --env).
    #[arg(
        long,
        value_name = "DEG",
        allow_hyphen_values = true,
        help_heading = render::OUTPUT
    )]
    pub env_rotate: Option<f32>,
    /// Multiply the sky's radiance (the scene's own sky without --env).
    #[arg(
        long,
        value_name = "S",
        allow_hyphen_values = true,
        help_heading = render::OUTPUT
    )]
    pub env_intensity: Option<f32>,
}

impl EnvironmentArgs {
    /// The flags as the library's environment settings.
    pub fn settings(&self) -> EnvSettings {
        EnvSettings {
            sky: self.env.clone(),
            rotate_deg: self.env_rotate,
            intensity: self.env_intensity,
        }
    }
}

fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Load a scene by built-in name or file, printing what the loader could not map. Also
/// returns the seconds it took (reading files, building the BVH).
pub fn scene(name_or_path: &str) -> Result<(Scene, RenderOptions, f64)> {
    scene_with(name_or_path, &EnvironmentArgs::default())
}

/// [`scene`] with the environment light the command line gives or changes.
pub fn scene_with(
    name_or_path: &str,
    env: &EnvironmentArgs,
) -> Result<(Scene, RenderOptions, f64)> {
    let start = std::time::Instant::now();
    let (scene, loaded) =
        photon::description::load_scene_with_environment(name_or_path, &env.settings())?;
    print_warnings(&loaded.warnings);
    Ok((scene, loaded.desc.render, start.elapsed().as_secs_f64()))
}
