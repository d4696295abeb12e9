//! Render jobs split into tasks for machines that share nothing but a folder: a job folder
//! holds the scene with every file it reads (content-hashed), a manifest of the settings and
//! of each task's range of passes (ppm) or samples (path, direct, photon), and a `parts/`
//! folder where each task's worker writes `I.part`. Parts add exactly in any order, so the
//! merged image of all parts is the image one machine would render, bit for bit.
//!
//! The schedulers (Slurm job arrays, GNU parallel, Kubernetes Indexed Jobs) run the workers;
//! this module only describes the work and checks and merges what the workers wrote.

mod merge;

pub use merge::{Merger, Part, load_part};

use crate::error::{Error, Result};
use crate::scene::Fnv1a;
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
    pub integrator: String,
    /// The `photon render` flags after the scene, as given to `photon job create`.
    pub render_args: Vec<String>,
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
        let manifest: Manifest = toml::from_str(&text).map_err(|e| {
            Error::SceneFile(Box::new(crate::description::source::Diagnostic::at_span(
                &path,
                &text,
                e.span().unwrap_or(0..0),
                format!("not a job manifest: {}", e.message()),
            )))
        })?;
        manifest.check(&path)?;
        Ok(manifest)
    }

    fn check(&self, path: &Path) -> Result<()> {
        let bad = |m: String| {
            Err(Error::SceneFile(Box::new(
                crate::description::source::Diagnostic::whole_file(path, m),
            )))
        };
        if self.tasks.is_empty() || self.tasks.len() as u64 > MAX_TASKS {
            return bad(format!(
                "{} tasks; a job has 1 to {MAX_TASKS}",
                self.tasks.len()
            ));
        }
        let mut next = 0;
        for (i, &[start, end]) in self.tasks.iter().enumerate() {
            if start != next || end <= start {
                return bad(format!(
                    "task {i} covers {start}..{end}; the tasks must cover 0..{} in order",
                    self.total
                ));
            }
            next = end;
        }
        if next != self.total {
            return bad(format!("the tasks end at {next}, not at {}", self.total));
        }
        Ok(())
    }

    /// Save as `JOB/job.toml` (atomically).
    pub fn save(&self, job: &Path) -> Result<()> {
        let text = toml::to_string(self)
            .map_err(|e| Error::InvalidSetting(format!("cannot write the manifest: {e}")))?;
        let path = job.join(MANIFEST);
        crate::io::image::write_atomically(&path, |tmp| {
            std::fs::write(tmp, text).map_err(|source| Error::Write {
                path: path.clone(),
                source,
            })
        })
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

/// `total` units split into `tasks` contiguous ranges whose sizes differ by at most one.
pub fn split(total: u64, tasks: u64) -> Result<Vec<[u64; 2]>> {
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
    let mut h = Fnv1a::default();
    h.write(bytes);
    format!("{:016x}", h.finish())
}

/// Where task `task`'s part goes.
pub fn part_path(job: &Path, task: usize) -> PathBuf {
    job.join(PARTS_DIR).join(format!("{task}.part"))
}

/// Where a failed task's message goes.
pub fn failure_path(job: &Path, task: usize) -> PathBuf {
    job.join(PARTS_DIR).join(format!("{task}.failed"))
}

/// Copy `files` (absolute paths, the scene file among them) into `JOB/scene/`, keeping their
/// layout relative to the deepest folder that holds them all, so relative references between
/// them (a scene to its meshes, an OBJ to its MTL, a glTF to its buffers) still hold.
/// Returns the manifest entries and where `scene` went, relative to the job folder.
pub fn copy_scene_files(
    job: &Path,
    scene: &Path,
    files: &[PathBuf],
) -> Result<(Vec<JobFile>, String)> {
    let scene = std::path::absolute(scene).map_err(|source| Error::Read {
        path: scene.to_owned(),
        source,
    })?;
    let mut all: Vec<PathBuf> = files.to_vec();
    if !all.contains(&scene) {
        all.insert(0, scene.clone());
    }
    let mut root = scene.parent().map(Path::to_owned).unwrap_or_default();
    for f in &all {
        while !f.starts_with(&root) {
            root = root.parent().map(Path::to_owned).unwrap_or_default();
        }
    }
    let mut entries = Vec::new();
    for f in &all {
        let relative = f.strip_prefix(&root).expect("every file is under the root");
        let inside = Path::new(SCENE_DIR).join(relative);
        let bytes = crate::io::input::read_file(f)?;
        let destination = job.join(&inside);
        if let Some(dir) = destination.parent() {
            std::fs::create_dir_all(dir).map_err(|source| Error::Write {
                path: dir.to_owned(),
                source,
            })?;
        }
        crate::io::image::write_atomically(&destination, |tmp| {
            std::fs::write(tmp, &bytes).map_err(|source| Error::Write {
                path: destination.clone(),
                source,
            })
        })?;
        entries.push(JobFile {
            path: portable(&inside),
            bytes: bytes.len() as u64,
            fnv64: fnv64_hex(&bytes),
        });
    }
    let scene_inside =
        Path::new(SCENE_DIR).join(scene.strip_prefix(&root).expect("under the root"));
    Ok((entries, portable(&scene_inside)))
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
    Missing,
    /// The worker's message from `I.failed`.
    Failed(String),
}

/// The state of every task: done when its part exists and holds exactly its range.
pub fn task_states(job: &Path, manifest: &Manifest) -> Vec<TaskState> {
    (0..manifest.tasks.len())
        .map(|i| {
            if part_is_complete(job, manifest, i) {
                TaskState::Done
            } else if let Ok(m) = crate::io::input::read_text(&failure_path(job, i)) {
                TaskState::Failed(m.trim().to_owned())
            } else {
                TaskState::Missing
            }
        })
        .collect()
}

/// Whether task `i`'s part is there, whole, and holds the task's range (an interrupted
/// worker may have saved fewer passes).
pub fn part_is_complete(job: &Path, manifest: &Manifest, i: usize) -> bool {
    let path = part_path(job, i);
    if !path.is_file() {
        return false;
    }
    let [start, end] = manifest.tasks[i];
    match load_part(&path) {
        Ok(part) => part.range() == (start, end),
        Err(_) => false,
    }
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

    #[test]
    fn task_lists_are_compact() {
        assert_eq!(compact_list(&[0, 1, 2, 3, 7, 9, 10]), "0-3,7,9-10");
        assert_eq!(compact_list(&[5]), "5");
        assert_eq!(compact_list(&[]), "");
    }
}
