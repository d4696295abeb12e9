//! The one place that reads files the user names, directly or through a scene (scene files,
//! meshes, material libraries, glTF buffers and images, textures, environment maps, photon
//! maps, checkpoints, images to compare). Every such path must name a regular file no larger
//! than a limit: a FIFO would block forever, `/dev/zero` would be read until memory ran out,
//! and a directory is not "not found". `tests/tidy.rs` checks that nothing else opens files.

use crate::error::{Error, Result};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The files checked or read while [`recording`] runs, from any thread.
static RECORDED: Mutex<Option<Vec<PathBuf>>> = Mutex::new(None);

/// Run `f`, and return with its result every file it checked or read through this module, in
/// order, absolute: what a scene needs, for a job folder that must hold all of it. While it
/// runs, reads from every thread are recorded, so it is for one-shot commands.
pub fn recording<R>(f: impl FnOnce() -> R) -> (R, Vec<PathBuf>) {
    *RECORDED.lock().unwrap_or_else(|e| e.into_inner()) = Some(Vec::new());
    let result = f();
    let files = RECORDED
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .take()
        .unwrap_or_default();
    (result, files)
}

fn record(path: &Path) {
    let mut recorded = RECORDED.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(files) = recorded.as_mut() {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
        if !files.contains(&path) {
            files.push(path);
        }
    }
}

/// Largest file read whole: 8 GiB (a 100 M-photon map is 2.4 GB).
pub const MAX_FILE_BYTES: u64 = 8 << 30;

fn refuse(path: &Path, why: String) -> Error {
    Error::Read {
        path: path.to_owned(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidInput, why),
    }
}

/// That `path` names a regular file (after symbolic links) of at most `max` bytes, without
/// opening it (opening a FIFO for reading blocks until someone writes to it).
pub fn check_regular_file(path: &Path, max: u64) -> Result<()> {
    record(path);
    let meta = std::fs::metadata(path).map_err(|source| Error::Read {
        path: path.to_owned(),
        source,
    })?;
    if meta.is_dir() {
        return Err(refuse(path, "it is a directory, not a file".into()));
    }
    if !meta.is_file() {
        return Err(refuse(
            path,
            "it is not a regular file (a device, FIFO or socket)".into(),
        ));
    }
    if meta.len() > max {
        return Err(refuse(
            path,
            format!("it is {} bytes, more than the {max} accepted", meta.len()),
        ));
    }
    Ok(())
}

/// The whole content of a regular file of at most [`MAX_FILE_BYTES`].
pub fn read_file(path: &Path) -> Result<Vec<u8>> {
    read_file_limited(path, MAX_FILE_BYTES)
}

/// The whole content of a regular file of at most `max` bytes; a file that grows past the
/// limit while it is read is refused too.
pub fn read_file_limited(path: &Path, max: u64) -> Result<Vec<u8>> {
    check_regular_file(path, max)?;
    let read_error = |source| Error::Read {
        path: path.to_owned(),
        source,
    };
    let file = std::fs::File::open(path).map_err(read_error)?;
    let mut bytes = Vec::new();
    file.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > max {
        return Err(refuse(
            path,
            format!("it holds more than the {max} bytes accepted"),
        ));
    }
    Ok(bytes)
}

/// A text file (UTF-8) of at most [`MAX_FILE_BYTES`].
pub fn read_text(path: &Path) -> Result<String> {
    String::from_utf8(read_file(path)?).map_err(|_| refuse(path, "it is not UTF-8 text".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_directories_are_refused_by_name() {
        let dir = std::env::temp_dir();
        let e = read_file(&dir).expect_err("a directory").to_string();
        assert!(e.contains("directory"), "{e}");
        if Path::new("/dev/zero").exists() {
            let e = read_file(Path::new("/dev/zero"))
                .expect_err("a device")
                .to_string();
            assert!(e.contains("not a regular file"), "{e}");
        }
        let e = read_file(Path::new("/nonexistent/file"))
            .expect_err("missing")
            .to_string();
        assert!(e.contains("/nonexistent/file"), "{e}");
        let small = dir.join(format!("photon-input-{}", std::process::id()));
        std::fs::write(&small, b"0123456789").expect("write");
        assert_eq!(read_file_limited(&small, 10).expect("fits"), b"0123456789");
        let e = read_file_limited(&small, 9)
            .expect_err("too big")
            .to_string();
        assert!(e.contains("more than the 9"), "{e}");
        let _ = std::fs::remove_file(&small);
    }
}
