//! `photon render --integrator sppm|ppm`: passes under a budget, snapshots, checkpoints,
//! resume, partial renders; and `photon merge`.

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use photon::io::checkpoint::{self, RunInfo};
use photon::io::image::write_image;
use photon::progressive::ProgressiveState;
use photon::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long a progressive render may go on.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    pub passes: Option<u64>,
    pub seconds: Option<f64>,
}

/// What to write while and after rendering.
pub struct Outputs {
    pub image: PathBuf,
    pub checkpoint: PathBuf,
    pub snapshots: bool,
    pub exposure: f32,
    pub quiet: bool,
    /// A partial render (`--pass-range`): the state file is the output, no image.
    pub partial: bool,
}

/// Snapshots at least this often (besides passes 1, 2, 4, 8, …), and checkpoints too.
const SNAPSHOT_EVERY: Duration = Duration::from_secs(60);
const CHECKPOINT_EVERY: Duration = Duration::from_secs(30);

/// `c.exr` → `c.checkpoint`.
pub fn default_checkpoint(output: &Path) -> PathBuf {
    output.with_extension("checkpoint")
}

fn snapshot_path(output: &Path, pass: u64) -> PathBuf {
    let stem = output
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    let ext = output
        .extension()
        .map_or_else(|| "exr".into(), |e| e.to_string_lossy().into_owned());
    output.with_file_name(format!("{stem}.pass{pass:05}.{ext}"))
}

fn interrupt_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    // Ctrl-C and `kill` (SIGTERM) finish the current pass, then save and stop. A second one
    // stops at once: the checkpoint written last (atomically) is kept as it was.
    let _ = ctrlc::set_handler(move || {
        if f.swap(true, Ordering::SeqCst) {
            eprintln!("photon: interrupted again: stopping now; the last checkpoint is kept");
            std::process::exit(130);
        }
    });
    flag
}

/// Run passes until the budget is spent (or an interrupt), writing snapshots, checkpoints and
/// the final image.
pub fn run(
    scene: &Scene,
    mut state: ProgressiveState,
    budget: Budget,
    out: &Outputs,
    pool: &rayon::ThreadPool,
) -> Result<()> {
    if budget.passes.is_none() && budget.seconds.is_none() {
        bail!("give --passes or --time for a progressive render");
    }
    let target = budget.passes;
    let stop = interrupt_flag();
    let bar = if out.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(target.unwrap_or(0))
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} pass {pos}/{len} [{bar:30}] {msg}  {elapsed_precise} elapsed, ETA {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let start = Instant::now();
    let (mut last_snapshot, mut last_checkpoint) = (start, start);
    let mut photons = 0u64;
    let mut rays = 0u64;
    let mut split = photon::progressive::PassSeconds::default();
    let info = RunInfo {
        output: Some(std::path::absolute(&out.image).unwrap_or_else(|_| out.image.clone())),
        target_passes: target,
        exposure: Some(out.exposure),
    };
    let done = |state: &ProgressiveState| {
        target.is_some_and(|t| state.next_pass() >= t)
            || budget
                .seconds
                .is_some_and(|s| start.elapsed().as_secs_f64() >= s)
    };
    let mut interrupted = false;
    // The first checkpoint comes after the first pass (then every CHECKPOINT_EVERY): a run
    // killed in its first 30 s left none.
    let mut checkpointed = false;
    while !done(&state) {
        if stop.load(Ordering::SeqCst) {
            interrupted = true;
            break;
        }
        let stats = pool.install(|| state.run_pass(scene))?;
        photons += stats.photons_emitted;
        rays += stats.rays.total();
        split.camera += stats.seconds.camera;
        split.photons += stats.seconds.photons;
        split.gather += stats.seconds.gather;
        let passes = state.next_pass();
        if target.is_none() {
            bar.set_length(passes + 1);
        }
        bar.set_position(passes);
        bar.set_message(format!("{:.1} M photons", photons as f64 / 1e6));
        if out.snapshots
            && !out.partial
            && (passes.is_power_of_two() || last_snapshot.elapsed() >= SNAPSHOT_EVERY)
        {
            write_image(
                &state.image(),
                &snapshot_path(&out.image, passes),
                out.exposure,
            )?;
            last_snapshot = Instant::now();
        }
        if !out.partial && (!checkpointed || last_checkpoint.elapsed() >= CHECKPOINT_EVERY) {
            checkpoint::save_with(&state, &info, &out.checkpoint)?;
            last_checkpoint = Instant::now();
            checkpointed = true;
        }
    }
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    if out.partial {
        checkpoint::save_with(&state, &info, &out.image)?;
    } else {
        checkpoint::save_with(&state, &info, &out.checkpoint)?;
        write_image(&state.image(), &out.image, out.exposure)?;
    }
    eprintln!(
        "photon: {} {}×{} {} passes {}..{} ({}) in {secs:.2} s: {:.2} M photons/s, {:.2} M rays/s → {}{}",
        scene.name,
        state.config.width,
        state.config.height,
        state.passes,
        state.first_pass,
        state.next_pass(),
        state.config.method.name(),
        photons as f64 / secs / 1e6,
        rays as f64 / secs / 1e6,
        out.image.display(),
        if out.partial {
            String::new()
        } else {
            format!(" (checkpoint {})", out.checkpoint.display())
        }
    );
    eprintln!(
        "photon: passes spent {:.2} s on camera paths, {:.2} s tracing photons, {:.2} s gathering",
        split.camera, split.photons, split.gather
    );
    if interrupted {
        eprintln!(
            "photon: interrupted after pass {}; continue with: photon render --resume {}",
            state.next_pass(),
            out.checkpoint.display()
        );
        std::process::exit(130);
    }
    Ok(())
}

