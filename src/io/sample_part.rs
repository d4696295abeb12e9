//! Partial renders of sample ranges (`photon render --sample-range a..b`, job tasks of the
//! path, direct and photon integrators): the fixed-point sums of [`SampleSums`], which add
//! exactly in any order into the sums, and so the image, of the whole render.
//!
//! ```text
//! "PHOTONSP" | version u32 | header length u32 | JSON header (scene, settings, samples)
//! | per pixel and component: 3 sums and a count, each a zigzag LEB128 varint
//! | FNV-1a 64 checksum of everything before it
//! ```
//! [`super::container`]'s layout. Varints because most sums fit in 5 to 9 bytes of their 16.
//! Written atomically.

use super::atomic::write_file;
use super::container::{self, Contents, Format};
use crate::error::{Error, Result};
use crate::film::FixedRgb;
use crate::render::{MAX_RESOLUTION, SampleSums};
use crate::settings::RenderOptions;
use serde::{Deserialize, Serialize};
use std::path::Path;

pub const SAMPLE_PART_VERSION: u32 = 2;
/// The container of sample parts.
const SAMPLE_PART: Format = Format {
    magic: b"PHOTONSP",
    version: SAMPLE_PART_VERSION,
    fixed_words: 0,
    max_header: 1 << 20,
    noun: "sample part",
};

/// What the sums were rendered from, which parts must share to be added.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartOrigin {
    pub scene: String,
    /// The scene's content hash, hexadecimal.
    pub scene_hash: String,
    /// Every setting that decides its samples, resolved (the integrator's defaults filled
    /// in), compared as typed values.
    pub settings: RenderOptions,
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
    let header = Header {
        origin: origin.clone(),
        width: sums.width,
        height: sums.height,
        spp: sums.spp,
        samples: sums.samples,
        splits_components: sums.splits_components,
    };
    let bytes = container::encode(&SAMPLE_PART, &[], &header, sums.sums.len() * 24, |out| {
        for (sum, count) in &sums.sums {
            for &v in &sum.0 {
                put_varint(out, v);
            }
            put_varint(out, i128::from(*count));
        }
    });
    write_file(path, &bytes)
}

/// Whether the file at `path` starts like a sample part (rather than a PPM part).
pub fn is_sample_part(bytes: &[u8]) -> bool {
    SAMPLE_PART.is_format_of(bytes)
}

/// Read a part written by [`save`], checked whole: magic, version, checksum, sizes.
pub fn load(path: &Path) -> Result<(SampleSums, PartOrigin)> {
    let bytes = crate::io::input::read_file(path)?;
    decode(&bytes).map_err(|m| bad(path, m))
}

/// [`load`] on bytes in memory (also what the fuzzer drives).
pub fn decode(bytes: &[u8]) -> Result<(SampleSums, PartOrigin), String> {
    let Contents {
        header: hd,
        body: data,
        ..
    } = container::decode::<Header>(&SAMPLE_PART, bytes)?;
    if hd.width == 0 || hd.height == 0 || hd.width > MAX_RESOLUTION || hd.height > MAX_RESOLUTION {
        return Err(format!(
            "resolution {}×{} out of range",
            hd.width, hd.height
        ));
    }
    if hd.samples == 0 || hd.samples > hd.spp {
        return Err(format!("{} samples of {} per pixel", hd.samples, hd.spp));
    }
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
        sums.push((FixedRgb(sum), count));
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
