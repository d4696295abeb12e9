//! Render jobs split into tasks for machines that share nothing but a folder: a job folder
//! holds the scene with every file it reads (content-hashed), a manifest of the settings and
//! of each task's range of passes (ppm) or samples (path, direct, photon), and a `parts/`
//! folder where each task's worker writes `I.part`. Parts add exactly in any order, so the
//! merged image of all parts is the image one machine would render, bit for bit.
//!
//! The schedulers (Slurm job arrays, GNU parallel, Kubernetes Indexed Jobs) run the workers;
//! this module only describes the work and checks and merges what the workers wrote.

pub mod lock;
mod merge;
pub mod part_file;
mod work;

pub use merge::{Merger, Part, decode_part, load_part};
pub use work::{JobPlan, Merged, TaskOutcome, create, merge, plan, run_task};

use crate::error::{Error, Result, SettingError};
use crate::hash::fnv1a;
use crate::io::checkpoint::EnvSettings;
use crate::settings::RenderOptions;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The manifest's file name in a job folder.
pub const MANIFEST: &str = "job.toml";
/// The folder of the scene and its files in a job folder.
pub const SCENE_DIR: &str = "scene";
/// The folder of the parts in a job folder.
pub const PARTS_DIR: &str = "parts";
/// Most tasks a job may have (a Slurm array's usual `MaxArraySize` is far below).
pub const MAX_TASKS: u64 = 1_000_000;
/// Most passes or samples per pixel a job may render: `--spp`'s limit (a 32-bit count),
/// which bounds `--passes` of a job too.
pub const MAX_TOTAL: u64 = u32::MAX as u64;

/// What a task's range counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Unit {
    /// PPM passes (`--pass-range`).
    Passes,
    /// Samples per pixel (`--sample-range`).
    Samples,
}

/// A file of the job's scene, with its size and content hash, relative to the job folder.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobFile {
    pub path: String,
    pub bytes: u64,
    /// FNV-1a 64 of the content, hexadecimal.
    pub fnv64: String,
}

/// `job.toml`: everything a worker needs besides the scene's files.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// The Photon version that made the job; workers must run the same.
    pub photon_version: String,
    /// The scene: a path relative to the job folder, or a built-in scene's name.
    pub scene: String,
    /// The scene's content hash (hexadecimal), checked by every worker after loading it.
    pub scene_hash: String,
    /// Every render setting given when the job was made (a task's range is set by the
    /// worker); the scene's `[render]` table and the defaults fill in the rest, as for any
    /// render.
    pub settings: RenderOptions,
    /// The environment light given or changed when the job was made.
    #[serde(default)]
    pub environment: EnvSettings,
    pub unit: Unit,
    /// Passes or samples per pixel of the whole render.
    pub total: u64,
    /// Each task's range `[start, end)` of passes or samples.
    pub tasks: Vec<[u64; 2]>,
    pub files: Vec<JobFile>,
}

impl Manifest {
    /// Read `JOB/job.toml`.
    pub fn load(job: &Path) -> Result<Self> {
        let path = job.join(MANIFEST);
        let text = crate::io::input::read_text(&path)?;
        Self::parse(&text, &path)
    }

