//! Catmull–Clark subdivision (Catmull & Clark, "Recursively generated B-spline surfaces on
//! arbitrary topological meshes", 1978), for polygon meshes with boundaries.
//!
//! One level turns a face of n sides into n quads. New vertices are laid out as
//! [vertex points (V), edge points (E), face points (F)], so counts follow
//! V' = V + E + F, F' = Σ nᶠ, E' = 2E + Σ nᶠ. Boundary edges use the midpoint and boundary
//! vertices the cubic B-spline curve rule (1/8, 6/8, 1/8), so open surfaces keep their rims.
//! Creased edges follow the same rules (sharp creases, DeRose et al. 1998 with infinite
//! sharpness); a vertex on three or more sharp edges is a corner and stays put.

use super::mesh::PolyMesh;
use glam::DVec3;
use std::collections::HashMap;

/// One level of Catmull–Clark subdivision.
pub fn catmull_clark(mesh: &PolyMesh) -> PolyMesh {
    let nv = mesh.positions.len();
    let face_points: Vec<DVec3> = mesh
        .faces
        .iter()
        .map(|f| f.iter().map(|&v| mesh.positions[v as usize]).sum::<DVec3>() / f.len() as f64)
        .collect();
    // Edges in first-seen order, with the faces on each side.
    let mut edge_index: HashMap<(u32, u32), usize> = HashMap::new();
    let mut edges: Vec<((u32, u32), Vec<usize>)> = Vec::new();
    for (fi, f) in mesh.faces.iter().enumerate() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            let key = (a.min(b), a.max(b));
            let e = *edge_index.entry(key).or_insert_with(|| {
                edges.push((key, Vec::new()));
                edges.len() - 1
            });
            edges[e].1.push(fi);
        }
    }
    let sharp =
        |key: &(u32, u32), faces: &Vec<usize>| faces.len() != 2 || mesh.creases.contains(key);
    let mid = |(a, b): (u32, u32)| 0.5 * (mesh.positions[a as usize] + mesh.positions[b as usize]);
    let edge_points: Vec<DVec3> = edges
        .iter()
        .map(|(key, faces)| {
            let key = *key;
            if !sharp(&key, faces) {
                let (a, b) = key;
                (mesh.positions[a as usize]
                    + mesh.positions[b as usize]
                    + face_points[faces[0]]
                    + face_points[faces[1]])
                    / 4.0
            } else {
                mid(key)
            }
        })
        .collect();
    // Per vertex: adjacent faces, adjacent edges, and boundary neighbours.
    let mut vert_faces = vec![Vec::new(); nv];
    for (fi, f) in mesh.faces.iter().enumerate() {
        for &v in f {
            vert_faces[v as usize].push(fi);
        }
    }
    let mut vert_edges = vec![Vec::new(); nv];
    let mut boundary_neighbours = vec![Vec::new(); nv];
    for (key, faces) in &edges {
        let key = *key;
        vert_edges[key.0 as usize].push(key);
        vert_edges[key.1 as usize].push(key);
        if sharp(&key, faces) {
            boundary_neighbours[key.0 as usize].push(key.1);
            boundary_neighbours[key.1 as usize].push(key.0);
        }
    }
    let vertex_points: Vec<DVec3> = (0..nv)
        .map(|v| {
            let p = mesh.positions[v];
            if boundary_neighbours[v].len() == 2 {
                let (a, b) = (boundary_neighbours[v][0], boundary_neighbours[v][1]);
                return 0.75 * p
                    + 0.125 * (mesh.positions[a as usize] + mesh.positions[b as usize]);
            }
            if boundary_neighbours[v].len() > 2 || vert_faces[v].is_empty() {
                return p; // Corners (three or more sharp edges) and loose vertices stay put.
            }
            let n = vert_faces[v].len() as f64;
            let f = vert_faces[v]
                .iter()
                .map(|&fi| face_points[fi])
                .sum::<DVec3>()
                / n;
            let r =
                vert_edges[v].iter().map(|&e| mid(e)).sum::<DVec3>() / vert_edges[v].len() as f64;
            (f + 2.0 * r + (n - 3.0) * p) / n
        })
        .collect();
    let e_base = nv as u32;
    let f_base = (nv + edges.len()) as u32;
    let mut out = PolyMesh {
        positions: vertex_points,
        ..PolyMesh::default()
    };
    // Each creased edge splits into two creased halves.
    for &(a, b) in &mesh.creases {
        if let Some(&e) = edge_index.get(&(a, b)) {
            let ep = e_base + e as u32;
            out.creases.insert((a.min(ep), a.max(ep)));
            out.creases.insert((b.min(ep), b.max(ep)));
        }
    }
    out.positions.extend(edge_points);
    out.positions.extend(face_points);
    for (fi, f) in mesh.faces.iter().enumerate() {
        let n = f.len();
        let edge_of = |k: usize| {
            let (a, b) = (f[k % n], f[(k + 1) % n]);
            e_base + edge_index[&(a.min(b), a.max(b))] as u32
        };
        for (k, &corner) in f.iter().enumerate() {
            out.faces.push(vec![
                corner,
                edge_of(k),
                f_base + fi as u32,
                edge_of(k + n - 1),
            ]);
        }
    }
    out
}

/// `levels` levels of Catmull–Clark subdivision.
pub fn subdivide(mesh: &PolyMesh, levels: u32) -> PolyMesh {
    (0..levels).fold(mesh.clone(), |m, _| catmull_clark(&m))
}

/// Limit position of an interior vertex of a quad mesh with valence n (Halstead et al. 1993):
/// (n² P + 4 Σ edge neighbours + Σ diagonal neighbours) / (n (n + 5)).
pub fn limit_position(p: DVec3, edge_neighbours: &[DVec3], diagonal_neighbours: &[DVec3]) -> DVec3 {
    let n = edge_neighbours.len() as f64;
    (n * n * p
        + 4.0 * edge_neighbours.iter().sum::<DVec3>()
        + diagonal_neighbours.iter().sum::<DVec3>())
        / (n * (n + 5.0))
}
