//! Atomic writes: every file Photon writes goes to a temporary sibling in the destination
//! folder, reaches the disk (fsync), and is only then renamed over the target, so an
//! interrupted or failed write never destroys what the user had and a crash never leaves a
//! torn file under the target's name (a rename within one folder is atomic on POSIX).

use crate::error::{Error, Result};
use std::fs;
use std::path::{Path, PathBuf};

/// Check that a file can be created beside `path` (creates and removes a temporary file), so
/// a long computation does not end in a failed write.
pub fn check_writable_path(path: &Path) -> Result<()> {
    let tmp = temp_path(path);
    fs::File::create(&tmp).map_err(|source| Error::Write {
        path: path.to_owned(),
        source,
    })?;
    let _ = fs::remove_file(&tmp);
    Ok(())
}

/// The temporary sibling a file is written to before being renamed into place:
/// `.NAME.HOST.PID.partial`, unique among the hosts that share a folder.
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(
        ".{name}.{}.{}.partial",
        host_name(),
        std::process::id()
    ))
}

/// This machine's name as file names and job locks record it: its host name with anything
/// but ASCII letters, digits, `-` and `.` replaced by `_` ("unknown" where there is none).
pub fn host_name() -> String {
    let raw = crate::io::input::read_text(Path::new("/proc/sys/kernel/hostname"))
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .or_else(|| std::env::var("COMPUTERNAME").ok())
        .unwrap_or_default();
    let name: String = raw
        .trim()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if name.is_empty() {
        "unknown".into()
    } else {
        name
    }
}

/// Whether process `pid` of this host runs, where that can be known (Linux: `/proc/PID`);
/// elsewhere every process is taken to run.
pub fn process_is_running(pid: u32) -> bool {
    !cfg!(target_os = "linux") || Path::new(&format!("/proc/{pid}")).exists()
}

/// A temporary file whose writer cannot be known to be gone is removed only this long after
/// its last change: no write of a live process pauses for a day.
const ABANDONED_AFTER: std::time::Duration = std::time::Duration::from_secs(24 * 3600);

/// Remove `.NAME.HOST.PID.partial` siblings of `path` that their writers left (a SIGKILL
/// leaves them; they reached 67 MB): this host's whose process has ended, and any, of any
/// host or of the older `.NAME.PID.partial` form, unchanged for [`ABANDONED_AFTER`]. Another
/// host's process cannot be seen from here, so its recent files are left alone.
fn remove_stale_partials(path: &Path) {
    let Some(name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return;
    };
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let prefix = format!(".{name}.");
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let this_host = host_name();
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(writer) = file
            .strip_prefix(&prefix)
            .and_then(|rest| rest.strip_suffix(".partial"))
        else {
            continue;
        };
        let (host, pid) = writer.rsplit_once('.').unwrap_or(("", writer));
        let Ok(pid) = pid.parse::<u32>() else {
            continue;
        };
        let ended_here = host == this_host && pid != std::process::id() && !process_is_running(pid);
        let abandoned = entry
            .metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|age| age > ABANDONED_AFTER);
        if ended_here || abandoned {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Write through `write`, which creates the temporary file it is given, then fsync that file
/// and rename it over `path`. On an error the temporary file is removed and `path` is left as
/// it was.
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let tmp = temp_path(path);
    remove_stale_partials(path);
    let result = write(&tmp).and_then(|()| {
        let err = |source| Error::Write {
            path: path.to_owned(),
            source,
        };
        // The data reaches the disk before the name does: a crash after the rename must not
        // leave an empty or torn file where the old one was.
        fs::OpenOptions::new()
            .write(true)
            .open(&tmp)
            .and_then(|f| f.sync_all())
            .map_err(err)?;
        fs::rename(&tmp, path).map_err(err)
    });
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Write `bytes` to `path` atomically (see [`write_atomically`]).
pub fn write_file(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    write_atomically(path, |tmp| {
        fs::write(tmp, bytes.as_ref()).map_err(|source| Error::Write {
            path: path.to_owned(),
            source,
        })
    })
}