    /// A manifest from the text of the file at `path` (named in errors), checked as untrusted
    /// input: every path in it stays inside the job's `scene/` folder, the tasks cover the
    /// total in order, and the total is within [`MAX_TOTAL`].
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let manifest: Manifest = toml::from_str(text).map_err(|e| {
            Error::SceneFile(Box::new(crate::description::source::Diagnostic::at_span(
                path,
                text,
                e.span().unwrap_or(0..0),
                format!("not a job manifest: {}", e.message()),
            )))
        })?;
        manifest.check().map_err(|m| {
            Error::SceneFile(Box::new(
                crate::description::source::Diagnostic::whole_file(path, m),
            ))
        })?;
        Ok(manifest)
    }

    fn check(&self) -> std::result::Result<(), String> {
        if !is_hex64(&self.scene_hash) {
            return Err(format!(
                "scene_hash '{}': expected 16 hexadecimal digits",
                self.scene_hash
            ));
        }
        self.check_tasks()?;
        self.settings
            .check_values()
            .map_err(|e| format!("settings: {e}"))?;
        what_a_job_cannot_carry(&self.settings, &self.environment)
            .map_err(|e| format!("settings: {e}"))?;
        let mut seen = std::collections::HashSet::new();
        for f in &self.files {
            if !is_scene_file_path(&f.path) {
                return Err(format!(
                    "files: path '{}' is not inside the job's '{SCENE_DIR}/' folder (expected a relative path such as '{SCENE_DIR}/meshes/cube.obj', without '..')",
                    f.path.escape_debug()
                ));
            }
            if !is_hex64(&f.fnv64) {
                return Err(format!(
                    "files: '{}' has fnv64 '{}': expected 16 hexadecimal digits",
                    f.path, f.fnv64
                ));
            }
            if !seen.insert(f.path.as_str()) {
                return Err(format!("files: '{}' is listed twice", f.path));
            }
        }
        let builtin = crate::description::builtin::BUILTINS
            .iter()
            .any(|b| b.name == self.scene);
        if !builtin && !is_scene_file_path(&self.scene) {
            return Err(format!(
                "scene '{}' is not inside the job's '{SCENE_DIR}/' folder (expected a built-in scene's name, or a relative path such as '{SCENE_DIR}/scene.toml', without '..')",
                self.scene.escape_debug()
            ));
        }
        if !builtin && !self.files.iter().any(|f| f.path == self.scene) {
            return Err(format!(
                "scene '{}' is neither a built-in scene nor one of the job's files (expected a path under '{SCENE_DIR}/' listed in [[files]])",
                self.scene.escape_debug()
            ));
        }
        Ok(())
    }

    fn check_tasks(&self) -> std::result::Result<(), String> {
        if self.total == 0 || self.total > MAX_TOTAL {
            return Err(format!(
                "total {}: a job renders 1 to {MAX_TOTAL} passes or samples per pixel",
                self.total
            ));
        }
        if self.tasks.is_empty() || self.tasks.len() as u64 > MAX_TASKS {
            return Err(format!(
                "{} tasks; a job has 1 to {MAX_TASKS}",
                self.tasks.len()
            ));
        }
        let mut next = 0;
        for (i, &[start, end]) in self.tasks.iter().enumerate() {
            if start != next || end <= start || end > self.total {
                return Err(format!(
                    "task {i} covers {start}..{end}; the tasks must cover 0..{} (the total) in order",
                    self.total
                ));
            }
            next = end;
        }
        if next != self.total {
            return Err(format!("the tasks end at {next}, not at {}", self.total));
        }
        Ok(())
    }

    /// The job's identity: a hash of everything that decides what its parts hold (version,
    /// scene, files, settings, tasks). Two jobs with the same identity render the same parts.
    pub fn job_id(&self) -> String {
        let text = toml::to_string(self).expect("a manifest is plain data");
        fnv64_hex(text.as_bytes())
    }

    /// Why a part labelled `label` is not task `task`'s of this job, if it is not.
    /// `job_id` is [`Manifest::job_id`], computed once by the caller.
    pub fn check_part_label(
        &self,
        job_id: &str,
        task: usize,
        label: &part_file::PartLabel,
    ) -> std::result::Result<(), String> {
        if label.job != job_id || label.scene_hash != self.scene_hash {
            return Err(format!(
                "it belongs to another job (job {} of scene {}; this is job {job_id} of scene {})",
                label.job, label.scene_hash, self.scene_hash
            ));
        }
        if label.task != task as u64 || Some(&label.range) != self.tasks.get(task) {
            return Err(format!(
                "it holds task {} ({}..{})",
                label.task, label.range[0], label.range[1]
            ));
        }
        Ok(())
    }

    /// Save as `JOB/job.toml` (atomically), after the checks a worker will make.
    pub fn save(&self, job: &Path) -> Result<()> {
        let path = job.join(MANIFEST);
        self.check().map_err(|m| {
            Error::InvalidSetting(format!("cannot write '{}': {m}", path.display()))
        })?;
        let text = toml::to_string(self)
            .map_err(|e| Error::InvalidSetting(format!("cannot write the manifest: {e}")))?;
        crate::io::atomic::write_file(&path, &text)
    }

    /// The task range flag for `photon render`: `--pass-range` or `--sample-range`.
    pub fn range_flag(&self) -> &'static str {
        match self.unit {
            Unit::Passes => "--pass-range",
            Unit::Samples => "--sample-range",
        }
    }

    /// Check every file of the scene against its recorded size and hash: a worker on a
    /// machine with an incomplete copy must not render another scene.
    pub fn verify_files(&self, job: &Path) -> Result<()> {
        for f in &self.files {
            let path = job.join(&f.path);
            let bytes = crate::io::input::read_file(&path)?;
            if bytes.len() as u64 != f.bytes || fnv64_hex(&bytes) != f.fnv64 {
                return Err(Error::InvalidSetting(format!(
                    "'{}' differs from the file the job was made with (size or content hash): copy the job folder again",
                    path.display()
                )));
            }
        }
        Ok(())
    }
}

