//! A job made, run and merged from the library: what `photon job create | run | merge` and
//! the Python module's `job_create`, `job_run` and `job_merge` call. A worker's task is
//! rendered by [`RenderJob`] from the manifest's typed settings, with its range set.

use super::lock::{Acquired, TaskLock};
use super::{Manifest, Merger, Unit};
use crate::description::{builtin::BUILTINS, environment, load_scene_with_environment};
use crate::error::{Error, Result, SettingError};
use crate::film::Image;
use crate::io::checkpoint::EnvSettings;
use crate::render_job::RenderJob;
use crate::scene::Scene;
use crate::settings::{IntegratorKind, RenderOptions, Span, defaults};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// A render checked and ready to be split: what [`create`] writes.
pub struct JobPlan {
    /// The scene as given: a built-in's name or a file's path.
    pub scene_arg: String,
    pub scene: Scene,
    /// Every file the scene read, absolute.
    pub files: Vec<PathBuf>,
    /// The settings given (each task sets its range).
    pub settings: RenderOptions,
    pub environment: EnvSettings,
    pub integrator: IntegratorKind,
    pub unit: Unit,
    /// Passes (ppm) or samples per pixel to split.
    pub total: u64,
    /// What the scene's loader could not map.
    pub warnings: Vec<String>,
}

fn refuse(name: &'static str, value: Option<String>, problem: &str) -> Error {
    Error::Setting(SettingError {
        name,
        value,
        problem: problem.into(),
    })
}

/// Check that `scene` (a built-in's name or a file) with `settings` and `environment`
/// renders and can be split into tasks, and load it, recording the files it reads.
pub fn plan(scene: &str, settings: RenderOptions, environment: EnvSettings) -> Result<JobPlan> {
    super::what_a_job_cannot_carry(&settings, &environment).map_err(Error::Setting)?;
    let environment = environment::portable(&environment);
    let (loaded, files) =
        crate::io::input::recording(|| load_scene_with_environment(scene, &environment));
    let (built, loaded) = loaded?;
    let scene_settings = &loaded.desc.render;
    let integrator = settings
        .integrator
        .or(scene_settings.integrator)
        .unwrap_or(defaults::INTEGRATOR);
    if integrator.has_independent_passes() && settings.passes.or(scene_settings.passes).is_none() {
        return Err(refuse(
            "passes",
            None,
            &format!(
                "a {} job splits its passes into tasks: give passes",
                integrator.name()
            ),
        ));
    }
    if integrator == IntegratorKind::Sppm {
        return Err(refuse(
            "integrator",
            Some("sppm".into()),
            "sppm cannot be split into tasks: each pass shrinks the radii the last one left, so passes depend on each other; use ppm, whose passes are independent",
        ));
    }
    // The whole render must be valid before it is split.
    let job = RenderJob::new(&built, scene_settings, settings.clone())?;
    let (unit, total) = match job.options().passes {
        Some(passes) if integrator.has_independent_passes() => (Unit::Passes, passes),
        _ => (Unit::Samples, u64::from(job.settings().spp)),
    };
    Ok(JobPlan {
        scene_arg: scene.to_owned(),
        scene: built,
        files,
        settings,
        environment,
        integrator,
        unit,
        total,
        warnings: loaded.warnings,
    })
}

fn is_builtin(scene: &str) -> bool {
    BUILTINS.iter().any(|b| b.name == scene)
}

/// Write the job folder `job_dir` (new, or empty) for `plan` split into `tasks` tasks: the
/// scene with every file it reads, the manifest and `parts/`.
pub fn create(job_dir: &Path, plan: &JobPlan, tasks: u64) -> Result<Manifest> {
    if job_dir.join(super::MANIFEST).exists()
        || std::fs::read_dir(job_dir).is_ok_and(|mut d| d.next().is_some())
    {
        return Err(Error::InvalidSetting(format!(
            "'{}' exists and is not empty; a job is written to a new folder",
            job_dir.display()
        )));
    }
    let ranges = super::split(plan.total, tasks)?;
    let parts = job_dir.join(super::PARTS_DIR);
    std::fs::create_dir_all(&parts).map_err(|source| Error::Write {
        path: parts.clone(),
        source,
    })?;
    let builtin = is_builtin(&plan.scene_arg);
    let (files, scene) = if builtin {
        (Vec::new(), plan.scene_arg.clone())
    } else {
        super::copy_scene_files(job_dir, Path::new(&plan.scene_arg), &plan.files)?
    };
    let manifest = Manifest {
        photon_version: env!("CARGO_PKG_VERSION").into(),
        scene,
        scene_hash: format!("{:016x}", plan.scene.content_hash()),
        settings: plan.settings.clone(),
        environment: plan.environment.clone(),
        unit: plan.unit,
        total: plan.total,
        tasks: ranges,
        files,
    };
    // The copy must be the same scene: a file named by an absolute path, or read from
    // outside what was copied, would not be.
    if !builtin {
        let copy = job_dir.join(&manifest.scene);
        let (copy, _) = load_scene_with_environment(&copy.to_string_lossy(), &plan.environment)?;
        if copy.content_hash() != plan.scene.content_hash() {
            return Err(Error::InvalidScene(format!(
                "the copied scene differs from '{}': does it name files by absolute path? Use paths relative to the scene file",
                plan.scene_arg
            )));
        }
    }
    manifest.save(job_dir)?;
    Ok(manifest)
}

/// What running a task came to.
#[derive(Clone, Debug, PartialEq)]
pub enum TaskOutcome {
    /// Rendered and its part written, in this many seconds.
    Rendered { seconds: f64 },
    /// Its part was complete before this worker began.
    AlreadyDone,
    /// Another worker finished it while this one rendered; that part is kept.
    DoneByAnother,
    /// Another live worker holds its lock: try again later.
    Busy { holder: String, lock: PathBuf },
}

