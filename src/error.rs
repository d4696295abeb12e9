//! Typed errors of the library. The binary turns them into messages and exit code 2.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(
        "unknown scene '{name}': it is neither a built-in scene ({available}) nor a .toml, .gltf or .glb file"
    )]
    UnknownScene { name: String, available: String },

    /// A problem in a scene, mesh or texture file, located where the format allows.
    #[error("{0}")]
    SceneFile(Box<crate::description::source::Diagnostic>),

    #[error("invalid scene: {0}")]
    InvalidScene(String),

    /// A problem with object `index` of a scene builder (in the order objects were added),
    /// which the scene description maps back to the shape or light that made it.
    #[error("invalid scene: object {index} {message}")]
    InvalidObject { index: usize, message: String },

    #[error("invalid setting: {0}")]
    InvalidSetting(String),

    #[error("cannot write '{path}': {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },

    #[error("cannot read '{path}': {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },

    #[error("'{path}': unsupported image format '{extension}' (expected one of: {expected})")]
    UnsupportedImageFormat {
        path: PathBuf,
        extension: String,
        expected: &'static str,
    },

    #[error("'{path}': {message}")]
    BadImage { path: PathBuf, message: String },

    #[error("'{path}': {message}")]
    BadPhotonMap { path: PathBuf, message: String },

    #[error("'{path}': {message}")]
    BadCheckpoint { path: PathBuf, message: String },

    #[error(
        "'{path}' was traced for scene '{traced_for}', which differs from '{scene}' (use --force to use it anyway)"
    )]
    PhotonMapSceneMismatch {
        path: PathBuf,
        traced_for: String,
        scene: String,
    },
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
