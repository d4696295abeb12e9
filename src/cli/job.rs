//! `photon job create | run | status | merge | submit`: a render split into tasks for Slurm
//! job arrays, GNU parallel or Kubernetes Indexed Jobs, merged bit for bit (see
//! `photon::job`).

use super::render::job_request;
use anyhow::{Context, Result, bail};
use photon::io::image::WriteAs;
use photon::job::{self, Manifest, TaskState};
use std::path::{Path, PathBuf};

/// Exit code of a task that may succeed if run again (EX_TEMPFAIL): a write failed, or the
/// worker was interrupted. Other failures (exit 2) will fail again the same way.
pub const EXIT_RETRY: i32 = 75;

#[derive(clap::Subcommand)]
pub enum JobCommand {
    /// Write a job folder: the scene with every file it reads, a manifest, and parts/.
    Create(CreateArgs),
    /// Render one task into JOB/parts/I.part (skipped if done).
    Run(RunArgs),
    /// List done, missing and failed tasks, with the commands that rerun the missing ones.
    Status(StatusArgs),
    /// Merge the parts present now into an image.
    Merge(MergeArgs),
    /// Submit the tasks to Slurm (an sbatch array and a merge job after it), or print a
    /// Kubernetes Indexed Job.
    Submit(SubmitArgs),
}

#[derive(clap::Args)]
pub struct CreateArgs {
    /// Number of tasks: the passes (ppm) or samples per pixel (path, direct, photon) are
    /// split into this many near-equal ranges.
    #[arg(long)]
    tasks: u64,
    /// The job folder to create (it must not exist, or be empty).
    #[arg(short, long)]
    output: PathBuf,
    /// The scene and `photon render` flags, as for `photon render`: SCENE --integrator ppm
    /// --passes 64 …
    #[arg(required = true, num_args = 1.., trailing_var_arg = true, allow_hyphen_values = true)]
    render: Vec<String>,
}

#[derive(clap::Args)]
pub struct RunArgs {
    job: PathBuf,
    /// The task (0-based) [default: from SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX, or
    /// PARALLEL_SEQ − 1].
    #[arg(long)]
    task: Option<usize>,
    /// Worker threads [default: one per core].
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(clap::Args)]
pub struct StatusArgs {
    job: PathBuf,
    /// Print only the failed and missing tasks' indices, one a line (for a pipe into a loop
    /// or GNU parallel).
    #[arg(long)]
    missing: bool,
}

#[derive(clap::Args)]
pub struct MergeArgs {
    job: PathBuf,
    /// The merged image (.exr, .pfm, .png).
    #[arg(short, long)]
    output: PathBuf,
    /// Exposure in stops, applied to PNG output only.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_exposure)]
    exposure: f32,
    /// Fail (exit 3) unless every task's part is present.
    #[arg(long)]
    require_all: bool,
}

#[derive(clap::Args)]
pub struct SubmitArgs {
    pub job: PathBuf,
    /// Submit to Slurm with sbatch.
    #[arg(long, conflicts_with = "k8s", required_unless_present = "k8s")]
    pub slurm: bool,
    /// Print a Kubernetes Indexed Job (JSON, which kubectl apply takes).
    #[arg(long)]
    pub k8s: bool,
    /// Slurm partition.
    #[arg(long)]
    pub partition: Option<String>,
    /// Slurm time limit per task (e.g. 1:00:00).
    #[arg(long)]
    pub time: Option<String>,
    /// CPUs per task (Slurm --cpus-per-task, Kubernetes CPU request).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=super::MAX_THREADS as i64))]
    pub cpus: u32,
    /// Most tasks running at once (Slurm's array throttle `%N`, Kubernetes parallelism).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_running: Option<u32>,
    /// Write the sbatch scripts and print the commands, but do not submit.
    #[arg(long)]
    pub dry_run: bool,
    /// The photon executable on the workers [default: this one].
    #[arg(long)]
    pub photon: Option<PathBuf>,
    /// Kubernetes: the container image with photon in its PATH.
    #[arg(long, default_value = "photon:latest")]
    pub image: String,
    /// Kubernetes: the PersistentVolumeClaim that holds the job folder.
    #[arg(long, default_value = "photon-jobs")]
    pub volume_claim: String,
}

fn parse_exposure(s: &str) -> Result<f32, String> {
    let max = super::render::MAX_EXPOSURE;
    s.trim()
        .parse::<f32>()
        .ok()
        .filter(|e| (-max..=max).contains(e))
        .ok_or_else(|| format!("'{s}': expected a number of stops between -{max} and {max}"))
}

