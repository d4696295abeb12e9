//! PLY meshes (ASCII and binary), read by `ply-rs-bw`: vertex positions, optional normals
//! (nx ny nz) and texture coordinates (u v, s t or texture_u texture_v), polygon faces
//! (vertex_indices or vertex_index) split into triangles.

use super::{MAX_ELEMENTS, MeshFile, MeshPart, fan, file_error, read_bytes};
use crate::error::Result;
use crate::math::{Vec2, Vec3};
use crate::scene::TriangleMesh;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    Encoding, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};
use std::path::Path;

/// One vertex as read: position, normal, texture coordinates, and which of them were present.
#[derive(Clone, Copy, Default)]
struct Vertex {
    values: [f32; 8],
    /// Bit k set when `values[k]` was given.
    given: u8,
}

const POSITION: u8 = 0b111;
const NORMAL: u8 = 0b111_000;
const UV: u8 = 0b11_000_000;

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, p: Property) -> PropertyAccessResult {
        let slot = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            "nx" => 3,
            "ny" => 4,
            "nz" => 5,
            "u" | "s" | "texture_u" | "texture_s" => 6,
            "v" | "t" | "texture_v" | "texture_t" => 7,
            _ => return PropertyAccessResult::Ignored,
        };
        match scalar(&p) {
            Some(x) => {
                self.values[slot] = x;
                self.given |= 1 << slot;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::Ignored,
        }
    }
}

/// One face as read: its vertex indices (`None` if the list was missing or negative).
#[derive(Clone, Default)]
struct Face {
    indices: Option<Vec<u32>>,
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, p: Property) -> PropertyAccessResult {
        if matches!(name, "vertex_indices" | "vertex_index") {
            self.indices = index_list(&p);
            PropertyAccessResult::Set
        } else {
            PropertyAccessResult::Ignored
        }
    }
}

/// Elements other than vertices and faces: read past, kept nowhere.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

pub fn read(path: &Path) -> Result<MeshFile> {
    let bytes = read_bytes(path)?;
    let mut reader = Reader::new(std::io::Cursor::new(&bytes[..]));
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| file_error(path, format!("not a valid PLY header: {e}")))?;
    let header_end = reader.get_ref().position() as usize;
    let payload_bytes = (bytes.len() - header_end) as u64;
    let locate = |element: &str, index: usize, message: String| {
        locate(path, &bytes, header_end, &header, element, index, message)
    };
    check_sizes(path, &header, payload_bytes)?;
    let bad_data = |e: ply_rs_bw::parser::ParseError| {
        file_error(path, format!("cannot read the PLY data: {e}"))
    };
    // Elements are read in file order, each with a type that keeps only what we use.
    let (mut vertices, mut faces) = (Vec::new(), Vec::new());
    for (name, def) in &header.elements {
        match name.as_str() {
            "vertex" => {
                vertices = Parser::<Vertex>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(bad_data)?;
            }
            "face" => {
                faces = Parser::<Face>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(bad_data)?;
            }
            _ => {
                Parser::<Skip>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(bad_data)?;
            }
        }
    }
    let all = |mask: u8| vertices.iter().all(|v| v.given & mask == mask);
    if let Some(i) = vertices.iter().position(|v| v.given & POSITION != POSITION) {
        return Err(locate(
            "vertex",
            i,
            format!("vertex {i} has no numeric x, y and z properties"),
        ));
    }
    let positions: Vec<Vec3> = vertices
        .iter()
        .map(|v| Vec3::new(v.values[0], v.values[1], v.values[2]))
        .collect();
    let normals = if all(NORMAL) {
        vertices
            .iter()
            .map(|v| Vec3::new(v.values[3], v.values[4], v.values[5]))
            .collect()
    } else {
        Vec::new()
    };
    let uvs = if all(UV) {
        vertices
            .iter()
            .map(|v| Vec2::new(v.values[6], v.values[7]))
            .collect()
    } else {
        Vec::new()
    };
    drop(vertices);
    let mut triangles = Vec::with_capacity(faces.len());
    for (k, f) in faces.iter().enumerate() {
        let Some(list) = &f.indices else {
            return Err(locate(
                "face",
                k,
                format!("face {k} has no vertex_indices list of non-negative integers"),
            ));
        };
        if let Some(&bad) = list.iter().find(|&&i| i as usize >= positions.len()) {
            return Err(locate(
                "face",
                k,
                format!(
                    "face {k} uses vertex {bad}, but the file has {} vertices",
                    positions.len()
                ),
            ));
        }
        fan(list, &mut triangles);
    }
    if triangles.is_empty() {
        return Err(file_error(path, "the PLY file has no faces"));
    }
    Ok(MeshFile {
        parts: vec![MeshPart {
            name: path
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
            mesh: TriangleMesh {
                positions,
                normals,
                uvs,
                second_uvs: Vec::new(),
                tangents: Vec::new(),
                triangles,
            },
            material: None,
        }],
        warnings: Vec::new(),
    })
}