/// Leave `message` in the task's `I.failed` for `job status`.
fn record_failure(failed: &Path, message: &str) {
    let _ = crate::io::atomic::write_file(failed, format!("{message}\n"));
}

/// Render task `task` of the job in `job_dir` into `parts/I.part`, unless it is done or
/// being done; call it inside a rayon pool to choose the threads. A failure is also left in
/// `parts/I.failed`.
pub fn run_task(job_dir: &Path, task: usize, cancel: &AtomicBool) -> Result<TaskOutcome> {
    let manifest = Manifest::load(job_dir)?;
    let Some(&[start, end]) = manifest.tasks.get(task) else {
        return Err(Error::InvalidSetting(format!(
            "task {task}: the job has tasks 0 to {}",
            manifest.tasks.len() - 1
        )));
    };
    // A copy of the job (rsync, git) may have dropped the empty parts/ folder.
    let parts = job_dir.join(super::PARTS_DIR);
    if !parts.is_dir() {
        std::fs::create_dir(&parts).map_err(|source| Error::Write {
            path: parts.clone(),
            source,
        })?;
    }
    let failed = super::failure_path(job_dir, task);
    if manifest.photon_version != env!("CARGO_PKG_VERSION") {
        let message = format!(
            "the job was made by Photon {}; this is {}: run the same version on every machine",
            manifest.photon_version,
            env!("CARGO_PKG_VERSION")
        );
        record_failure(&failed, &message);
        return Err(Error::InvalidSetting(message));
    }
    if super::part_is_complete(job_dir, &manifest, task) {
        return Ok(TaskOutcome::AlreadyDone);
    }
    let lock = match TaskLock::acquire(job_dir, task)? {
        Acquired::Held(lock) => lock,
        Acquired::Busy(holder) => {
            return Ok(TaskOutcome::Busy {
                holder: holder.to_string(),
                lock: super::lock::lock_path(job_dir, task),
            });
        }
    };
    if super::part_is_complete(job_dir, &manifest, task) {
        return Ok(TaskOutcome::AlreadyDone);
    }
    let _ = std::fs::remove_file(&failed);
    let began = Instant::now();
    let rendered = super::lock::worker_part_path(job_dir, task, lock.holder());
    let outcome = render_part(job_dir, &manifest, (start, end), &rendered, cancel)
        .and_then(|()| super::promote_part(job_dir, &manifest, task, &rendered));
    let _ = std::fs::remove_file(&rendered);
    drop(lock);
    match outcome {
        Ok(true) => Ok(TaskOutcome::Rendered {
            seconds: began.elapsed().as_secs_f64(),
        }),
        Ok(false) => Ok(TaskOutcome::DoneByAnother),
        Err(e) => {
            record_failure(&failed, &e.to_string());
            Err(e)
        }
    }
}

/// Render the job's scene and settings restricted to `range` into the part file `output`.
fn render_part(
    job_dir: &Path,
    manifest: &Manifest,
    range: (u64, u64),
    output: &Path,
    cancel: &AtomicBool,
) -> Result<()> {
    manifest.verify_files(job_dir)?;
    let scene = if is_builtin(&manifest.scene) {
        manifest.scene.clone()
    } else {
        job_dir.join(&manifest.scene).to_string_lossy().into_owned()
    };
    let (scene, loaded) = load_scene_with_environment(&scene, &manifest.environment)?;
    let mut settings = manifest.settings.clone();
    let span = Some(Span::from(range));
    match manifest.unit {
        Unit::Passes => settings.pass_range = span,
        Unit::Samples => settings.sample_range = span,
    }
    let job = RenderJob::new(&scene, &loaded.desc.render, settings)?;
    let result = job.render(&|_| {}, cancel)?;
    if result.cancelled {
        return Err(Error::Cancelled);
    }
    job.write_part(&result, output)
}

/// The merge of the parts a job holds now.
pub struct Merged {
    pub image: Image,
    /// Tasks whose parts were merged.
    pub done: usize,
    /// Passes or samples per pixel the image holds.
    pub units: u64,
    /// Tasks without a usable part.
    pub missing: Vec<usize>,
    /// Why a part present was not used (damaged, short, another job's).
    pub problems: Vec<String>,
}

/// Merge the parts present in `job_dir`, one in memory at a time.
pub fn merge(job_dir: &Path) -> Result<Merged> {
    let manifest = Manifest::load(job_dir)?;
    let job_id = manifest.job_id();
    let mut merger = Merger::default();
    let (mut missing, mut problems) = (Vec::new(), Vec::new());
    for i in 0..manifest.tasks.len() {
        // Each part is read once: a missing, damaged, short or foreign part is a missing task.
        if !super::part_path(job_dir, i).is_file() {
            missing.push(i);
            continue;
        }
        match super::load_job_part(job_dir, &manifest, &job_id, i) {
            Ok(part) => merger.add(part)?,
            Err(e) => {
                problems.push(e.to_string());
                missing.push(i);
            }
        }
    }
    let image = merger.image().ok_or_else(|| {
        let why = problems
            .iter()
            .take(3)
            .cloned()
            .collect::<Vec<_>>()
            .join("; ");
        Error::InvalidSetting(format!(
            "no task of '{}' is done yet{}",
            job_dir.display(),
            if why.is_empty() {
                why
            } else {
                format!(" ({why})")
            }
        ))
    })?;
    Ok(Merged {
        image,
        done: manifest.tasks.len() - missing.len(),
        units: merger.units(),
        missing,
        problems,
    })
}