pub fn run(command: JobCommand) -> Result<()> {
    match command {
        JobCommand::Create(a) => create(&a),
        JobCommand::Run(a) => run_task(&a),
        JobCommand::Status(a) => status(&a),
        JobCommand::Merge(a) => merge(&a),
        JobCommand::Submit(a) => super::job_submit::submit(&a),
    }
}

fn create(a: &CreateArgs) -> Result<()> {
    let (scene, settings, environment) = job_request(&a.render)?;
    let plan = job::plan(&scene, settings, environment)?;
    for w in &plan.warnings {
        eprintln!("warning: {w}");
    }
    let manifest = job::create(&a.output, &plan, a.tasks)?;
    let job_dir = &a.output;
    let sizes = manifest.tasks.iter().map(|t| t[1] - t[0]);
    let bytes: u64 = manifest.files.iter().map(|f| f.bytes).sum();
    eprintln!(
        "photon: job {}: {} {} {} in {} tasks of {}–{}; {} files ({:.1} MB) copied",
        job_dir.display(),
        plan.integrator.name(),
        manifest.total,
        unit_name(manifest.unit),
        manifest.tasks.len(),
        sizes.clone().min().unwrap_or(0),
        sizes.max().unwrap_or(0),
        manifest.files.len(),
        bytes as f64 / 1e6
    );
    outln!(
        "run the tasks:\n  for i in $(seq 0 {}); do photon job run {} --task \"$i\"; done",
        manifest.tasks.len() - 1,
        sh_quote_path(job_dir)
    );
    Ok(())
}

fn unit_name(unit: job::Unit) -> &'static str {
    match unit {
        job::Unit::Passes => "passes",
        job::Unit::Samples => "samples per pixel",
    }
}

/// The task index from the scheduler's environment, for `--task` not given.
fn task_from_environment() -> Result<usize> {
    for (var, offset) in [
        ("SLURM_ARRAY_TASK_ID", 0),
        ("JOB_COMPLETION_INDEX", 0),
        // GNU parallel numbers its jobs from 1.
        ("PARALLEL_SEQ", 1),
    ] {
        if let Ok(v) = std::env::var(var) {
            let n: usize = v
                .trim()
                .parse()
                .with_context(|| format!("{var}={v} is not a task number"))?;
            return n
                .checked_sub(offset)
                .with_context(|| format!("{var}={v}: numbering starts at {offset}"));
        }
    }
    bail!(
        "give --task I, or run under Slurm (SLURM_ARRAY_TASK_ID), Kubernetes (JOB_COMPLETION_INDEX) or GNU parallel (PARALLEL_SEQ)"
    )
}

/// Whether an error may pass if the task is run again: a write failed.
fn is_worth_a_retry(e: &photon::Error) -> bool {
    matches!(e, photon::Error::Write { .. })
}

fn run_task(a: &RunArgs) -> Result<()> {
    let task = match a.task {
        Some(t) => t,
        None => task_from_environment()?,
    };
    let pool = super::thread_pool(a.threads)?;
    // Ctrl-C or SIGTERM abandons the task (a rerun redoes it).
    let signals = super::progressive::interrupts();
    match pool.install(|| job::run_task(&a.job, task, &signals.stop)) {
        Ok(job::TaskOutcome::Rendered { seconds }) => {
            let manifest = Manifest::load(&a.job)?;
            let [start, end] = manifest.tasks[task];
            eprintln!(
                "photon: task {task} ({} {start}..{end}) done in {seconds:.2} s",
                unit_name(manifest.unit),
            );
        }
        Ok(job::TaskOutcome::AlreadyDone) => eprintln!("photon: task {task} is already done"),
        Ok(job::TaskOutcome::DoneByAnother) => {
            eprintln!("photon: task {task} was done meanwhile by another worker; its part is kept")
        }
        Ok(job::TaskOutcome::Busy { holder, lock }) => {
            eprintln!(
                "error: task {task} is being rendered by {holder} (it holds {}); run it again later",
                lock.display()
            );
            std::process::exit(EXIT_RETRY);
        }
        Err(photon::Error::Cancelled) => {
            eprintln!("photon: task {task} interrupted; run it again to redo it");
            std::process::exit(130);
        }
        Err(e) if is_worth_a_retry(&e) => {
            eprintln!("error: task {task}: {e}");
            std::process::exit(EXIT_RETRY);
        }
        Err(e) => {
            return Err(anyhow::Error::new(e).context(format!(
                "task {task} of '{}'",
                a.job.join(job::MANIFEST).display()
            )));
        }
    }
    Ok(())
}

