//! The `photon` command line: arguments, progress and messages over the library.

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use photon::compare::{Comparison, Crop, compare};
use photon::film::PixelFilter;
use photon::integrator::{DirectConfig, Integrator, PathConfig};
use photon::io::image::{check_writable, read_image, write_image};
use photon::render::{RenderSettings, render};
use photon::scene::builtin::{BUILTINS, DEFAULT_SCENE, load};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "photon",
    version,
    about = "Photon: a photon-mapping global-illumination renderer"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image (.png, .exr or .pfm, chosen by the extension).
    Render(RenderArgs),
    /// Print how far one image is from a reference: RMSE, relMSE and mean ratio per channel.
    Compare(CompareArgs),
    /// List the built-in scenes.
    Scenes,
}

#[derive(Clone, Copy, ValueEnum)]
enum IntegratorName {
    /// Ray-traced direct light with mirror and glass recursion; no indirect diffuse light.
    Direct,
    /// Unidirectional path tracing with NEE and MIS: the reference.
    Path,
}

#[derive(clap::Args)]
struct RenderArgs {
    /// Built-in scene name (see `photon scenes`).
    #[arg(default_value = DEFAULT_SCENE)]
    scene: String,
    /// Output image; the extension picks the format (.png, .exr, .pfm).
    #[arg(short, long, default_value = "render.png")]
    output: PathBuf,
    #[arg(long, value_enum, default_value = "direct")]
    integrator: IntegratorName,
    /// Samples per pixel [default: 16 for direct, 64 for path].
    #[arg(long)]
    spp: Option<u32>,
    /// Image width in pixels [default: the scene's].
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels [default: the scene's].
    #[arg(long)]
    height: Option<u32>,
    /// Seed of every random stream; the same seed gives the same image.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Worker threads [default: one per core]; the image does not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Maximum number of bounces [default: 16 for direct, 256 for path].
    #[arg(long)]
    max_depth: Option<u32>,
    /// Samples per area light at each diffuse hit (direct integrator).
    #[arg(long, default_value_t = 4)]
    light_samples: u32,
    /// Pixel filter: `box` or `gaussian:SIGMA` (SIGMA in pixels).
    #[arg(long, default_value = "box", value_parser = parse_filter)]
    filter: PixelFilter,
    /// Exposure in stops, applied to PNG output only.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(clap::Args)]
struct CompareArgs {
    /// The image to judge (.exr or .pfm).
    image: PathBuf,
    /// The reference (.exr or .pfm).
    reference: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Restrict to a rectangle: x0,y0,x1,y1 (pixels, end exclusive).
    #[arg(long, value_parser = parse_crop)]
    crop: Option<Crop>,
}

fn parse_filter(s: &str) -> Result<PixelFilter, String> {
    if s == "box" {
        return Ok(PixelFilter::Box);
    }
    let sigma = s
        .strip_prefix("gaussian:")
        .ok_or_else(|| format!("'{s}' is not a filter; expected 'box' or 'gaussian:SIGMA'"))?;
    let sigma: f32 = sigma.parse().map_err(|_| {
        format!("'{sigma}' is not a number; expected 'gaussian:SIGMA' such as 'gaussian:0.5'")
    })?;
    Ok(PixelFilter::Gaussian { sigma })
}

fn parse_crop(s: &str) -> Result<Crop, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|t| t.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not a crop; expected x0,y0,x1,y1"))?;
    match v.as_slice() {
        &[x0, y0, x1, y1] => Ok(Crop { x0, x1, y0, y1 }),
        _ => Err(format!(
            "'{s}' is not a crop; expected four numbers x0,y0,x1,y1"
        )),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => cmd_render(args),
        Command::Compare(args) => cmd_compare(&args),
        Command::Scenes => {
            for b in BUILTINS {
                println!("{:<14} {}", b.name, b.description);
            }
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn cmd_render(a: RenderArgs) -> Result<()> {
    let scene = load(&a.scene)?;
    check_writable(&a.output)?;
    let (default_w, default_h) = scene.default_resolution;
    let integrator = match a.integrator {
        IntegratorName::Direct => Integrator::Direct(DirectConfig {
            max_depth: a.max_depth.unwrap_or(DirectConfig::default().max_depth),
            light_samples: a.light_samples,
            ..DirectConfig::default()
        }),
        IntegratorName::Path => Integrator::Path(PathConfig {
            max_depth: a.max_depth.unwrap_or(PathConfig::default().max_depth),
            ..PathConfig::default()
        }),
    };
    if a.light_samples == 0 {
        bail!("--light-samples must be at least 1");
    }
    let settings = RenderSettings {
        width: a.width.unwrap_or(default_w),
        height: a.height.unwrap_or(default_h),
        spp: a.spp.unwrap_or(match a.integrator {
            IntegratorName::Direct => 16,
            IntegratorName::Path => 64,
        }),
        seed: a.seed,
        filter: a.filter,
    };
    settings.validate()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .context("cannot start worker threads")?;
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(0)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}%  {elapsed_precise} elapsed, ETA {eta}",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    let start = Instant::now();
    let out = pool.install(|| {
        render(&scene, &integrator, &settings, &|done, total| {
            bar.set_length(total);
            bar.set_position(done);
        })
    })?;
    let secs = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    write_image(&out.image, &a.output, a.exposure)?;
    let m = |x: u64| x as f64 / secs / 1e6;
    eprintln!(
        "photon: {} {}×{} {} spp ({}) in {:.2} s on {} threads: {:.2} M samples/s, {:.2} M rays/s (camera {:.2}, bounce {:.2}, shadow {:.2}) → {}",
        scene.name,
        settings.width,
        settings.height,
        settings.spp,
        integrator.name(),
        secs,
        pool.current_num_threads(),
        m(out.samples),
        m(out.rays.total()),
        m(out.rays.camera),
        m(out.rays.bounce),
        m(out.rays.shadow),
        a.output.display()
    );
    Ok(())
}

fn cmd_compare(a: &CompareArgs) -> Result<()> {
    let img = read_image(&a.image)?;
    let reference = read_image(&a.reference)?;
    if (img.width, img.height) != (reference.width, reference.height) {
        bail!(
            "the images differ in size: '{}' is {}×{}, '{}' is {}×{}",
            a.image.display(),
            img.width,
            img.height,
            a.reference.display(),
            reference.width,
            reference.height
        );
    }
    let Some(c) = compare(&img, &reference, a.crop) else {
        bail!(
            "the crop lies outside the {}×{} image",
            img.width,
            img.height
        );
    };
    if a.json {
        println!("{}", serde_json::to_string_pretty(&c)?);
    } else {
        print_comparison(&c);
    }
    Ok(())
}

fn print_comparison(c: &Comparison) {
    println!(
        "{:<8} {:>12} {:>12} {:>12}",
        "channel", "RMSE", "relMSE", "mean ratio"
    );
    for (name, e) in [
        ("red", &c.red),
        ("green", &c.green),
        ("blue", &c.blue),
        ("overall", &c.overall),
    ] {
        println!(
            "{name:<8} {:>12.6} {:>12.6} {:>12.6}",
            e.rmse, e.rel_mse, e.mean_ratio
        );
    }
}
