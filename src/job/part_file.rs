//! A job's part file: the worker's part (a sample part or a PPM pass-range checkpoint) with a
//! label that proves which job, scene and task it belongs to.
//!
//! ```text
//! "PHOTONJP" | version u32 | label length u32 | JSON label (job, scene hash, task, range)
//! | the bare part, whole | FNV-1a 64 checksum of everything before it
//! ```
//! ([`crate::io::container`]'s layout).
//! The label must agree with the bare part inside (its range and scene hash), and the job's
//! manifest decides whether the label is its own ([`super::Manifest::check_part_label`]).

use super::merge::{Part, decode_part};
use crate::io::container::{self, Contents, Format};
use serde::{Deserialize, Serialize};

pub const JOB_PART_VERSION: u32 = 1;
/// The container of job part files: the label is its header, the bare part its body.
const JOB_PART: Format = Format {
    magic: b"PHOTONJP",
    version: JOB_PART_VERSION,
    fixed_words: 0,
    max_header: 1 << 16,
    noun: "job part",
};

/// Which job, scene and task a part was rendered for.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartLabel {
    /// The job's identity ([`super::Manifest::job_id`]).
    pub job: String,
    /// The scene's content hash, hexadecimal.
    pub scene_hash: String,
    pub task: u64,
    /// The passes or samples `[start, end)` it holds.
    pub range: [u64; 2],
}

/// Whether `bytes` start like a job's part file.
pub fn is_job_part(bytes: &[u8]) -> bool {
    JOB_PART.is_format_of(bytes)
}

/// `part` (the bytes of a bare part) with `label`.
pub fn encode(label: &PartLabel, part: &[u8]) -> Vec<u8> {
    container::encode(&JOB_PART, &[], label, part.len(), |out| {
        out.extend_from_slice(part);
    })
}

/// The label and the part of a job's part file, checked whole: magic, version, checksum, and
/// that the label describes the part inside.
pub fn decode(bytes: &[u8]) -> Result<(PartLabel, Part), String> {
    let Contents {
        header: label,
        body,
        ..
    } = container::decode::<PartLabel>(&JOB_PART, bytes)?;
    let part = decode_part(body)?;
    let (start, end) = part.range();
    if [start, end] != label.range || part.scene_hash() != label.scene_hash {
        return Err(format!(
            "the label (range {}..{}, scene {}) does not describe the part inside (range {start}..{end}, scene {})",
            label.range[0],
            label.range[1],
            label.scene_hash,
            part.scene_hash()
        ));
    }
    Ok((label, part))
}
