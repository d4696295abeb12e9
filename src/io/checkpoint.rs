//! Progressive-render checkpoints and partial renders (`.checkpoint`, `.part`): everything a
//! render needs to continue, or to be merged, bit for bit.
//!
//! ```text
//! "PHOTONCK" | version u32 | header length u32 | JSON header (scene, settings, passes)
//! | per pixel: SPPM 8 × f64 (r², N, τ rgb, direct rgb) or PPM 3 × i128 (fixed-point sums)
//! | FNV-1a 64 checksum of everything before it
//! ```
//! [`super::container`]'s layout; written atomically.

use super::atomic::write_file;
use super::container::{self, Contents, Format};
use crate::error::{Error, Result};
use crate::film::FixedRgb;
use crate::progressive::{Method, Pixels, ProgressiveConfig, ProgressiveState, SppmPixel};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// 2: PPM sums are 128-bit (they were 64-bit and wrapped).
pub const CHECKPOINT_VERSION: u32 = 2;
/// The container of checkpoints and PPM parts.
const CHECKPOINT: Format = Format {
    magic: b"PHOTONCK",
    version: CHECKPOINT_VERSION,
    fixed_words: 0,
    max_header: 1 << 20,
    noun: "checkpoint",
};

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Header {
    method: String,
    width: u32,
    height: u32,
    seed: u64,
    alpha: f64,
    photons_per_pass: u64,
    initial_radius: Option<f32>,
    max_depth: u32,
    light_samples: u32,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    spectral: bool,
    scene: String,
    scene_hash: String,
    first_pass: u64,
    passes: u64,
    #[serde(default)]
    output: Option<String>,
    #[serde(default)]
    target_passes: Option<u64>,
    #[serde(default)]
    exposure: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    env: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    env_rotate: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    env_intensity: Option<f32>,
}

/// How the run that wrote a checkpoint was set up, so `--resume` can carry on alone.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunInfo {
    /// The output image, absolute (a relative one failed to resume from another folder).
    pub output: Option<std::path::PathBuf>,
    pub target_passes: Option<u64>,
    /// The PNG exposure the run was asked for, which `--resume` keeps.
    pub exposure: Option<f32>,
    /// The environment light the run's command line gave or changed: part of the scene, so
    /// `--resume` applies it again.
    pub env: EnvSettings,
}

/// `--env`, `--env-rotate`, `--env-intensity` as given (a sky file's path absolute).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EnvSettings {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sky: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotate_deg: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intensity: Option<f32>,
}

fn bad(path: &Path, m: impl Into<String>) -> Error {
    Error::BadCheckpoint {
        path: path.to_owned(),
        message: m.into(),
    }
}

/// A pixel's size in the body: SPPM 8 × f64, PPM 3 × i128.
fn bytes_per_pixel(method: Method) -> usize {
    match method {
        Method::Sppm => 64,
        Method::Ppm | Method::Vcm | Method::Bdpt | Method::LightTrace => 48,
    }
}

pub fn save(state: &ProgressiveState, path: &Path) -> Result<()> {
    save_with(state, &RunInfo::default(), path)
}

/// Save with the run's output path and target pass count.
pub fn save_with(state: &ProgressiveState, info: &RunInfo, path: &Path) -> Result<()> {
    let c = &state.config;
    let header = Header {
        method: c.method.name().into(),
        width: c.width,
        height: c.height,
        seed: c.seed,
        alpha: c.alpha,
        photons_per_pass: c.photons_per_pass,
        initial_radius: c.initial_radius,
        max_depth: c.max_depth,
        light_samples: c.light_samples,
        spectral: c.spectral,
        scene: state.scene_name.clone(),
        scene_hash: format!("{:016x}", state.scene_hash),
        first_pass: state.first_pass,
        passes: state.passes,
        output: info
            .output
            .as_ref()
            .map(|p| p.to_string_lossy().into_owned()),
        target_passes: info.target_passes,
        exposure: info.exposure,
        env: info.env.sky.clone(),
        env_rotate: info.env.rotate_deg,
        env_intensity: info.env.intensity,
    };
    let body_len = bytes_per_pixel(c.method) * c.width as usize * c.height as usize;
    let bytes = container::encode(&CHECKPOINT, &[], &header, body_len, |out| {
        match &state.pixels {
            Pixels::Sppm(pixels) => {
                for p in pixels {
                    for v in [
                        p.r2,
                        p.n,
                        p.tau[0],
                        p.tau[1],
                        p.tau[2],
                        p.direct[0],
                        p.direct[1],
                        p.direct[2],
                    ] {
                        out.extend_from_slice(&v.to_le_bytes());
                    }
                }
            }
            Pixels::Ppm(pixels) => {
                for p in pixels {
                    for v in p.0 {
                        out.extend_from_slice(&v.to_le_bytes());
                    }
                }
            }
        }
    });
    write_file(path, &bytes)
}

