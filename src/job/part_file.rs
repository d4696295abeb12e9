//! A job's part file: the worker's part (a sample part or a PPM pass-range checkpoint) with a
//! label that proves which job, scene and task it belongs to.
//!
//! ```text
//! "PHOTONJP" | version u32 | label length u32 | JSON label (job, scene hash, task, range)
//! | the bare part, whole | FNV-1a 64 checksum of everything before it
//! ```
//! The label must agree with the bare part inside (its range and scene hash), and the job's
//! manifest decides whether the label is its own ([`super::Manifest::check_part_label`]).

use super::merge::{Part, decode_part};
use crate::scene::Fnv1a;
use serde::{Deserialize, Serialize};

pub const MAGIC: &[u8; 8] = b"PHOTONJP";
pub const JOB_PART_VERSION: u32 = 1;
const MAX_LABEL: usize = 1 << 16;

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
    bytes.starts_with(MAGIC)
}

/// `part` (the bytes of a bare part) with `label`.
pub fn encode(label: &PartLabel, part: &[u8]) -> Vec<u8> {
    let json = serde_json::to_vec(label).expect("a label is plain data");
    let mut out = Vec::with_capacity(24 + json.len() + part.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&JOB_PART_VERSION.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(part);
    let mut h = Fnv1a::default();
    h.write(&out);
    out.extend_from_slice(&h.finish().to_le_bytes());
    out
}

/// The label and the part of a job's part file, checked whole: magic, version, checksum, and
/// that the label describes the part inside.
pub fn decode(bytes: &[u8]) -> Result<(PartLabel, Part), String> {
    if bytes.len() < 24 || !is_job_part(bytes) {
        return Err("not a part of a Photon job (bad magic number)".into());
    }
    let u32_at =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let version = u32_at(8);
    if version != JOB_PART_VERSION {
        return Err(format!(
            "job part version {version}; this Photon reads {JOB_PART_VERSION}"
        ));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    let mut h = Fnv1a::default();
    h.write(body);
    if h.finish() != u64::from_le_bytes(tail.try_into().expect("8 bytes")) {
        return Err("checksum mismatch: the part is truncated or corrupted".into());
    }
    let label_len = u32_at(12) as usize;
    if label_len > MAX_LABEL || 16 + label_len > body.len() {
        return Err("truncated label".into());
    }
    let label: PartLabel = serde_json::from_slice(&body[16..16 + label_len])
        .map_err(|e| format!("unreadable label: {e}"))?;
    let part = decode_part(&body[16 + label_len..])?;
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
