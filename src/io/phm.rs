//! Photon-map files (`.phm`): a versioned binary format that loads with one bulk read.
//!
//! ```text
//! offset  size  content
//! 0       8     magic "PHOTONMP"
//! 8       4     format version (u32, little-endian) = 2 (2: photons mark a smooth last scattering)
//! 12      4     endianness mark 0x01020304 written little-endian
//! 16      4     bytes per photon = 24 (layout in photon::Photon's docs)
//! 20      4     length H of the JSON header
//! 24      H     JSON header: scene name and content hash, trace parameters and seed, counts,
//!               power scale of each map, per-depth counts
//! 24+H    24·C  caustic photons, kd-tree order
//! ...     24·G  global photons, kd-tree order
//! end-8   8     FNV-1a 64 checksum of everything before it
//! ```
//! Photons are stored in kd-tree order, so loading needs no rebuild.

use super::image::write_atomically;
use crate::error::{Error, Result};
use crate::photon::{MapKind, Photon, PhotonConfig, PhotonMap, PhotonMaps, TraceStats};
use crate::scene::Fnv1a;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"PHOTONMP";
pub const FORMAT_VERSION: u32 = 2;
const ENDIAN_MARK: u32 = 0x0102_0304;
const PHOTON_SIZE: usize = std::mem::size_of::<Photon>();
const FIXED: usize = 24;
/// A header larger than this is not one we wrote.
const MAX_HEADER: usize = 1 << 20;

#[derive(Serialize, Deserialize, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
struct Header {
    scene: String,
    scene_hash: String,
    photons: u64,
    global_photons: Option<u64>,
    max_depth: u32,
    absorption: Option<f32>,
    per_channel: bool,
    seed: u64,
    emitted: u64,
    global_emitted: u64,
    caustic_power_scale: f32,
    global_power_scale: f32,
    caustic_count: u64,
    global_count: u64,
    stored_by_depth: Vec<u64>,
    layout: String,
}

fn bad(path: &Path, message: impl Into<String>) -> Error {
    Error::BadPhotonMap {
        path: path.to_owned(),
        message: message.into(),
    }
}

