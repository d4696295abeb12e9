//! One worker per task: a worker holds `parts/I.lock`, created exclusively (`O_EXCL`, which
//! NFS v3 and later honour), recording its host and process id, and touched every
//! [`HEARTBEAT`] while it renders. A lock is stale, and may be taken over, when this host's
//! process that holds it has ended, or when it has not been touched for [`STALE_AFTER`]
//! (its holder, on whatever host, has stopped).

use crate::error::{Error, Result};
use crate::io::atomic::{host_name, process_is_running};
use serde::{Deserialize, Serialize};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, SystemTime};

/// How often a holder touches its lock.
pub const HEARTBEAT: Duration = Duration::from_secs(60);
/// A lock untouched this long is stale, whoever holds it.
pub const STALE_AFTER: Duration = Duration::from_secs(15 * 60);

/// Who holds a task's lock.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Holder {
    pub host: String,
    pub pid: u32,
}

impl Holder {
    fn this_process() -> Self {
        Holder {
            host: host_name(),
            pid: std::process::id(),
        }
    }
}

impl std::fmt::Display for Holder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "host {} (pid {})", self.host, self.pid)
    }
}

/// Where task `task`'s lock is.
pub fn lock_path(job: &Path, task: usize) -> PathBuf {
    job.join(super::PARTS_DIR).join(format!("{task}.lock"))
}

/// Where `holder` renders task `task` before the part is checked and moved to `I.part`.
pub fn worker_part_path(job: &Path, task: usize, holder: &Holder) -> PathBuf {
    job.join(super::PARTS_DIR)
        .join(format!("{task}.{}-{}.part", holder.host, holder.pid))
}

/// The holder recorded in a lock file; `None` when it cannot be read (being written, or
/// damaged).
fn read_holder(path: &Path) -> Option<Holder> {
    toml::from_str(&crate::io::input::read_text(path).ok()?).ok()
}

/// Whether the lock at `path` held by `holder` may be taken over.
fn is_stale(path: &Path, holder: Option<&Holder>) -> bool {
    let untouched = fs::metadata(path)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok())
        .is_some_and(|age| age > STALE_AFTER);
    let ended_here = holder.is_some_and(|h| {
        h.host == host_name() && h.pid != std::process::id() && !process_is_running(h.pid)
    });
    untouched || ended_here
}

/// The live holder of task `task`'s lock, if any.
pub fn live_holder(job: &Path, task: usize) -> Option<Holder> {
    let path = lock_path(job, task);
    let holder = read_holder(&path);
    if !path.exists() || is_stale(&path, holder.as_ref()) {
        return None;
    }
    Some(holder.unwrap_or(Holder {
        host: "unknown".into(),
        pid: 0,
    }))
}

/// A held task lock: released (removed) on drop.
pub struct TaskLock {
    path: PathBuf,
    holder: Holder,
    heartbeat: Option<(mpsc::Sender<()>, std::thread::JoinHandle<()>)>,
}

/// What [`TaskLock::acquire`] found.
pub enum Acquired {
    Held(TaskLock),
    /// Another live worker holds the task.
    Busy(Holder),
}

impl TaskLock {
    /// Take task `task`'s lock, taking over a stale one (and removing the part its holder
    /// left unfinished).
    pub fn acquire(job: &Path, task: usize) -> Result<Acquired> {
        let path = lock_path(job, task);
        let me = Holder::this_process();
        let record = toml::to_string(&me).expect("a holder is plain data");
        for _ in 0..3 {
            match fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut file) => {
                    file.write_all(record.as_bytes())
                        .and_then(|()| file.sync_all())
                        .map_err(|source| Error::Write {
                            path: path.clone(),
                            source,
                        })?;
                    return Ok(Acquired::Held(TaskLock::held(path, me, file)));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let holder = read_holder(&path);
                    if !is_stale(&path, holder.as_ref()) {
                        return Ok(Acquired::Busy(holder.unwrap_or(Holder {
                            host: "unknown".into(),
                            pid: 0,
                        })));
                    }
                    break_stale_lock(&path, holder.as_ref());
                    if let Some(h) = holder {
                        let _ = fs::remove_file(worker_part_path(job, task, &h));
                    }
                }
                Err(source) => return Err(Error::Write { path, source }),
            }
        }
        Ok(Acquired::Busy(read_holder(&path).unwrap_or(Holder {
            host: "unknown".into(),
            pid: 0,
        })))
    }

    fn held(path: PathBuf, holder: Holder, file: fs::File) -> Self {
        let (stop, stopped) = mpsc::channel::<()>();
        let thread = std::thread::spawn(move || {
            while let Err(mpsc::RecvTimeoutError::Timeout) = stopped.recv_timeout(HEARTBEAT) {
                let _ = file.set_modified(SystemTime::now());
            }
        });
        TaskLock {
            path,
            holder,
            heartbeat: Some((stop, thread)),
        }
    }

    /// Who holds it: this process.
    pub fn holder(&self) -> &Holder {
        &self.holder
    }
}

impl Drop for TaskLock {
    fn drop(&mut self) {
        if let Some((stop, thread)) = self.heartbeat.take() {
            drop(stop);
            let _ = thread.join();
        }
        // A lock taken over while this worker was thought gone is its new holder's.
        if read_holder(&self.path).as_ref() == Some(&self.holder) {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Remove the stale lock at `path` unless another worker has replaced it meanwhile: it is
/// moved aside under a name of this process's (a rename has one winner), and put back if what
/// was moved is not the stale holder's.
fn break_stale_lock(path: &Path, stale: Option<&Holder>) {
    let me = Holder::this_process();
    let aside = path.with_extension(format!("lock.{}-{}.stale", me.host, me.pid));
    if fs::rename(path, &aside).is_err() {
        return;
    }
    if read_holder(&aside).as_ref() == stale {
        let _ = fs::remove_file(&aside);
    } else {
        // Another worker's fresh lock: restore it, unless yet another has been made.
        let _ = fs::hard_link(&aside, path);
        let _ = fs::remove_file(&aside);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lock_has_one_holder_and_is_released_on_drop() {
        let job = std::env::temp_dir().join(format!("photon-lock-{}", std::process::id()));
        fs::create_dir_all(job.join(super::super::PARTS_DIR)).expect("parts");
        let Acquired::Held(lock) = TaskLock::acquire(&job, 3).expect("acquire") else {
            panic!("a free task is busy");
        };
        // A second worker of this process sees it held (its own pid is alive).
        match TaskLock::acquire(&job, 3).expect("acquire") {
            Acquired::Busy(h) => assert_eq!(&h, lock.holder()),
            Acquired::Held(_) => panic!("two holders"),
        }
        assert_eq!(live_holder(&job, 3).as_ref(), Some(lock.holder()));
        drop(lock);
        assert!(!lock_path(&job, 3).exists());
        assert_eq!(live_holder(&job, 3), None);
        let _ = fs::remove_dir_all(&job);
    }
}
