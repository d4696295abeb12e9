//! `photon job create | run | status | merge | submit`: a render split into tasks for Slurm
//! job arrays, GNU parallel or Kubernetes Indexed Jobs, merged bit for bit (see
//! `photon::job`).

use super::render::{plan_job, render_task};
use anyhow::{Context, Result, bail};
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
}

#[derive(clap::Args)]
pub struct MergeArgs {
    job: PathBuf,
    /// The merged image (.exr, .pfm, .png).
    #[arg(short, long)]
    output: PathBuf,
    /// Exposure in stops, applied to PNG output only.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
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
    #[arg(long, default_value_t = 1)]
    pub cpus: u32,
    /// Most tasks running at once (Slurm's array throttle `%N`, Kubernetes parallelism).
    #[arg(long)]
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
    let job_dir = &a.output;
    if job_dir.join(job::MANIFEST).exists()
        || std::fs::read_dir(job_dir).is_ok_and(|mut d| d.next().is_some())
    {
        bail!(
            "'{}' exists and is not empty; a job is written to a new folder",
            job_dir.display()
        );
    }
    let plan = plan_job(&a.render)?;
    let tasks = job::split(plan.total, a.tasks)?;
    std::fs::create_dir_all(job_dir.join(job::PARTS_DIR))
        .with_context(|| format!("cannot create '{}'", job_dir.display()))?;
    let scene_arg = &a.render[0];
    let builtin = photon::description::builtin::BUILTINS
        .iter()
        .any(|b| b.name == scene_arg);
    let (files, scene) = if builtin {
        (Vec::new(), scene_arg.clone())
    } else {
        job::copy_scene_files(job_dir, Path::new(scene_arg), &plan.files)?
    };
    let manifest = Manifest {
        photon_version: env!("CARGO_PKG_VERSION").into(),
        scene,
        scene_hash: format!("{:016x}", plan.scene.content_hash()),
        integrator: plan.integrator.into(),
        render_args: a.render[1..].to_vec(),
        unit: plan.unit,
        total: plan.total,
        tasks,
        files,
    };
    // The copy must be the same scene: a file named by an absolute path, or read from
    // outside what was copied, would not be.
    if !builtin {
        let (copy, _, _) = super::scene(&job_dir.join(&manifest.scene).to_string_lossy())?;
        if copy.content_hash() != plan.scene.content_hash() {
            bail!(
                "the copied scene differs from '{scene_arg}': does it name files by absolute path? Use paths relative to the scene file"
            );
        }
    }
    manifest.save(job_dir)?;
    let bytes: u64 = manifest.files.iter().map(|f| f.bytes).sum();
    eprintln!(
        "photon: job {}: {} {} {} in {} tasks of {}–{}; {} files ({:.1} MB) copied",
        job_dir.display(),
        manifest.integrator,
        manifest.total,
        unit_name(manifest.unit),
        manifest.tasks.len(),
        manifest
            .tasks
            .iter()
            .map(|t| t[1] - t[0])
            .min()
            .unwrap_or(0),
        manifest
            .tasks
            .iter()
            .map(|t| t[1] - t[0])
            .max()
            .unwrap_or(0),
        manifest.files.len(),
        bytes as f64 / 1e6
    );
    outln!(
        "run the tasks:\n  {}",
        local_command(job_dir, &(0..manifest.tasks.len()).collect::<Vec<_>>())
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

fn run_task(a: &RunArgs) -> Result<()> {
    let manifest = Manifest::load(&a.job)?;
    if manifest.photon_version != env!("CARGO_PKG_VERSION") {
        bail!(
            "the job was made by Photon {}; this is {}: run the same version on every machine",
            manifest.photon_version,
            env!("CARGO_PKG_VERSION")
        );
    }
    let task = match a.task {
        Some(t) => t,
        None => task_from_environment()?,
    };
    let Some(&[start, end]) = manifest.tasks.get(task) else {
        bail!(
            "task {task}: the job has tasks 0 to {}",
            manifest.tasks.len() - 1
        );
    };
    if job::part_is_complete(&a.job, &manifest, task) {
        eprintln!("photon: task {task} is already done");
        return Ok(());
    }
    let failed = job::failure_path(&a.job, task);
    let _ = std::fs::remove_file(&failed);
    let outcome = render_one(a, &manifest, task, (start, end));
    if let Err(e) = &outcome {
        let retry = e.chain().any(|c| {
            matches!(
                c.downcast_ref::<photon::Error>(),
                Some(photon::Error::Write { .. })
            )
        });
        let message = format!("{e:#}\n");
        let _ = photon::io::image::write_atomically(&failed, |tmp| {
            std::fs::write(tmp, &message).map_err(|source| photon::Error::Write {
                path: failed.clone(),
                source,
            })
        });
        if retry {
            eprintln!("error: task {task}: {e:#}");
            std::process::exit(EXIT_RETRY);
        }
    }
    outcome.with_context(|| format!("task {task}"))
}

fn render_one(a: &RunArgs, manifest: &Manifest, task: usize, range: (u64, u64)) -> Result<()> {
    manifest.verify_files(&a.job)?;
    let scene = if photon::description::builtin::BUILTINS
        .iter()
        .any(|b| b.name == manifest.scene)
    {
        manifest.scene.clone()
    } else {
        a.job.join(&manifest.scene).to_string_lossy().into_owned()
    };
    let mut scene_and_flags = vec![scene];
    scene_and_flags.extend(manifest.render_args.iter().cloned());
    let start = std::time::Instant::now();
    render_task(
        &scene_and_flags,
        manifest.unit,
        range,
        job::part_path(&a.job, task),
        a.threads,
    )?;
    eprintln!(
        "photon: task {task} ({} {}..{}) done in {:.2} s",
        unit_name(manifest.unit),
        range.0,
        range.1,
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// A shell command that runs `tasks` here, one after another.
fn local_command(job_dir: &Path, tasks: &[usize]) -> String {
    let list = tasks
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(" ");
    format!(
        "for i in {list}; do photon job run {} --task $i; done",
        job_dir.display()
    )
}

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
    let failed = pick(&|s| matches!(s, TaskState::Failed(_)));
    let missing = pick(&|s| *s == TaskState::Missing);
    let units: u64 = done
        .iter()
        .map(|&i| manifest.tasks[i][1] - manifest.tasks[i][0])
        .sum();
    outln!(
        "{} of {} tasks done ({units} of {} {}); {} failed, {} not run",
        done.len(),
        states.len(),
        manifest.total,
        unit_name(manifest.unit),
        failed.len(),
        missing.len()
    );
    for (i, s) in states.iter().enumerate() {
        if let TaskState::Failed(m) = s {
            outln!("task {i} failed: {}", m.lines().next().unwrap_or(""));
        }
    }
    let rerun: Vec<usize> = failed.iter().chain(&missing).copied().collect::<Vec<_>>();
    if rerun.is_empty() {
        outln!(
            "all parts present: photon job merge {} -o image.exr",
            a.job.display()
        );
        return Ok(());
    }
    let mut rerun = rerun;
    rerun.sort_unstable();
    let list = job::compact_list(&rerun);
    outln!("rerun the missing tasks ({list}):");
    outln!("  here:     {}", local_command(&a.job, &rerun));
    outln!(
        "  parallel: parallel photon job run {} --task {{}} ::: {}",
        a.job.display(),
        rerun
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(" ")
    );
    outln!(
        "  Slurm:    sbatch --array={list} {}",
        a.job.join(super::job_submit::TASK_SCRIPT).display()
    );
    Ok(())
}

fn merge(a: &MergeArgs) -> Result<()> {
    photon::io::image::check_writable(&a.output)?;
    let manifest = Manifest::load(&a.job)?;
    let mut merger = job::Merger::default();
    let mut missing = Vec::new();
    let start = std::time::Instant::now();
    for (i, &[start, end]) in manifest.tasks.iter().enumerate() {
        // Each part is read once: a missing, damaged or short part is a missing task.
        let path = job::part_path(&a.job, i);
        match path.is_file().then(|| job::load_part(&path)) {
            Some(Ok(part)) if part.range() == (start, end) => merger
                .add(part)
                .with_context(|| format!("merging task {i}"))?,
            _ => missing.push(i),
        }
    }
    let image = merger
        .image()
        .with_context(|| format!("no task of '{}' is done yet", a.job.display()))?;
    photon::io::image::write_image(&image, &a.output, a.exposure)?;
    let done = manifest.tasks.len() - missing.len();
    eprintln!(
        "photon: merged {done} of {} tasks in {:.2} s: the image holds {} of {} {} → {}",
        manifest.tasks.len(),
        start.elapsed().as_secs_f64(),
        merger.units(),
        manifest.total,
        unit_name(manifest.unit),
        a.output.display()
    );
    if !missing.is_empty() {
        eprintln!(
            "photon: missing tasks: {} (see photon job status {})",
            job::compact_list(&missing),
            a.job.display()
        );
        if a.require_all {
            std::process::exit(3);
        }
    }
    Ok(())
}