/// What a job's settings cannot hold: a sample or pass range (each task sets its own), a
/// time (not the same work on every machine), or a sky file given beside the scene (it would
/// not travel with the job, and a manifest naming one would make workers read any file).
pub fn what_a_job_cannot_carry(
    settings: &RenderOptions,
    environment: &EnvSettings,
) -> std::result::Result<(), SettingError> {
    let refuse = |name, value: String, problem: &str| {
        Err(SettingError {
            name,
            value: Some(value),
            problem: problem.into(),
        })
    };
    for (name, range) in [
        ("sample_range", settings.sample_range),
        ("pass_range", settings.pass_range),
    ] {
        if let Some(r) = range {
            return refuse(
                name,
                format!("{}..{}", r.start, r.end),
                "a job sets each task's range itself",
            );
        }
    }
    if let Some(t) = settings.time {
        return refuse(
            "time",
            t.to_string(),
            "a time budget is not the same work on every machine; a job takes passes or spp",
        );
    }
    if let Some(sky) = &environment.sky
        && !crate::description::environment::is_colour(sky)
    {
        return refuse(
            "env",
            sky.clone(),
            "a job carries a sky only in its scene: put it in the scene file ([[lights]] type = \"environment\")",
        );
    }
    Ok(())
}

/// `total` units split into `tasks` contiguous ranges whose sizes differ by at most one.
pub fn split(total: u64, tasks: u64) -> Result<Vec<[u64; 2]>> {
    if total > MAX_TOTAL {
        return Err(Error::InvalidSetting(format!(
            "{total} passes or samples: a job renders at most {MAX_TOTAL}"
        )));
    }
    if tasks == 0 || tasks > total || tasks > MAX_TASKS {
        return Err(Error::InvalidSetting(format!(
            "{tasks} tasks for {total} passes or samples: give 1 to {} tasks",
            total.min(MAX_TASKS)
        )));
    }
    Ok((0..tasks)
        .map(|i| {
            let at = |k: u64| (u128::from(k) * u128::from(total) / u128::from(tasks)) as u64;
            [at(i), at(i + 1)]
        })
        .collect())
}

pub fn fnv64_hex(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

/// Where task `task`'s part goes.
pub fn part_path(job: &Path, task: usize) -> PathBuf {
    job.join(PARTS_DIR).join(format!("{task}.part"))
}

/// Where a failed task's message goes.
pub fn failure_path(job: &Path, task: usize) -> PathBuf {
    job.join(PARTS_DIR).join(format!("{task}.failed"))
}

/// Copy `files` (the scene file among them) into `JOB/scene/`, keeping their layout relative
/// to the deepest folder that holds them all, so relative references between them (a scene to
/// its meshes, an OBJ to its MTL, a glTF to its buffers) still hold. Paths are resolved
/// (`..`, symbolic links) before the layout is taken: every copy lands inside `JOB/scene/`.
/// Returns the manifest entries and where `scene` went, relative to the job folder.
pub fn copy_scene_files(
    job: &Path,
    scene: &Path,
    files: &[PathBuf],
) -> Result<(Vec<JobFile>, String)> {
    let resolve = |p: &Path| {
        std::fs::canonicalize(p).map_err(|source| Error::Read {
            path: p.to_owned(),
            source,
        })
    };
    let scene = resolve(scene)?;
    let mut all = vec![scene.clone()];
    for f in files {
        let f = resolve(f)?;
        if !all.contains(&f) {
            all.push(f);
        }
    }
    let mut root = scene.parent().map(Path::to_owned).unwrap_or_default();
    for f in &all {
        while !f.starts_with(&root) {
            root = root.parent().map(Path::to_owned).unwrap_or_default();
        }
    }
    let inside_scene_dir = |f: &Path| -> Result<PathBuf> {
        let relative = f.strip_prefix(&root).unwrap_or(f);
        if !relative
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)))
        {
            return Err(Error::InvalidSetting(format!(
                "'{}' cannot be copied into the job: its path leaves the job's scene folder",
                f.display()
            )));
        }
        Ok(Path::new(SCENE_DIR).join(relative))
    };
    let mut entries = Vec::new();
    for f in &all {
        let inside = inside_scene_dir(f)?;
        let bytes = crate::io::input::read_file(f)?;
        let destination = job.join(&inside);
        if let Some(dir) = destination.parent() {
            std::fs::create_dir_all(dir).map_err(|source| Error::Write {
                path: dir.to_owned(),
                source,
            })?;
        }
        crate::io::atomic::write_file(&destination, &bytes)?;
        entries.push(JobFile {
            path: portable(&inside),
            bytes: bytes.len() as u64,
            fnv64: fnv64_hex(&bytes),
        });
    }
    Ok((entries, portable(&inside_scene_dir(&scene)?)))
}

