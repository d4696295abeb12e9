//! Procedural models out as Wavefront OBJ (named objects, vertex normals) or ASCII PLY.

use super::atomic::write_file;
use crate::error::Result;
use crate::modeling::PolyMesh;
use std::fmt::Write as _;
use std::path::Path;

/// A named part of a model.
pub struct Part<'a> {
    pub name: &'a str,
    pub mesh: &'a PolyMesh,
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    write_file(path, text)
}

/// OBJ with one `o NAME` per part, positions, smooth vertex normals, and polygon faces.
pub fn write_obj(path: &Path, parts: &[Part]) -> Result<()> {
    let mut s = String::from("# Photon procedural model\n");
    let mut base = 1usize;
    for part in parts {
        let _ = writeln!(s, "o {}", part.name);
        for p in &part.mesh.positions {
            let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
        }
        for n in part.mesh.vertex_normals() {
            let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
        }
        for f in &part.mesh.faces {
            s.push('f');
            for &v in f {
                let i = base + v as usize;
                let _ = write!(s, " {i}//{i}");
            }
            s.push('\n');
        }
        base += part.mesh.positions.len();
    }
    write_text(path, &s)
}

/// ASCII PLY of all parts merged (vertices with normals, polygon faces).
pub fn write_ply(path: &Path, parts: &[Part]) -> Result<()> {
    let mut merged = PolyMesh::default();
    for part in parts {
        merged.append(part.mesh);
    }
    let normals = merged.vertex_normals();
    let mut s = format!(
        "ply\nformat ascii 1.0\ncomment Photon procedural model: {}\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        parts.iter().map(|p| p.name).collect::<Vec<_>>().join(", "),
        merged.positions.len(),
        merged.faces.len()
    );
    for (p, n) in merged.positions.iter().zip(&normals) {
        let _ = writeln!(s, "{} {} {} {} {} {}", p.x, p.y, p.z, n.x, n.y, n.z);
    }
    for f in &merged.faces {
        let _ = write!(s, "{}", f.len());
        for v in f {
            let _ = write!(s, " {v}");
        }
        s.push('\n');
    }
    write_text(path, &s)
}
