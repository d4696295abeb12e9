//! `photon render --integrator sppm|ppm`: passes under a budget, snapshots, checkpoints,
//! resume, partial renders; and `photon merge`.

use super::live::{Live, LiveOutputs};
use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use photon::io::checkpoint::{self, EnvSettings, RunInfo};
use photon::io::image::{ColorSpace, WriteAs, write_image};
use photon::progressive::ProgressiveState;
use photon::scene::Scene;
use photon::session::{CHECKPOINT_EVERY, CheckpointPlan, Ending, Session, Totals};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

pub use photon::session::Budget;

/// What to write while and after rendering.
pub struct Outputs {
    pub image: PathBuf,
    pub checkpoint: PathBuf,
    /// Keep the checkpoint when the render finishes.
    pub keep_checkpoint: bool,
    pub snapshots: bool,
    /// The exposure of PNG output and the colour space of EXR output.
    pub write_as: WriteAs,
    /// Where the image is shown as passes land: tev, the viewer.
    pub live: LiveOutputs,
    pub quiet: bool,
    /// A partial render (`--pass-range`): the state file is the output, no image.
    pub partial: bool,
    /// The environment flags, which the checkpoint keeps for `--resume`.
    pub env: EnvSettings,
    /// The pass target the checkpoint keeps when the budget has none (a resumed run under a
    /// time budget keeps its run's).
    pub target_passes: Option<u64>,
}

/// The environment flags as a checkpoint keeps them: a sky file's path made absolute (so a
/// resume from another folder finds it), a colour as given.
pub fn env_settings(env: &super::EnvironmentArgs) -> EnvSettings {
    photon::description::environment::portable(&env.settings())
}

fn env_args(env: &EnvSettings) -> super::EnvironmentArgs {
    super::EnvironmentArgs {
        env: env.sky.clone(),
        env_rotate: env.rotate_deg,
        env_intensity: env.intensity,
    }
}

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

/// What Ctrl-C and `kill` (SIGINT, SIGTERM) asked for.
pub struct Interrupts {
    /// The first: finish the pass in flight, then save and stop.
    pub stop: Arc<AtomicBool>,
    /// Any later one: abandon the pass in flight, then save the completed passes and stop.
    /// (`timeout` and a terminal signal the process group too, so two often arrive at once.)
    pub abandon: Arc<AtomicBool>,
}

pub fn interrupts() -> Interrupts {
    let flags = Interrupts {
        stop: Arc::new(AtomicBool::new(false)),
        abandon: Arc::new(AtomicBool::new(false)),
    };
    let (stop, abandon) = (flags.stop.clone(), flags.abandon.clone());
    let _ = ctrlc::set_handler(move || {
        if stop.swap(true, Ordering::SeqCst) && !abandon.swap(true, Ordering::SeqCst) {
            eprintln!(
                "photon: interrupted again: abandoning the pass in flight; saving the completed ones"
            );
        }
    });
    flags
}

/// Run the session's passes until its budget is spent (or an interrupt), showing progress and
/// writing snapshots; then the image (or the partial render) and the report.
pub fn run(
    scene: &Scene,
    state: ProgressiveState,
    budget: Budget,
    out: &Outputs,
    pool: &rayon::ThreadPool,
) -> Result<()> {
    let info = RunInfo {
        output: Some(std::path::absolute(&out.image).unwrap_or_else(|_| out.image.clone())),
        target_passes: budget.passes.or(out.target_passes),
        exposure: Some(out.write_as.exposure),
        env: out.env.clone(),
    };
    let mut session = Session::new(state, budget)?;
    if !out.partial {
        session = session.with_checkpoints(CheckpointPlan {
            path: out.checkpoint.clone(),
            info: info.clone(),
            every: CHECKPOINT_EVERY,
            keep: out.keep_checkpoint,
        });
    }
    let signals = interrupts();
    let mut live = Live::start(&out.live, &out.image, signals.stop.clone(), || {
        session.state().image()
    })?;
    let bar = progress_bar(out.quiet, budget.passes);
    let ending = pool.install(|| {
        session.run(scene, &signals.stop, &signals.abandon, |s, _| {
            live.pass(|| s.state().image(), s.state().passes);
            let passes = s.state().next_pass();
            if budget.passes.is_none() {
                bar.set_length(passes + 1);
            }
            bar.set_position(passes);
            bar.set_message(format!("{:.1} M photons", s.totals().photons as f64 / 1e6));
            if out.snapshots && !out.partial && s.take_snapshot() {
                write_image(
                    &s.state().image(),
                    &snapshot_path(&out.image, passes),
                    out.write_as,
                )?;
            }
            Ok(())
        })
    })?;
    bar.finish_and_clear();
    let (totals, secs) = (*session.totals(), session.elapsed());
    if session.state().passes == 0 {
        eprintln!("photon: interrupted before the first pass completed; nothing was written");
        std::process::exit(130);
    }
    // No moment loses the passes: an interrupted run saves its checkpoint before the image; a
    // finished one removes its checkpoint only once the image is written.
    let write = |state: &ProgressiveState| -> Result<()> {
        if out.partial {
            checkpoint::save_with(state, &info, &out.image)?;
        } else {
            write_image(&state.image(), &out.image, out.write_as)?;
        }
        Ok(())
    };
    let state = if ending == Ending::Interrupted {
        let state = session.finish(ending)?;
        write(&state)?;
        state
    } else {
        write(session.state())?;
        session.finish(ending)?
    };
    if !out.partial {
        live.finish(state.image(), state.passes);
    }
    report(scene, &state, out, &totals, secs, ending)?;
    live.linger();
    Ok(())
}

