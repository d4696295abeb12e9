//! Lathe (Blender's Screw modifier) and solidify.

use super::mesh::{PolyMesh, edge_use};
use glam::{DVec2, DVec3};
use std::f64::consts::TAU;

/// Revolve a profile of (radius, height) points around the z axis in `steps` steps. Profile
/// points on the axis (radius 0) become a single vertex with a fan of triangles. Faces wind
/// outward when the profile runs upward on the outside (or inward across a bottom).
pub fn lathe(profile: &[DVec2], steps: u32) -> PolyMesh {
    let steps = steps.max(3);
    let mut mesh = PolyMesh::default();
    // Vertex indices of each profile point per step (one shared index on the axis).
    let mut rings: Vec<Vec<u32>> = Vec::new();
    for p in profile {
        if p.x.abs() < 1e-12 {
            mesh.positions.push(DVec3::new(0.0, 0.0, p.y));
            rings.push(vec![(mesh.positions.len() - 1) as u32; steps as usize]);
        } else {
            let start = mesh.positions.len() as u32;
            for s in 0..steps {
                let a = TAU * f64::from(s) / f64::from(steps);
                mesh.positions
                    .push(DVec3::new(p.x * a.cos(), p.x * a.sin(), p.y));
            }
            rings.push((start..start + steps).collect());
        }
    }
    for i in 0..profile.len().saturating_sub(1) {
        for s in 0..steps as usize {
            let t = (s + 1) % steps as usize;
            let (a, b, c, d) = (rings[i][s], rings[i][t], rings[i + 1][t], rings[i + 1][s]);
            let mut face = vec![a, b, c, d];
            face.dedup();
            if face.first() == face.last() && face.len() > 1 {
                face.pop();
            }
            if face.len() >= 3 {
                mesh.faces.push(face);
            }
        }
    }
    mesh
}

/// Give a surface thickness (Blender's Solidify): an inner copy offset by `thickness` against
/// the vertex normals, wound the other way, joined to the outer surface along every boundary
/// edge by a quad. An open surface becomes a closed shell.
pub fn solidify(surface: &PolyMesh, thickness: f64) -> PolyMesh {
    let n = surface.positions.len() as u32;
    let normals = surface.vertex_normals();
    let mut mesh = surface.clone();
    for (p, nrm) in surface.positions.iter().zip(&normals) {
        mesh.positions.push(*p - thickness * *nrm);
    }
    for f in &surface.faces {
        mesh.faces.push(f.iter().rev().map(|&v| v + n).collect());
    }
    let uses = edge_use(&surface.faces);
    for f in &surface.faces {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            if uses[&(a.min(b), a.max(b))] == 1 {
                // Boundary edge a→b of the outer surface: the rim quad runs b→a on the outside.
                mesh.faces.push(vec![b, a, a + n, b + n]);
            }
        }
    }
    mesh
}
