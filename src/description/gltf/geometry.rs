//! Meshes of the node hierarchy: accessors checked against their buffers, then read.

use super::material::convert_material;
use super::{Opened, Sink};
use crate::description::mesh::{ImportedMaterial, MeshFile, MeshPart};
use crate::error::Result;
use crate::math::{Vec2, Vec3};
use crate::scene::TriangleMesh;
use glam::{Mat3, Mat4};
use gltf::Semantic;
use gltf::accessor::{DataType, Dimensions};
use std::collections::HashMap;

pub(super) fn read_parts(
    g: &Opened,
    sink: &mut Sink,
    nodes: &[(gltf::Node<'_>, Mat4)],
) -> Result<MeshFile> {
    let mut parts = Vec::new();
    let mut materials: HashMap<Option<usize>, ImportedMaterial> = HashMap::new();
    for (node, world) in nodes {
        let Some(mesh) = node.mesh() else { continue };
        let normal_matrix = Mat3::from_mat4(*world).inverse().transpose();
        for (k, primitive) in mesh.primitives().enumerate() {
            let what = format!("mesh {} primitive {k}", mesh.index());
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                sink.warn(
                    "points, lines and triangle strips/fans are not rendered (only triangle lists)",
                );
                continue;
            }
            let mut part = read_primitive(g, &primitive, &what)?;
            for p in &mut part.positions {
                *p = world.transform_point3(*p);
            }
            for n in &mut part.normals {
                *n = (normal_matrix * *n).normalize_or_zero();
            }
            let key = primitive.material().index();
            let material = match materials.get(&key) {
                Some(m) => m.clone(),
                None => {
                    let m = convert_material(g, sink, &primitive.material())?;
                    materials.insert(key, m.clone());
                    m
                }
            };
            parts.push(MeshPart {
                name: node
                    .name()
                    .or(mesh.name())
                    .map_or_else(|| format!("mesh {}", mesh.index()), str::to_owned),
                mesh: part,
                material: Some(material),
            });
        }
    }
    Ok(MeshFile {
        parts,
        warnings: std::mem::take(&mut sink.warnings).into_iter().collect(),
    })
}

/// Check that an accessor fits its buffer view and buffer and has the expected layout, so
/// that reading it cannot run out of bounds.
fn check_accessor(
    g: &Opened,
    a: &gltf::Accessor,
    what: &str,
    dims: &[Dimensions],
    types: &[DataType],
) -> Result<()> {
    let bad = |m: String| g.error(format!("accessor {} ({what}): {m}", a.index()));
    if a.sparse().is_some() {
        return Err(bad("sparse accessors are not supported".into()));
    }
    if !dims.contains(&a.dimensions()) || !types.contains(&a.data_type()) {
        return Err(bad(format!(
            "has type {:?} of {:?}, expected {dims:?} of {types:?}",
            a.dimensions(),
            a.data_type()
        )));
    }
    if a.count() == 0 {
        return Err(bad("has no elements".into()));
    }
    let Some(view) = a.view() else {
        return Err(bad("has no buffer view".into()));
    };
    let element = a.size();
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(bad(format!(
            "its buffer view's stride {stride} is smaller than its {element}-byte elements"
        )));
    }
    let needed = (a.count() as u64 - 1)
        .saturating_mul(stride as u64)
        .saturating_add((a.offset() + element) as u64);
    if needed > view.length() as u64 {
        return Err(bad(format!(
            "{} elements from offset {} need {needed} bytes, but buffer view {} has {}",
            a.count(),
            a.offset(),
            view.index(),
            view.length()
        )));
    }
    let buffer_len = g.buffers.get(view.buffer().index()).map_or(0, Vec::len) as u64;
    if (view.offset() + view.length()) as u64 > buffer_len {
        return Err(bad(format!(
            "buffer view {} ends at byte {}, past the end of its {buffer_len}-byte buffer",
            view.index(),
            view.offset() + view.length()
        )));
    }
    Ok(())
}

fn read_primitive(g: &Opened, p: &gltf::Primitive, what: &str) -> Result<TriangleMesh> {
    let Some(pos) = p.get(&Semantic::Positions) else {
        return Err(g.error(format!("{what} has no POSITION attribute")));
    };
    check_accessor(g, &pos, what, &[Dimensions::Vec3], &[DataType::F32])?;
    let normals = p.get(&Semantic::Normals);
    if let Some(n) = &normals {
        check_accessor(g, n, what, &[Dimensions::Vec3], &[DataType::F32])?;
    }
    let tangents = p.get(&Semantic::Tangents);
    if let Some(t) = &tangents {
        check_accessor(g, t, what, &[Dimensions::Vec4], &[DataType::F32])?;
    }
    for set in [0, 1] {
        if let Some(t) = &p.get(&Semantic::TexCoords(set)) {
            check_accessor(
                g,
                t,
                what,
                &[Dimensions::Vec2],
                &[DataType::F32, DataType::U8, DataType::U16],
            )?;
        }
    }
    if let Some(i) = p.indices() {
        check_accessor(
            g,
            &i,
            what,
            &[Dimensions::Scalar],
            &[DataType::U8, DataType::U16, DataType::U32],
        )?;
    }
    let reader = p.reader(|b| g.buffers.get(b.index()).map(Vec::as_slice));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .map(|it| it.map(Vec3::from_array).collect())
        .unwrap_or_default();
    let n = positions.len();
    let mut mesh = TriangleMesh {
        positions,
        ..TriangleMesh::default()
    };
    if let Some(it) = reader.read_normals() {
        mesh.normals = it.map(Vec3::from_array).collect();
    }
    if let Some(it) = reader.read_tangents() {
        mesh.tangents = it.map(glam::Vec4::from_array).collect();
    }
    // glTF's (0, 0) is the image's top-left corner; ours is the bottom-left.
    if let Some(it) = reader.read_tex_coords(0) {
        mesh.uvs = it.into_f32().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect();
    }
    if let Some(it) = reader.read_tex_coords(1) {
        mesh.second_uvs = it.into_f32().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect();
    }
    let indices: Vec<u32> = match reader.read_indices() {
        Some(it) => it.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(g.error(format!(
            "{what} uses vertex {bad}, but its POSITION accessor has {n} vertices"
        )));
    }
    mesh.triangles = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    if mesh.normals.len() != n {
        mesh.normals.clear();
    }
    if mesh.uvs.len() != n {
        mesh.uvs.clear();
    }
    if mesh.second_uvs.len() != n {
        mesh.second_uvs.clear();
    }
    if mesh.tangents.len() != n {
        mesh.tangents.clear();
    }
    Ok(mesh)
}
