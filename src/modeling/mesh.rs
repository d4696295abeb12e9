//! Polygon meshes for modelling: any number of sides per face, double precision.

use glam::DVec3;
use std::collections::HashMap;

/// A polygon mesh. Faces list vertex indices counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyMesh {
    pub positions: Vec<DVec3>,
    pub faces: Vec<Vec<u32>>,
    /// Sharp (infinitely creased) edges, as (smaller, larger) vertex index pairs: subdivision
    /// treats them like boundaries, so they stay sharp.
    pub creases: std::collections::HashSet<(u32, u32)>,
}

/// How many faces use each undirected edge.
pub fn edge_use(faces: &[Vec<u32>]) -> HashMap<(u32, u32), u32> {
    let mut uses = HashMap::new();
    for f in faces {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

impl PolyMesh {
    pub fn edge_count(&self) -> usize {
        edge_use(&self.faces).len()
    }

    /// Every edge is shared by exactly two faces: a closed surface without cracks.
    pub fn is_watertight(&self) -> bool {
        edge_use(&self.faces).values().all(|&n| n == 2)
    }

    /// Signed volume by the divergence theorem (positive when faces wind outward).
    pub fn signed_volume(&self) -> f64 {
        let mut v = 0.0;
        for f in &self.faces {
            let p0 = self.positions[f[0] as usize];
            for k in 1..f.len() - 1 {
                let (p1, p2) = (
                    self.positions[f[k] as usize],
                    self.positions[f[k + 1] as usize],
                );
                v += p0.dot(p1.cross(p2)) / 6.0;
            }
        }
        v
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        )
    }

    /// Area-weighted vertex normals (smooth shading), unit length.
    pub fn vertex_normals(&self) -> Vec<DVec3> {
        let mut n = vec![DVec3::ZERO; self.positions.len()];
        for f in &self.faces {
            let p0 = self.positions[f[0] as usize];
            let mut fnorm = DVec3::ZERO;
            for k in 1..f.len() - 1 {
                fnorm += (self.positions[f[k] as usize] - p0)
                    .cross(self.positions[f[k + 1] as usize] - p0);
            }
            for &v in f {
                n[v as usize] += fnorm;
            }
        }
        n.into_iter().map(|v| v.normalize_or_zero()).collect()
    }

    /// Fan triangulation of every face.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let mut t = Vec::new();
        for f in &self.faces {
            for k in 1..f.len() - 1 {
                t.push([f[0], f[k], f[k + 1]]);
            }
        }
        t
    }

    pub fn transform(&mut self, m: &glam::DAffine3) {
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
    }

    /// Append another mesh's vertices and faces.
    pub fn append(&mut self, other: &PolyMesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.faces.extend(
            other
                .faces
                .iter()
                .map(|f| f.iter().map(|&i| i + base).collect()),
        );
    }
}
