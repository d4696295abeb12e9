//! Partial renders of sample ranges (`photon render --sample-range a..b`, job tasks of the
//! path, direct and photon integrators): the fixed-point sums of [`SampleSums`], which add
//! exactly in any order into the sums, and so the image, of the whole render.
//!
//! ```text
//! "PHOTONSP" | version u32 | header length u32 | JSON header (scene, settings, samples)
//! | per pixel and component: 3 sums and a count, each a zigzag LEB128 varint
//! | FNV-1a 64 checksum of everything before it
//! ```
//! Varints because most sums fit in 5 to 9 bytes of their 16. Written atomically.

use super::image::write_atomically;
use crate::error::{Error, Result};
use crate::render::{MAX_RESOLUTION, SampleSums};
use crate::scene::Fnv1a;
use serde::{Deserialize, Serialize};
use std::path::Path;

pub const MAGIC: &[u8; 8] = b"PHOTONSP";
pub const SAMPLE_PART_VERSION: u32 = 1;
const MAX_HEADER: usize = 1 << 20;

/// What the sums were rendered from, which parts must share to be added.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartOrigin {
    pub scene: String,
    /// The scene's content hash, hexadecimal.
    pub scene_hash: String,
    /// The integrator and every setting that changes its samples, as one string.
    pub settings: String,
    /// The first sample of each pixel that the sums hold (the range's start).
    pub first_sample: u32,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Header {
    origin: PartOrigin,
    width: u32,
    height: u32,
    spp: u32,
    samples: u32,
    splits_components: bool,
}

fn bad(path: &Path, m: impl Into<String>) -> Error {
    Error::BadCheckpoint {
        path: path.to_owned(),
        message: m.into(),
    }
}

fn put_varint(out: &mut Vec<u8>, v: i128) {
    let mut z = ((v << 1) ^ (v >> 127)) as u128;
    loop {
        let byte = (z & 0x7f) as u8;
        z >>= 7;
        if z == 0 {
            out.push(byte);
            return;
        }
        out.push(byte | 0x80);
    }
}

fn get_varint(data: &[u8], at: &mut usize) -> Option<i128> {
    let mut z = 0u128;
    for shift in (0..128).step_by(7) {
        let byte = *data.get(*at)?;
        *at += 1;
        z |= u128::from(byte & 0x7f).checked_shl(shift)?;
        if byte & 0x80 == 0 {
            return Some(((z >> 1) as i128) ^ -((z & 1) as i128));
        }
    }
    None
}

/// Write `sums` with their `origin` to `path` (atomically).
pub fn save(sums: &SampleSums, origin: &PartOrigin, path: &Path) -> Result<()> {
    let header = serde_json::to_vec(&Header {
        origin: origin.clone(),
        width: sums.width,
        height: sums.height,
        spp: sums.spp,
        samples: sums.samples,
        splits_components: sums.splits_components,
    })
    .map_err(|e| Error::InvalidSetting(format!("cannot encode a part header: {e}")))?;
    let mut out = Vec::with_capacity(24 + header.len() + sums.sums.len() * 24);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&SAMPLE_PART_VERSION.to_le_bytes());
    out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    out.extend_from_slice(&header);
    for (sum, count) in &sums.sums {
        for &v in sum {
            put_varint(&mut out, v);
        }
        put_varint(&mut out, i128::from(*count));
    }
    let mut h = Fnv1a::default();
    h.write(&out);
    out.extend_from_slice(&h.finish().to_le_bytes());
    write_atomically(path, |tmp| {
        std::fs::write(tmp, &out).map_err(|source| Error::Write {
            path: path.to_owned(),
            source,
        })
    })
}

/// Whether the file at `path` starts like a sample part (rather than a PPM part).
pub fn is_sample_part(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// Read a part written by [`save`], checked whole: magic, version, checksum, sizes.
pub fn load(path: &Path) -> Result<(SampleSums, PartOrigin)> {
    let bytes = crate::io::input::read_file(path)?;
    decode(&bytes).map_err(|m| bad(path, m))
}

/// [`load`] on bytes in memory (also what the fuzzer drives).
pub fn decode(bytes: &[u8]) -> Result<(SampleSums, PartOrigin), String> {
    if bytes.len() < 24 || !is_sample_part(bytes) {
        return Err("not a Photon sample part (bad magic number)".into());
    }
    let u32_at =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let version = u32_at(8);
    if version != SAMPLE_PART_VERSION {
        return Err(format!(
            "sample part version {version}; this Photon reads {SAMPLE_PART_VERSION}"
        ));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    let mut h = Fnv1a::default();
    h.write(body);
    if h.finish() != u64::from_le_bytes(tail.try_into().expect("8 bytes")) {
        return Err("checksum mismatch: the part is truncated or corrupted".into());
    }
    let header_len = u32_at(12) as usize;
    if header_len > MAX_HEADER || 16 + header_len > body.len() {
        return Err("truncated header".into());
    }
    let hd: Header = serde_json::from_slice(&body[16..16 + header_len])
        .map_err(|e| format!("unreadable header: {e}"))?;
    if hd.width == 0 || hd.height == 0 || hd.width > MAX_RESOLUTION || hd.height > MAX_RESOLUTION {
        return Err(format!(
            "resolution {}×{} out of range",
            hd.width, hd.height
        ));
    }
    if hd.samples == 0 || hd.samples > hd.spp {
        return Err(format!("{} samples of {} per pixel", hd.samples, hd.spp));
    }
    let data = &body[16 + header_len..];
    let slots = hd.width as usize * hd.height as usize * if hd.splits_components { 4 } else { 1 };
    // Every slot takes at least 4 bytes: a short file cannot claim a huge image.
    if data.len() < slots * 4 {
        return Err(format!(
            "{} bytes of pixel data for {}×{} pixels",
            data.len(),
            hd.width,
            hd.height
        ));
    }
    let mut sums = Vec::with_capacity(slots);
    let mut at = 0;
    let truncated = || "truncated or malformed pixel data".to_string();
    for _ in 0..slots {
        let mut sum = [0i128; 3];
        for v in &mut sum {
            *v = get_varint(data, &mut at).ok_or_else(truncated)?;
        }
        let count = get_varint(data, &mut at).ok_or_else(truncated)?;
        let count = u32::try_from(count).map_err(|_| truncated())?;
        sums.push((sum, count));
    }
    if at != data.len() {
        return Err("trailing bytes after the pixel data".into());
    }
    Ok((
        SampleSums {
            width: hd.width,
            height: hd.height,
            spp: hd.spp,
            samples: hd.samples,
            splits_components: hd.splits_components,
            sums,
        },
        hd.origin,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn varints_round_trip_the_extremes() {
        for v in [0, 1, -1, 63, -64, 1 << 40, -(1 << 90), i128::MAX, i128::MIN] {
            let mut out = Vec::new();
            put_varint(&mut out, v);
            let mut at = 0;
            assert_eq!(get_varint(&out, &mut at), Some(v));
            assert_eq!(at, out.len());
        }
        // Nineteen continuation bytes overflow 128 bits: refused, not wrapped.
        let mut at = 0;
        assert_eq!(get_varint(&[0xff; 20], &mut at), None);
    }
}
