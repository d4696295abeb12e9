//! The one container of Photon's binary files: photon maps (`.phm`), progressive checkpoints
//! and PPM parts, sample parts, and a job's labelled parts.
//!
//! ```text
//! offset  size  content
//! 0       8     magic number, one per format
//! 8       4     format version
//! 12      4·W   W fixed words of the format (W = 0 but for .phm)
//! 12+4W   4     length H of the JSON header
//! 16+4W   H     JSON header
//! ...           body, the format's own
//! end-8   8     FNV-1a 64 checksum of everything before it
//! ```
//! All numbers little-endian. A file is checked whole before its header is read: magic,
//! version, checksum, then the header's length and contents.

use crate::hash::fnv1a;
use serde::Serialize;
use serde::de::DeserializeOwned;

/// What tells one format's files apart, and how its errors name them.
pub struct Format {
    pub magic: &'static [u8; 8],
    pub version: u32,
    /// The number of `u32` words between the version and the header's length.
    pub fixed_words: usize,
    /// A header longer than this is not one Photon wrote.
    pub max_header: usize,
    /// What its error messages call a file of this format ("checkpoint").
    pub noun: &'static str,
}

impl Format {
    /// Bytes before the header: magic, version, fixed words, header length.
    fn preamble(&self) -> usize {
        16 + 4 * self.fixed_words
    }

    /// Whether `bytes` start with this format's magic number.
    pub fn is_format_of(&self, bytes: &[u8]) -> bool {
        bytes.starts_with(self.magic)
    }
}

/// A file's contents, checked: its fixed words, header and body.
pub struct Contents<'a, H> {
    pub fixed: Vec<u32>,
    pub header: H,
    /// The bytes between the header and the checksum.
    pub body: &'a [u8],
}

/// The bytes of a file of `format`: `fixed` (as many as the format has), `header` as JSON, the
/// body that `write_body` appends (`body_len` of it, to reserve), and the checksum.
pub fn encode<H: Serialize>(
    format: &Format,
    fixed: &[u32],
    header: &H,
    body_len: usize,
    write_body: impl FnOnce(&mut Vec<u8>),
) -> Vec<u8> {
    debug_assert_eq!(fixed.len(), format.fixed_words);
    let json = serde_json::to_vec(header).expect("a header is plain data, always JSON");
    let mut out = Vec::with_capacity(format.preamble() + json.len() + body_len + 8);
    out.extend_from_slice(format.magic);
    out.extend_from_slice(&format.version.to_le_bytes());
    for word in fixed {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    write_body(&mut out);
    let checksum = fnv1a(&out);
    out.extend_from_slice(&checksum.to_le_bytes());
    out
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Read a file written by [`encode`], checked whole; the error is the reason, in words.
pub fn decode<'a, H: DeserializeOwned>(
    format: &Format,
    bytes: &'a [u8],
) -> Result<Contents<'a, H>, String> {
    let noun = format.noun;
    let preamble = format.preamble();
    if bytes.len() < preamble + 8 || !format.is_format_of(bytes) {
        return Err(format!("not a Photon {noun} (bad magic number)"));
    }
    let version = u32_at(bytes, 8);
    if version != format.version {
        return Err(format!(
            "{noun} version {version}; this Photon reads version {}",
            format.version
        ));
    }
    let (checked, tail) = bytes.split_at(bytes.len() - 8);
    if fnv1a(checked) != u64::from_le_bytes(tail.try_into().expect("8 bytes")) {
        return Err(format!(
            "checksum mismatch: the {noun} is truncated or corrupted"
        ));
    }
    let fixed = (0..format.fixed_words)
        .map(|k| u32_at(bytes, 12 + 4 * k))
        .collect();
    let header_len = u32_at(bytes, preamble - 4) as usize;
    if header_len > format.max_header || preamble + header_len > checked.len() {
        return Err("truncated header".into());
    }
    let header = serde_json::from_slice(&checked[preamble..preamble + header_len])
        .map_err(|e| format!("unreadable header: {e}"))?;
    Ok(Contents {
        fixed,
        header,
        body: &checked[preamble + header_len..],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEST: Format = Format {
        magic: b"PHOTONTT",
        version: 3,
        fixed_words: 1,
        max_header: 64,
        noun: "test file",
    };

    fn sample() -> Vec<u8> {
        encode(&TEST, &[7], &vec![1u32, 2], 3, |out| {
            out.extend_from_slice(b"abc");
        })
    }

    #[test]
    fn round_trips_fixed_words_header_and_body() {
        let bytes = sample();
        let c: Contents<Vec<u32>> = decode(&TEST, &bytes).expect("decodes");
        assert_eq!(c.fixed, [7]);
        assert_eq!(c.header, [1, 2]);
        assert_eq!(c.body, b"abc");
        // magic, version, 1 word, length, "[1,2]", "abc", checksum.
        assert_eq!(bytes.len(), 8 + 4 + 4 + 4 + 5 + 3 + 8);
    }

    #[test]
    fn refuses_what_it_did_not_write() {
        let bytes = sample();
        let reason = |b: &[u8]| decode::<Vec<u32>>(&TEST, b).err().expect("refused");
        assert!(reason(&bytes[..10]).contains("bad magic"));
        let mut other = bytes.clone();
        other[8] = 4;
        assert!(reason(&other).contains("test file version 4"));
        let mut flipped = bytes.clone();
        flipped[22] ^= 1;
        assert!(reason(&flipped).contains("checksum mismatch"));
        assert!(reason(&bytes[..bytes.len() - 1]).contains("checksum mismatch"));
    }
}