/// A relative path with `/` separators, as the manifest keeps them.
fn portable(p: &Path) -> String {
    p.components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

/// Where each task stands.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TaskState {
    Done,
    /// A live worker holds its lock.
    Running(lock::Holder),
    Missing,
    /// The worker's message from `I.failed`.
    Failed(String),
}

/// The state of every task: done when its part is this job's and whole.
pub fn task_states(job: &Path, manifest: &Manifest) -> Vec<TaskState> {
    let job_id = manifest.job_id();
    (0..manifest.tasks.len())
        .map(|i| {
            if load_job_part(job, manifest, &job_id, i).is_ok() {
                TaskState::Done
            } else if let Some(holder) = lock::live_holder(job, i) {
                TaskState::Running(holder)
            } else if let Ok(m) = crate::io::input::read_text(&failure_path(job, i)) {
                TaskState::Failed(m.trim().to_owned())
            } else {
                TaskState::Missing
            }
        })
        .collect()
}

/// Whether task `i`'s part is there, whole, and this job's (an interrupted worker may have
/// saved fewer passes; another job's part may have been copied in).
pub fn part_is_complete(job: &Path, manifest: &Manifest, i: usize) -> bool {
    load_job_part(job, manifest, &manifest.job_id(), i).is_ok()
}

/// Task `i`'s part, checked to be this job's task `i` (`job_id` is [`Manifest::job_id`]).
pub fn load_job_part(job: &Path, manifest: &Manifest, job_id: &str, i: usize) -> Result<Part> {
    let path = part_path(job, i);
    let bytes = crate::io::input::read_file(&path)?;
    let bad = |message: String| Error::BadCheckpoint {
        path: path.clone(),
        message,
    };
    let (label, part) = part_file::decode(&bytes).map_err(bad)?;
    manifest
        .check_part_label(job_id, i, &label)
        .map_err(|m| bad(format!("not task {i} of this job: {m}")))?;
    Ok(part)
}

/// Label the bare part a worker rendered at `rendered` for task `i` and move it to `I.part`,
/// unless a complete part is there already: a part is never replaced. Returns whether it
/// was moved.
pub fn promote_part(job: &Path, manifest: &Manifest, i: usize, rendered: &Path) -> Result<bool> {
    let bytes = crate::io::input::read_file(rendered)?;
    let part = decode_part(&bytes).map_err(|message| Error::BadCheckpoint {
        path: rendered.to_owned(),
        message,
    })?;
    let (start, end) = part.range();
    if [start, end] != manifest.tasks[i] || part.scene_hash() != manifest.scene_hash {
        return Err(Error::InvalidSetting(format!(
            "'{}' holds {start}..{end} of scene {}, not task {i}'s {}..{} of scene {}",
            rendered.display(),
            part.scene_hash(),
            manifest.tasks[i][0],
            manifest.tasks[i][1],
            manifest.scene_hash
        )));
    }
    let job_id = manifest.job_id();
    if load_job_part(job, manifest, &job_id, i).is_ok() {
        return Ok(false);
    }
    let label = part_file::PartLabel {
        job: job_id,
        scene_hash: manifest.scene_hash.clone(),
        task: i as u64,
        range: manifest.tasks[i],
    };
    let labelled = part_file::encode(&label, &bytes);
    let path = part_path(job, i);
    crate::io::atomic::write_file(&path, &labelled)?;
    Ok(true)
}

fn is_hex64(s: &str) -> bool {
    s.len() == 16 && s.bytes().all(|b| b.is_ascii_hexdigit())
}

/// Whether `p` is a plain relative path under `scene/`: `/`-separated names, none empty,
/// `.` or `..`, and nothing a platform reads as a root, a drive or a control character.
fn is_scene_file_path(p: &str) -> bool {
    let mut names = p.split('/');
    names.next() == Some(SCENE_DIR)
        && p.len() > SCENE_DIR.len() + 1
        && names.all(|n| {
            !n.is_empty()
                && n != "."
                && n != ".."
                && !n.contains('\\')
                && !n.chars().any(char::is_control)
        })
        && Path::new(p)
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)))
}