pub fn load(path: &Path) -> Result<ProgressiveState> {
    load_with(path).map(|(s, _)| s)
}

/// Load a checkpoint and the run information saved with it.
pub fn load_with(path: &Path) -> Result<(ProgressiveState, RunInfo)> {
    let bytes = crate::io::input::read_file(path)?;
    decode_with(&bytes).map_err(|m| bad(path, m))
}

/// [`load_with`] on bytes in memory; the error is the reason, without the path.
pub fn decode_with(bytes: &[u8]) -> std::result::Result<(ProgressiveState, RunInfo), String> {
    let Contents {
        header: hd,
        body: data,
        ..
    } = container::decode::<Header>(&CHECKPOINT, bytes)?;
    let Some(method) = Method::from_name(&hd.method) else {
        return Err(format!("unknown method '{}'", hd.method));
    };
    let pixels = hd.width as usize * hd.height as usize;
    if Some(data.len()) != pixels.checked_mul(bytes_per_pixel(method)) {
        return Err(format!(
            "{} bytes of pixel data for {}×{} pixels",
            data.len(),
            hd.width,
            hd.height
        ));
    }
    let scene_hash =
        u64::from_str_radix(&hd.scene_hash, 16).map_err(|_| "bad scene hash".to_string())?;
    let config = ProgressiveConfig {
        method,
        width: hd.width,
        height: hd.height,
        seed: hd.seed,
        alpha: hd.alpha,
        photons_per_pass: hd.photons_per_pass,
        initial_radius: hd.initial_radius,
        max_depth: hd.max_depth,
        light_samples: hd.light_samples,
        spectral: hd.spectral,
    };
    config.validate().map_err(|e| e.to_string())?;
    let info = RunInfo {
        output: hd.output.map(std::path::PathBuf::from),
        target_passes: hd.target_passes,
        exposure: hd.exposure,
        env: EnvSettings {
            sky: hd.env,
            rotate_deg: hd.env_rotate,
            intensity: hd.env_intensity,
        },
    };
    let pixels = match method {
        Method::Sppm => Pixels::Sppm(
            data.chunks_exact(64)
                .map(|px| {
                    let v =
                        |k: usize| f64::from_le_bytes(px[k * 8..k * 8 + 8].try_into().expect("8"));
                    SppmPixel {
                        r2: v(0),
                        n: v(1),
                        tau: [v(2), v(3), v(4)],
                        direct: [v(5), v(6), v(7)],
                    }
                })
                .collect(),
        ),
        Method::Ppm | Method::Vcm | Method::Bdpt | Method::LightTrace => Pixels::Ppm(
            data.chunks_exact(48)
                .map(|px| {
                    let v = |k: usize| {
                        i128::from_le_bytes(px[k * 16..k * 16 + 16].try_into().expect("16"))
                    };
                    FixedRgb([v(0), v(1), v(2)])
                })
                .collect(),
        ),
    };
    let state = ProgressiveState {
        config,
        scene_name: hd.scene,
        scene_hash,
        first_pass: hd.first_pass,
        passes: hd.passes,
        pixels,
        buffers: Default::default(),
    };
    Ok((state, info))
}
