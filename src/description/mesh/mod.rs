//! Mesh files: OBJ (with MTL), PLY, and the meshes of a glTF file, read into triangle meshes
//! with the materials the file gives them.

pub(super) mod obj;
pub(super) mod ply;

use super::source::Diagnostic;
use super::{EmissionSpec, MaterialSpec};
use crate::error::{Error, Result};
use crate::scene::TriangleMesh;
use std::path::Path;

/// Largest mesh accepted from a file, in vertices or triangles: 2³¹, ~100 GB of geometry.
/// Counts declared above it are refused before anything is allocated.
pub const MAX_ELEMENTS: u64 = 1 << 31;

/// A material read from a mesh file.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedMaterial {
    pub name: String,
    pub spec: MaterialSpec,
    pub emission: Option<EmissionSpec>,
}

/// One piece of a mesh file with a single material.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshPart {
    pub name: String,
    /// In the file's coordinates, with the file's own node transforms applied (glTF).
    pub mesh: TriangleMesh,
    pub material: Option<ImportedMaterial>,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshFile {
    pub parts: Vec<MeshPart>,
    /// One message per kind of thing the reader could not map.
    pub warnings: Vec<String>,
}

impl MeshFile {
    pub fn triangle_count(&self) -> usize {
        self.parts.iter().map(|p| p.mesh.triangles.len()).sum()
    }
}

/// Mesh files already read, by path: a file named twice (or read while importing a glTF
/// scene) is parsed once.
pub type MeshCache = std::collections::HashMap<std::path::PathBuf, std::sync::Arc<MeshFile>>;

/// Split a polygon into a triangle fan (exact for the convex polygons files hold).
pub(crate) fn fan(polygon: &[u32], out: &mut Vec<[u32; 3]>) {
    for k in 1..polygon.len().saturating_sub(1) {
        out.push([polygon[0], polygon[k], polygon[k + 1]]);
    }
}

pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    crate::io::input::read_file(path)
}

pub(crate) fn file_error(path: &Path, message: impl Into<String>) -> Error {
    Error::SceneFile(Box::new(Diagnostic::whole_file(path, message)))
}