/// An error about element `index` of `element`: at its line in an ASCII file, else for the
/// whole (binary) file.
fn locate(
    path: &Path,
    bytes: &[u8],
    header_end: usize,
    header: &Header,
    element: &str,
    index: usize,
    message: String,
) -> crate::error::Error {
    if header.encoding != Encoding::Ascii {
        return file_error(path, message);
    }
    let before: usize = header
        .elements
        .iter()
        .take_while(|(name, _)| name.as_str() != element)
        .map(|(_, d)| d.count)
        .sum();
    let header_lines = bytes[..header_end].iter().filter(|&&b| b == b'\n').count();
    let text = String::from_utf8_lossy(bytes);
    let line = header_lines + before + index + 1;
    crate::error::Error::SceneFile(Box::new(crate::description::source::Diagnostic::at_line(
        path, &text, line, message,
    )))
}

/// Refuse declared element counts the file cannot hold (or that would need absurd memory)
/// before anything is allocated: each element needs at least its fixed-size properties in
/// binary, or two characters in ASCII.
fn check_sizes(path: &Path, header: &Header, payload_bytes: u64) -> Result<()> {
    let mut needed: u64 = 0;
    for (name, def) in &header.elements {
        let count = def.count as u64;
        if count > MAX_ELEMENTS {
            return Err(file_error(
                path,
                format!(
                    "the header declares {count} '{name}' elements; at most {MAX_ELEMENTS} are accepted"
                ),
            ));
        }
        let per_element: u64 = match header.encoding {
            Encoding::Ascii => 2,
            Encoding::BinaryBigEndian | Encoding::BinaryLittleEndian => def
                .properties
                .values()
                .map(|p| match &p.data_type {
                    PropertyType::Scalar(s) => scalar_size(s),
                    PropertyType::List(count, _) => scalar_size(count),
                })
                .sum::<u64>()
                .max(1),
        };
        needed = needed.saturating_add(count.saturating_mul(per_element));
    }
    if needed > payload_bytes {
        let counts: Vec<String> = header
            .elements
            .iter()
            .map(|(n, d)| format!("{} {n}", d.count))
            .collect();
        return Err(file_error(
            path,
            format!(
                "the header declares {} elements, which need at least {needed} bytes, but only {payload_bytes} bytes follow the header (truncated file?)",
                counts.join(" and ")
            ),
        ));
    }
    Ok(())
}

fn scalar_size(s: &ScalarType) -> u64 {
    match s {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

fn scalar(p: &Property) -> Option<f32> {
    Some(match *p {
        Property::Float(x) => x,
        Property::Double(x) => x as f32,
        Property::Char(x) => f32::from(x),
        Property::UChar(x) => f32::from(x),
        Property::Short(x) => f32::from(x),
        Property::UShort(x) => f32::from(x),
        Property::Int(x) => x as f32,
        Property::UInt(x) => x as f32,
        _ => return None,
    })
}

fn index_list(p: &Property) -> Option<Vec<u32>> {
    let non_negative = |v: Vec<i64>| v.into_iter().map(|i| u32::try_from(i).ok()).collect();
    match p {
        Property::ListUInt(v) => Some(v.clone()),
        Property::ListInt(v) => non_negative(v.iter().map(|&i| i64::from(i)).collect()),
        Property::ListUShort(v) => Some(v.iter().map(|&i| u32::from(i)).collect()),
        Property::ListShort(v) => non_negative(v.iter().map(|&i| i64::from(i)).collect()),
        Property::ListUChar(v) => Some(v.iter().map(|&i| u32::from(i)).collect()),
        Property::ListChar(v) => non_negative(v.iter().map(|&i| i64::from(i)).collect()),
        _ => None,
    }
}
