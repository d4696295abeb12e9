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
//! This is [`super::container`]'s layout with two fixed words. Photons are stored in kd-tree
//! order, so loading needs no rebuild.

use super::atomic::write_file;
use super::container::{self, Contents, Format};
use crate::error::{Error, Result};
use crate::photon::{MapKind, Photon, PhotonConfig, PhotonMap, PhotonMaps, TraceStats};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub const FORMAT_VERSION: u32 = 2;
/// The container of `.phm` files; its fixed words are the endianness mark and the photon size.
const PHM: Format = Format {
    magic: b"PHOTONMP",
    version: FORMAT_VERSION,
    fixed_words: 2,
    max_header: 1 << 20,
    noun: "photon-map file",
};
const ENDIAN_MARK: u32 = 0x0102_0304;
const PHOTON_SIZE: usize = std::mem::size_of::<Photon>();

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
    /// Traced with spectral photons (stored, as all photons are, with RGB power).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    spectral: bool,
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

/// Save maps atomically (temporary file, then rename). Maps of a scene with media are
/// refused: the format holds no volume photons.
pub fn save(maps: &PhotonMaps, path: &Path) -> Result<()> {
    if !maps.volume.is_empty() {
        return Err(Error::InvalidScene(
            crate::photon::SAVED_MAPS_AND_MEDIA.into(),
        ));
    }
    let header = Header {
        scene: maps.scene_name.clone(),
        scene_hash: format!("{:016x}", maps.scene_hash),
        photons: maps.config.photons,
        global_photons: maps.config.global_photons,
        max_depth: maps.config.max_depth,
        absorption: maps.config.absorption,
        per_channel: maps.config.per_channel,
        spectral: maps.config.spectral,
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
    let photons = maps.caustic.len() + maps.global.len();
    let bytes = container::encode(
        &PHM,
        &[ENDIAN_MARK, PHOTON_SIZE as u32],
        &header,
        PHOTON_SIZE * photons,
        |out| {
            out.extend_from_slice(bytemuck::cast_slice(maps.caustic.photons()));
            out.extend_from_slice(bytemuck::cast_slice(maps.global.photons()));
        },
    );
    write_file(path, &bytes)
}

/// Load maps saved by [`save`]. Truncated, corrupted or foreign files are errors.
pub fn load(path: &Path) -> Result<PhotonMaps> {
    let bytes = crate::io::input::read_file(path)?;
    decode(&bytes).map_err(|m| bad(path, m))
}

/// [`load`] on bytes in memory; the error is the reason, without the path.
fn decode(bytes: &[u8]) -> std::result::Result<PhotonMaps, String> {
    let contents: Contents<Header> = container::decode(&PHM, bytes)?;
    if contents.fixed[0] != ENDIAN_MARK {
        return Err("written with another byte order".into());
    }
    let size = contents.fixed[1] as usize;
    if size != PHOTON_SIZE {
        return Err(format!(
            "photon records are {size} bytes; expected {PHOTON_SIZE}"
        ));
    }
    let header = contents.header;
    let body = contents.body;
    let expected = header
        .caustic_count
        .checked_add(header.global_count)
        .and_then(|n| usize::try_from(n).ok())
        .and_then(|n| n.checked_mul(PHOTON_SIZE))
        .ok_or("photon counts overflow")?;
    if body.len() != expected {
        return Err(format!(
            "truncated or padded: {} bytes of photons, the header announces {expected}",
            body.len(),
        ));
    }
    let scene_hash =
        u64::from_str_radix(&header.scene_hash, 16).map_err(|_| "bad scene hash in header")?;
    let (caustic, global) = body.split_at(header.caustic_count as usize * PHOTON_SIZE);
    let caustic: Vec<Photon> = bytemuck::pod_collect_to_vec(caustic);
    let global: Vec<Photon> = bytemuck::pod_collect_to_vec(global);
    Ok(PhotonMaps {
        scene_name: header.scene,
        scene_hash,
        config: PhotonConfig {
            photons: header.photons,
            global_photons: header.global_photons,
            max_depth: header.max_depth,
            absorption: header.absorption,
            per_channel: header.per_channel,
            spectral: header.spectral,
            seed: header.seed,
        },
        caustic: PhotonMap::from_tree_order(MapKind::Caustic, caustic, header.caustic_power_scale),
        global: PhotonMap::from_tree_order(MapKind::Global, global, header.global_power_scale),
        volume: Vec::new(),
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