/// `path` quoted for a POSIX shell.
fn sh_quote_path(path: &Path) -> String {
    super::job_submit::sh_quote(&path.to_string_lossy())
}

/// Most failed or running tasks `job status` lists one by one.
const LISTED: usize = 10;

fn status(a: &StatusArgs) -> Result<()> {
    let manifest = Manifest::load(&a.job)?;
    let states = job::task_states(&a.job, &manifest);
    let pick = |f: &dyn Fn(&TaskState) -> bool| -> Vec<usize> {
        states
            .iter()
            .enumerate()
            .filter(|(_, s)| f(s))
            .map(|(i, _)| i)
            .collect()
    };
    let done = pick(&|s| *s == TaskState::Done);
    let running = pick(&|s| matches!(s, TaskState::Running(_)));
    let rerun = pick(&|s| matches!(s, TaskState::Failed(_) | TaskState::Missing));
    if a.missing {
        for i in &rerun {
            outln!("{i}");
        }
        return Ok(());
    }
    let units: u64 = done
        .iter()
        .map(|&i| manifest.tasks[i][1] - manifest.tasks[i][0])
        .sum();
    let failed = states
        .iter()
        .filter(|s| matches!(s, TaskState::Failed(_)))
        .count();
    outln!(
        "{} of {} tasks done ({units} of {} {}); {failed} failed, {} running, {} not run",
        done.len(),
        states.len(),
        manifest.total,
        unit_name(manifest.unit),
        running.len(),
        rerun.len() - failed
    );
    let notes = states.iter().enumerate().filter_map(|(i, s)| match s {
        TaskState::Failed(m) => Some(format!(
            "task {i} failed: {}",
            m.lines().next().unwrap_or("")
        )),
        TaskState::Running(h) => Some(format!("task {i} is running on {h}")),
        _ => None,
    });
    for note in notes.take(LISTED) {
        outln!("{note}");
    }
    if failed + running.len() > LISTED {
        outln!("… and {} more", failed + running.len() - LISTED);
    }
    let job_dir = sh_quote_path(&a.job);
    if rerun.is_empty() {
        if running.is_empty() {
            outln!("all parts present: photon job merge {job_dir} -o image.exr");
        }
        return Ok(());
    }
    let list = rerun_list(&rerun);
    outln!("rerun the missing tasks ({list}):");
    outln!(
        "  here:     photon job status {job_dir} --missing | while read -r i; do photon job run {job_dir} --task \"$i\"; done"
    );
    outln!(
        "  parallel: photon job status {job_dir} --missing | parallel -q photon job run {job_dir} --task {{}}"
    );
    outln!(
        "  Slurm:    cd {job_dir} && sbatch --array={list} {}",
        super::job_submit::TASK_SCRIPT
    );
    Ok(())
}

/// Longest task list printed as it is; a longer one is given as its span (the tasks in it
/// that are done end at once).
const MAX_LIST: usize = 200;

/// `tasks` as a Slurm array list whose length does not grow with their number.
fn rerun_list(tasks: &[usize]) -> String {
    let list = job::compact_list(tasks);
    match (tasks.first(), tasks.last()) {
        (Some(first), Some(last)) if list.len() > MAX_LIST => format!("{first}-{last}"),
        _ => list,
    }
}

fn merge(a: &MergeArgs) -> Result<()> {
    photon::io::image::check_writable(&a.output)?;
    let manifest = Manifest::load(&a.job)?;
    let start = std::time::Instant::now();
    let merged = job::merge(&a.job)?;
    for e in merged.problems.iter().take(LISTED) {
        eprintln!("photon: {e}");
    }
    photon::io::image::write_image(&merged.image, &a.output, WriteAs::exposure(a.exposure))?;
    eprintln!(
        "photon: merged {} of {} tasks in {:.2} s: the image holds {} of {} {} → {}",
        merged.done,
        manifest.tasks.len(),
        start.elapsed().as_secs_f64(),
        merged.units,
        manifest.total,
        unit_name(manifest.unit),
        a.output.display()
    );
    if !merged.missing.is_empty() {
        eprintln!(
            "photon: missing tasks: {} (see photon job status {})",
            rerun_list(&merged.missing),
            sh_quote_path(&a.job)
        );
        if a.require_all {
            std::process::exit(3);
        }
    }
    Ok(())
}