/// Task indices as a compact list: `0-3,7,9-10`.
pub fn compact_list(indices: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let mut j = i;
        while j + 1 < indices.len() && indices[j + 1] == indices[j] + 1 {
            j += 1;
        }
        out.push(if j > i {
            format!("{}-{}", indices[i], indices[j])
        } else {
            indices[i].to_string()
        });
        i = j + 1;
    }
    out.join(",")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_cover_the_total_in_near_equal_contiguous_ranges() {
        let ranges = split(64, 3).expect("split");
        assert_eq!(ranges, vec![[0, 21], [21, 42], [42, 64]]);
        assert_eq!(split(5, 5).expect("split").len(), 5);
        assert!(split(4, 5).is_err());
        assert!(split(4, 0).is_err());
    }

    /// A one-pixel sample part of `samples` samples from `first` at `path`.
    fn sample_part(path: &Path, first: u32, samples: u32, value: i128) {
        let sums = crate::render::SampleSums {
            width: 1,
            height: 1,
            spp: 2,
            samples,
            splits_components: false,
            sums: vec![(crate::film::FixedRgb([value; 3]), samples)],
        };
        let origin = crate::io::sample_part::PartOrigin {
            scene: "cornell".into(),
            scene_hash: "00000000000000aa".into(),
            settings: RenderOptions::default(),
            first_sample: first,
        };
        crate::io::sample_part::save(&sums, &origin, path).expect("save");
    }

    /// A manifest is untrusted: one naming a sky file would make every worker read that
    /// file as an image.
    #[test]
    fn a_manifest_naming_a_sky_file_or_a_range_is_refused() {
        let base = "photon_version = \"0.1.0\"\nscene = \"cornell\"\nscene_hash = \"00000000000000aa\"\nunit = \"samples\"\ntotal = 2\ntasks = [[0, 2]]\nfiles = []\n";
        let parse = |extra: &str| Manifest::parse(&format!("{base}{extra}"), Path::new("job.toml"));
        assert!(parse("[settings]\n[environment]\nsky = \"1,1,1\"\n").is_ok());
        for (extra, needle) in [
            (
                "[settings]\n[environment]\nsky = \"/etc/hostname\"\n",
                "carries a sky only in its scene",
            ),
            (
                "[settings]\nsample_range = [0, 1]\n",
                "sets each task's range itself",
            ),
            (
                "[settings]\ntime = 5.0\n",
                "not the same work on every machine",
            ),
        ] {
            let e = parse(extra).expect_err(extra).to_string();
            assert!(e.contains(needle), "{extra}: {e}");
        }
    }

    #[test]
    fn a_complete_part_is_never_replaced_and_parts_must_match_their_task() {
        let job = std::env::temp_dir().join(format!("photon-promote-{}", std::process::id()));
        std::fs::create_dir_all(job.join(PARTS_DIR)).expect("parts");
        let manifest = Manifest {
            photon_version: "0".into(),
            scene: "cornell".into(),
            scene_hash: "00000000000000aa".into(),
            settings: RenderOptions::default(),
            environment: EnvSettings::default(),
            unit: Unit::Samples,
            total: 2,
            tasks: vec![[0, 1], [1, 2]],
            files: Vec::new(),
        };
        let rendered = job.join("rendered.part");
        sample_part(&rendered, 0, 1, 5);
        assert!(promote_part(&job, &manifest, 0, &rendered).expect("promote"));
        let first = crate::io::input::read_file(&part_path(&job, 0)).expect("part");
        // A later worker's part of the same task is dropped, not written over the first.
        sample_part(&rendered, 0, 1, 7);
        assert!(!promote_part(&job, &manifest, 0, &rendered).expect("promote"));
        assert_eq!(
            crate::io::input::read_file(&part_path(&job, 0)).expect("part"),
            first
        );
        // A part of another range is not the task's.
        assert!(promote_part(&job, &manifest, 1, &rendered).is_err());
        let _ = std::fs::remove_dir_all(&job);
    }

    #[test]
    fn manifests_name_only_files_inside_the_scene_folder() {
        for good in ["scene/s.toml", "scene/a/b.obj", "scene/..x"] {
            assert!(is_scene_file_path(good), "{good}");
        }
        for bad in [
            "scene",
            "scene/",
            "/etc/passwd",
            "scene/../x",
            "scene/a/../../x",
            "scene//x",
            "scene/./x",
            "parts/x",
            "scene/a\\..\\..\\x",
            "scene/a\nb",
        ] {
            assert!(!is_scene_file_path(bad), "{bad}");
        }
    }

    #[test]
    fn task_lists_are_compact() {
        assert_eq!(compact_list(&[0, 1, 2, 3, 7, 9, 10]), "0-3,7,9-10");
        assert_eq!(compact_list(&[5]), "5");
        assert_eq!(compact_list(&[]), "");
    }
}
