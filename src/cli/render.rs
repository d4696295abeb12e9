//! `photon render`.

use super::progress;
use anyhow::{Result, bail};
use clap::ValueEnum;
use photon::film::PixelFilter;
use photon::integrator::{DirectConfig, Integrator, PathConfig};
use photon::io::image::{check_writable, write_image};
use photon::render::{RenderSettings, render};
use photon::scene::builtin::{DEFAULT_SCENE, load};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Clone, Copy, ValueEnum)]
enum IntegratorName {
    /// Ray-traced direct light with mirror and glass recursion; no indirect diffuse light.
    Direct,
    /// Unidirectional path tracing with NEE and MIS: the reference.
    Path,
}

#[derive(clap::Args)]
pub struct RenderArgs {
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

pub fn run(a: RenderArgs) -> Result<()> {
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
    let pool = super::thread_pool(a.threads)?;
    let bar = progress::bar("rendering", a.quiet);
    let start = Instant::now();
    let out = pool.install(|| render(&scene, &integrator, &settings, &progress::callback(&bar)))?;
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