/// Save maps atomically (temporary file, then rename).
pub fn save(maps: &PhotonMaps, path: &Path) -> Result<()> {
    let header = Header {
        scene: maps.scene_name.clone(),
        scene_hash: format!("{:016x}", maps.scene_hash),
        photons: maps.config.photons,
        global_photons: maps.config.global_photons,
        max_depth: maps.config.max_depth,
        absorption: maps.config.absorption,
        per_channel: maps.config.per_channel,
        seed: maps.config.seed,
        emitted: maps.stats.emitted,
        global_emitted: maps.stats.global_emitted,
        caustic_power_scale: maps.caustic.power_scale,
        global_power_scale: maps.global.power_scale,
        caustic_count: maps.caustic.len() as u64,
        global_count: maps.global.len() as u64,
        stored_by_depth: maps.stats.stored_by_depth.clone(),
        layout: "position f32x3, power f16x3 (x power_scale W), direction octahedral u8x2, normal octahedral u8x2, depth u8, flags u8".into(),
    };
    let json = serde_json::to_vec(&header).map_err(|e| bad(path, e.to_string()))?;
    let mut bytes = Vec::with_capacity(
        FIXED + json.len() + PHOTON_SIZE * (maps.caustic.len() + maps.global.len()) + 8,
    );
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&ENDIAN_MARK.to_le_bytes());
    bytes.extend_from_slice(&(PHOTON_SIZE as u32).to_le_bytes());
    bytes.extend_from_slice(&(json.len() as u32).to_le_bytes());
    bytes.extend_from_slice(&json);
    bytes.extend_from_slice(bytemuck::cast_slice(maps.caustic.photons()));
    bytes.extend_from_slice(bytemuck::cast_slice(maps.global.photons()));
    let mut h = Fnv1a::default();
    h.write(&bytes);
    bytes.extend_from_slice(&h.finish().to_le_bytes());
    write_atomically(path, |tmp| {
        std::fs::File::create(tmp)
            .and_then(|mut f| f.write_all(&bytes).and_then(|()| f.sync_all()))
            .map_err(|source| Error::Write {
                path: path.to_owned(),
                source,
            })
    })
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// Load maps saved by [`save`]. Truncated, corrupted or foreign files are errors.
pub fn load(path: &Path) -> Result<PhotonMaps> {
    let bytes = crate::io::input::read_file(path)?;
    if bytes.len() < FIXED + 8 || &bytes[..8] != MAGIC {
        return Err(bad(path, "not a Photon photon-map file (bad magic number)"));
    }
    let version = u32_at(&bytes, 8);
    if version != FORMAT_VERSION {
        return Err(bad(
            path,
            format!("format version {version}; this Photon reads version {FORMAT_VERSION}"),
        ));
    }
    if u32_at(&bytes, 12) != ENDIAN_MARK {
        return Err(bad(path, "written with another byte order"));
    }
    let size = u32_at(&bytes, 16) as usize;
    if size != PHOTON_SIZE {
        return Err(bad(
            path,
            format!("photon records are {size} bytes; expected {PHOTON_SIZE}"),
        ));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    let stored = u64::from_le_bytes(tail.try_into().expect("8 bytes"));
    let header_len = u32_at(&bytes, 20) as usize;
    if header_len > MAX_HEADER || FIXED + header_len > body.len() {
        return Err(bad(path, "truncated header"));
    }
    let header: Header = serde_json::from_slice(&bytes[FIXED..FIXED + header_len])
        .map_err(|e| bad(path, format!("unreadable header: {e}")))?;
    let expected = header
        .caustic_count
        .checked_add(header.global_count)
        .and_then(|n| usize::try_from(n).ok())
        .and_then(|n| n.checked_mul(PHOTON_SIZE))
        .and_then(|n| n.checked_add(FIXED + header_len))
        .ok_or_else(|| bad(path, "photon counts overflow"))?;
    if body.len() != expected {
        return Err(bad(
            path,
            format!(
                "truncated or padded: {} bytes of photons, the header announces {}",
                body.len(),
                expected
            ),
        ));
    }
    let mut h = Fnv1a::default();
    h.write(body);
    if h.finish() != stored {
        return Err(bad(path, "checksum mismatch: the file is corrupted"));
    }
    let scene_hash = u64::from_str_radix(&header.scene_hash, 16)
        .map_err(|_| bad(path, "bad scene hash in header"))?;
    let photons_at = FIXED + header_len;
    let split = photons_at + header.caustic_count as usize * PHOTON_SIZE;
    let caustic: Vec<Photon> = bytemuck::pod_collect_to_vec(&body[photons_at..split]);
    let global: Vec<Photon> = bytemuck::pod_collect_to_vec(&body[split..]);
    Ok(PhotonMaps {
        scene_name: header.scene,
        scene_hash,
        config: PhotonConfig {
            photons: header.photons,
            global_photons: header.global_photons,
            max_depth: header.max_depth,
            absorption: header.absorption,
            per_channel: header.per_channel,
            seed: header.seed,
        },
        caustic: PhotonMap::from_tree_order(MapKind::Caustic, caustic, header.caustic_power_scale),
        global: PhotonMap::from_tree_order(MapKind::Global, global, header.global_power_scale),
        stats: TraceStats {
            emitted: header.emitted,
            global_emitted: header.global_emitted,
            stored_by_depth: header.stored_by_depth,
        },
    })
}

/// Refuse maps traced for another scene, unless `force`.
pub fn check_scene(
    maps: &PhotonMaps,
    path: &Path,
    scene_name: &str,
    scene_hash: u64,
    force: bool,
) -> Result<()> {
    if force || maps.scene_hash == scene_hash {
        return Ok(());
    }
    Err(Error::PhotonMapSceneMismatch {
        path: PathBuf::from(path),
        traced_for: maps.scene_name.clone(),
        scene: scene_name.to_owned(),
    })
}