fn progress_bar(quiet: bool, target: Option<u64>) -> ProgressBar {
    let bar = if quiet {
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
    bar
}

/// Report what the run did; an interrupted run then exits with 130.
fn report(
    scene: &Scene,
    state: &ProgressiveState,
    out: &Outputs,
    totals: &Totals,
    secs: f64,
    ending: Ending,
) -> Result<()> {
    let kept = ending == Ending::Interrupted || out.keep_checkpoint;
    // The vcm family traces light paths (one a pixel) where sppm and ppm trace photons.
    let vcm = state.config.method.vcm_mode().is_some();
    let traced = if vcm { "light paths" } else { "photons" };
    eprintln!(
        "photon: {} {}×{} {} passes {}..{} ({}) in {secs:.2} s: {:.2} M {traced}/s, {:.2} M rays/s → {}{}",
        scene.name,
        state.config.width,
        state.config.height,
        state.passes,
        state.first_pass,
        state.next_pass(),
        state.config.method.name(),
        totals.photons as f64 / secs / 1e6,
        totals.rays as f64 / secs / 1e6,
        out.image.display(),
        if out.partial || !kept {
            String::new()
        } else {
            format!(" (checkpoint {})", out.checkpoint.display())
        }
    );
    let split = &totals.seconds;
    if vcm {
        eprintln!(
            "photon: passes spent {:.2} s on camera paths (with their connections and merges), {:.2} s tracing light paths",
            split.camera, split.photons
        );
    } else {
        eprintln!(
            "photon: passes spent {:.2} s on camera paths, {:.2} s tracing photons, {:.2} s gathering",
            split.camera, split.photons, split.gather
        );
    }
    if ending == Ending::Interrupted {
        eprintln!(
            "photon: interrupted after pass {}; continue with: photon render --resume {}",
            state.next_pass(),
            out.checkpoint.display()
        );
        std::process::exit(130);
    }
    Ok(())
}

/// What `--resume` takes besides the checkpoint.
pub struct ResumeArgs<'a> {
    pub budget: Budget,
    pub output: Option<&'a Path>,
    pub exposure: f32,
    pub space: ColorSpace,
    pub live: &'a LiveOutputs,
    pub quiet: bool,
    /// Environment flags given again: they must be the run's.
    pub env: &'a super::EnvironmentArgs,
}

/// The environment flags of a run, as a command line would give them.
fn describe_env(env: &EnvSettings) -> String {
    let mut flags = Vec::new();
    if let Some(s) = &env.sky {
        flags.push(format!("--env {s}"));
    }
    if let Some(r) = env.rotate_deg {
        flags.push(format!("--env-rotate {r}"));
    }
    if let Some(i) = env.intensity {
        flags.push(format!("--env-intensity {i}"));
    }
    if flags.is_empty() {
        "no environment flags".into()
    } else {
        flags.join(" ")
    }
}

/// `photon render --resume FILE [--passes N] [--time S] [-o OUT]`: the scene is loaded with
/// the environment flags the checkpoint keeps.
pub fn resume(path: &Path, args: &ResumeArgs, pool: &rayon::ThreadPool) -> Result<()> {
    let ResumeArgs {
        budget,
        output,
        exposure,
        space,
        live,
        quiet,
        ..
    } = *args;
    let (session, info) = Session::resume(path, budget)?;
    let budget = session.budget();
    let state = session.into_state();
    let given = env_settings(args.env);
    if given != EnvSettings::default() && given != info.env {
        bail!(
            "'{}' was rendered with {}; --resume keeps its environment flags, so give the same or none",
            path.display(),
            describe_env(&info.env)
        );
    }
    let (loaded, files) =
        photon::io::input::recording(|| super::scene_with(&state.scene_name, &env_args(&info.env)));
    let (scene, _, _) = loaded?;
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
    let out = Outputs {
        image,
        checkpoint: path.to_path_buf(),
        // The user named it as this run's input: it stays.
        keep_checkpoint: true,
        snapshots: false,
        // An exposure given now wins; otherwise the run's own.
        write_as: WriteAs {
            exposure: if exposure != 0.0 {
                exposure
            } else {
                info.exposure.unwrap_or(0.0)
            },
            space,
        },
        live: live.clone(),
        quiet,
        partial: false,
        env: info.env,
        target_passes: info.target_passes,
    };
    out.write_as.check(&out.image)?;
    super::render::refuse_inputs(&out.image, Some(&out.checkpoint), &[], false, &files)?;
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
    write_image(&image, &a.output, WriteAs::default())?;
    eprintln!(
        "photon: merged {} parts ({} passes or samples per pixel) → {}",
        a.parts.len(),
        merger.units(),
        a.output.display()
    );
    Ok(())
}