/// `photon render --resume FILE [--passes N] [--time S] [-o OUT]`.
pub fn resume(
    path: &Path,
    budget: Budget,
    output: Option<&Path>,
    exposure: f32,
    quiet: bool,
    pool: &rayon::ThreadPool,
) -> Result<()> {
    let (state, info) = checkpoint::load_with(path)?;
    let (scene, _, _) = super::scene(&state.scene_name)?;
    if scene.content_hash() != state.scene_hash {
        bail!(
            "'{}' was written for a different version of scene '{}'; it cannot be continued",
            path.display(),
            state.scene_name
        );
    }
    let image = output
        .map(Path::to_path_buf)
        .or(info.output)
        .context("the checkpoint names no output image; give -o")?;
    let budget = Budget {
        passes: budget.passes.or(if budget.seconds.is_some() {
            None
        } else {
            info.target_passes
        }),
        seconds: budget.seconds,
    };
    let out = Outputs {
        image,
        checkpoint: path.to_path_buf(),
        snapshots: false,
        // An exposure given now wins; otherwise the run's own.
        exposure: if exposure != 0.0 {
            exposure
        } else {
            info.exposure.unwrap_or(0.0)
        },
        quiet,
        partial: false,
    };
    run(&scene, state, budget, &out, pool)
}

#[derive(clap::Args)]
pub struct MergeArgs {
    /// Partial renders: `--integrator ppm --pass-range a..b -o NAME.part`, or
    /// `--sample-range a..b -o NAME.part` (path, direct, photon).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The merged image (.exr, .pfm, .png).
    #[arg(short, long)]
    output: PathBuf,
}

/// `photon merge PART... -o OUT`: one part in memory at a time.
pub fn merge(a: &MergeArgs) -> Result<()> {
    photon::io::image::check_writable(&a.output)?;
    let mut merger = photon::job::Merger::default();
    for p in &a.parts {
        merger
            .add(photon::job::load_part(p)?)
            .with_context(|| format!("merging '{}'", p.display()))?;
    }
    let image = merger.image().context("nothing to merge")?;
    write_image(&image, &a.output, 0.0)?;
    eprintln!(
        "photon: merged {} parts ({} passes or samples per pixel) → {}",
        a.parts.len(),
        merger.units(),
        a.output.display()
    );
    Ok(())
}
