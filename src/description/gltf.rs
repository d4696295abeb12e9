//! glTF 2.0 (.gltf with its buffers, or .glb): meshes with normals and UVs under the node
//! hierarchy, the first perspective camera, `KHR_lights_punctual` point and spot lights, and
//! metallic-roughness materials mapped onto ours:
//! - `KHR_materials_transmission` > 0 → glass of index `KHR_materials_ior` (1.5);
//! - metallic ≥ 0.5 and roughness < 0.5 → mirror tinted by the base colour;
//! - otherwise diffuse with the base colour (factor × texture), also for rough metals;
//! - emissive factor × `KHR_materials_emissive_strength` > 0 → an area light of that radiance.
//!
//! Whatever cannot be mapped is reported once per kind as a warning. Accessors are checked
//! against their buffers before anything is read, so a malformed file is an error, not a panic.

use super::mesh::{ImportedMaterial, MeshFile, MeshPart, file_error, read_bytes};
use super::source::Diagnostic;
use super::{
    CameraSpec, ColorSpec, EmissionSpec, Intensity, LightSpec, Loaded, MaterialSpec, SceneDesc,
    ShapeKind, ShapeSpec,
};
use crate::error::{Error, Result};
use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::TriangleMesh;
use crate::texture::ImageTexture;
use base64::Engine;
use glam::{Mat3, Mat4};
use gltf::Semantic;
use gltf::accessor::{DataType, Dimensions};
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Luminous efficacy used to turn glTF's photometric light units (candela) into watts.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Image height used when the file's camera gives only an aspect ratio.
pub const DEFAULT_HEIGHT: u32 = 512;

struct Opened {
    path: PathBuf,
    doc: gltf::Document,
    buffers: Vec<Vec<u8>>,
}

/// What reading collects as it goes: warnings (once per kind) and decoded textures.
struct Sink {
    path: PathBuf,
    warnings: BTreeSet<String>,
    textures: HashMap<usize, Arc<ImageTexture>>,
}

impl Sink {
    fn warn(&mut self, message: &str) {
        self.warnings
            .insert(format!("{}: {message}", self.path.display()));
    }
}

/// Import a whole glTF scene: meshes, camera, lights.
pub fn import_scene(path: &Path) -> Result<Loaded> {
    let (g, mut sink) = open(path)?;
    let nodes = scene_nodes(&g)?;
    let mut camera = None;
    let mut lights = Vec::new();
    let mut directional = 0;
    for (node, world) in &nodes {
        if let Some(cam) = node.camera()
            && camera.is_none()
        {
            match cam.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    camera = Some(camera_spec(world, p.yfov(), p.aspect_ratio()));
                }
                gltf::camera::Projection::Orthographic(_) => {
                    sink.warn(
                        "orthographic cameras are not supported; the scene is framed instead",
                    );
                }
            }
        }
        if let Some(light) = node.light() {
            let color = Rgb::from_array(light.color()) * light.intensity() / LUMENS_PER_WATT;
            let position = world.transform_point3(Vec3::ZERO);
            let forward = world.transform_vector3(-Vec3::Z);
            if light.range().is_some() {
                sink.warn("light ranges are ignored (lights fall off with the inverse square)");
            }
            match light.kind() {
                gltf::khr_lights_punctual::Kind::Point => lights.push(LightSpec::Point {
                    position,
                    intensity: Intensity::Intensity(color),
                }),
                gltf::khr_lights_punctual::Kind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => lights.push(LightSpec::Spot {
                    position,
                    look_at: position + forward,
                    intensity: Intensity::Intensity(color),
                    angle_deg: outer_cone_angle.to_degrees(),
                    falloff_deg: (outer_cone_angle - inner_cone_angle).max(0.0).to_degrees(),
                }),
                gltf::khr_lights_punctual::Kind::Directional => directional += 1,
            }
        }
    }
    if directional > 0 {
        sink.warn(&format!(
            "directional lights are not supported; {directional} skipped"
        ));
    }
    // Read the meshes now, so that errors and warnings come out at load time.
    let mut meshes = read_parts(&g, &mut sink, &nodes)?;
    let camera = match camera {
        Some(c) => c,
        None => {
            sink.warn("the file has no perspective camera; the scene is framed from +z");
            frame_camera(&meshes)
        }
    };
    if lights.is_empty()
        && !meshes
            .parts
            .iter()
            .any(|p| p.material.as_ref().is_some_and(|m| m.emission.is_some()))
    {
        sink.warn("the file has no lights and no emissive materials: the image will be black");
    }
    let name = path
        .file_stem()
        .map_or_else(|| "gltf".into(), |s| s.to_string_lossy().into_owned());
    let mut desc = SceneDesc::new(&name, camera);
    desc.base_dir = path.parent().map(Path::to_owned).unwrap_or_default();
    desc.shapes.push(ShapeSpec {
        kind: ShapeKind::MeshFile {
            file: PathBuf::from(path.file_name().unwrap_or_default()),
            smooth: true,
        },
        material: None,
        transform: Vec::new(),
        emission: None,
    });
    desc.lights = lights;
    meshes.warnings.extend(sink.warnings);
    meshes.warnings.sort();
    meshes.warnings.dedup();
    Ok(Loaded {
        desc,
        warnings: meshes.warnings,
    })
}

/// Read every mesh of the file's default scene, node transforms applied.
pub fn read_meshes(path: &Path) -> Result<MeshFile> {
    let (g, mut sink) = open(path)?;
    let nodes = scene_nodes(&g)?;
    read_parts(&g, &mut sink, &nodes)
}

impl Opened {
    fn error(&self, message: impl Into<String>) -> Error {
        file_error(&self.path, message)
    }
}

fn open(path: &Path) -> Result<(Opened, Sink)> {
    let bytes = read_bytes(path)?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| gltf_error(path, &bytes, e))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut buffers = Vec::new();
    for buffer in gltf.document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                file_error(
                    path,
                    "buffer 0 refers to the binary chunk, but the file has none",
                )
            })?,
            gltf::buffer::Source::Uri(uri) => read_uri(path, dir, uri)?,
        };
        if data.len() < buffer.length() {
            return Err(file_error(
                path,
                format!(
                    "buffer {} declares {} bytes but only {} are there",
                    buffer.index(),
                    buffer.length(),
                    data.len()
                ),
            ));
        }
        buffers.push(data);
    }
    let mut warnings = BTreeSet::new();
    for ext in gltf.document.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            warnings.insert(format!(
                "{}: required extension {ext} is not supported; the scene may look wrong",
                path.display()
            ));
        }
    }
    for ext in gltf.document.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) && !IGNORED_EXTENSIONS.contains(&ext) {
            warnings.insert(format!("{}: extension {ext} is ignored", path.display()));
        }
    }
    Ok((
        Opened {
            path: path.to_owned(),
            doc: gltf.document,
            buffers,
        },
        Sink {
            path: path.to_owned(),
            warnings,
            textures: HashMap::new(),
        },
    ))
}

const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
];
/// Extensions whose effect our materials cannot show but which do not change what is lit.
const IGNORED_EXTENSIONS: &[&str] = &["KHR_materials_volume", "KHR_materials_specular"];

fn gltf_error(path: &Path, bytes: &[u8], e: gltf::Error) -> Error {
    match e {
        gltf::Error::Deserialize(json) if !bytes.starts_with(b"glTF") => {
            let text = String::from_utf8_lossy(bytes);
            // serde_json ends its message with " at line L column C"; we show those as a location.
            let message = json.to_string();
            let message = message
                .rsplit_once(" at line ")
                .map_or(message.as_str(), |(m, _)| m)
                .to_owned();
            Error::SceneFile(Box::new(Diagnostic::at_line_column(
                path,
                &text,
                json.line(),
                json.column(),
                format!("invalid glTF JSON: {message}"),
            )))
        }
        gltf::Error::Validation(errors) => {
            let list: Vec<String> = errors
                .iter()
                .take(5)
                .map(|(p, err)| format!("{}: {err}", p.as_str()))
                .collect();
            file_error(path, format!("invalid glTF: {}", list.join("; ")))
        }
        other => file_error(path, format!("cannot read glTF: {other}")),
    }
}

fn read_uri(path: &Path, dir: &Path, uri: &str) -> Result<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .ok_or_else(|| file_error(path, "a data URI is not base64-encoded"))?;
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| file_error(path, format!("a data URI is not valid base64: {e}")));
    }
    let file = dir.join(uri.replace("%20", " "));
    std::fs::read(&file).map_err(|e| {
        file_error(
            path,
            format!("cannot read the buffer or image '{}': {e}", file.display()),
        )
    })
}

/// Nodes of the default (or first) scene with their world transforms, depth first.
fn scene_nodes(g: &Opened) -> Result<Vec<(gltf::Node<'_>, Mat4)>> {
    let Some(scene) = g.doc.default_scene().or_else(|| g.doc.scenes().next()) else {
        return Err(g.error("the file has no scene"));
    };
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node, Mat4, usize)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    stack.reverse();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(g.error("the node hierarchy is deeper than 256 levels (a cycle?)"));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let children: Vec<_> = node.children().map(|c| (c, world, depth + 1)).collect();
        stack.extend(children.into_iter().rev());
        out.push((node, world));
    }
    Ok(out)
}

fn camera_spec(world: &Mat4, yfov: f32, aspect: Option<f32>) -> CameraSpec {
    let position = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(-Vec3::Z).normalize_or(-Vec3::Z);
    let up = world.transform_vector3(Vec3::Y).normalize_or(Vec3::Y);
    let aspect = aspect.filter(|a| *a > 0.0 && a.is_finite()).unwrap_or(1.0);
    CameraSpec {
        position,
        look_at: position + forward,
        up,
        fov_y_deg: yfov.to_degrees(),
        width: ((DEFAULT_HEIGHT as f32 * aspect).round() as u32).max(1),
        height: DEFAULT_HEIGHT,
    }
}

/// A camera on +z looking at the middle of the meshes, far enough to see them all.
fn frame_camera(meshes: &MeshFile) -> CameraSpec {
    let points = meshes.parts.iter().flat_map(|p| p.mesh.positions.iter());
    let (lo, hi) = points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), &p| {
        (a.min(p), b.max(p))
    });
    let (centre, radius) = if lo.x <= hi.x {
        (0.5 * (lo + hi), 0.5 * (hi - lo).length().max(1e-3))
    } else {
        (Vec3::ZERO, 1.0)
    };
    let fov = 40.0f32;
    let distance = radius / (0.5 * fov.to_radians()).sin();
    CameraSpec {
        position: centre + Vec3::Z * distance,
        look_at: centre,
        up: Vec3::Y,
        fov_y_deg: fov,
        width: DEFAULT_HEIGHT,
        height: DEFAULT_HEIGHT,
    }
}

fn read_parts(g: &Opened, sink: &mut Sink, nodes: &[(gltf::Node<'_>, Mat4)]) -> Result<MeshFile> {
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
    let uvs = p.get(&Semantic::TexCoords(0));
    if let Some(t) = &uvs {
        check_accessor(
            g,
            t,
            what,
            &[Dimensions::Vec2],
            &[DataType::F32, DataType::U8, DataType::U16],
        )?;
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
    if let Some(it) = reader.read_tex_coords(0) {
        // glTF's (0, 0) is the image's top-left corner; ours is the bottom-left.
        mesh.uvs = it.into_f32().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect();
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
    Ok(mesh)
}

fn convert_material(g: &Opened, sink: &mut Sink, m: &gltf::Material) -> Result<ImportedMaterial> {
    let name = m.name().map(str::to_owned).unwrap_or_else(|| {
        m.index()
            .map_or("default".into(), |i| format!("material {i}"))
    });
    let pbr = m.pbr_metallic_roughness();
    let [r, gr, b, _] = pbr.base_color_factor();
    let base = Rgb::new(r, gr, b);
    let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
    if m.alpha_mode() != gltf::material::AlphaMode::Opaque {
        sink.warn("alpha blending and masking are ignored (surfaces are opaque)");
    }
    if m.normal_texture().is_some() || m.occlusion_texture().is_some() {
        sink.warn("normal and occlusion maps are ignored");
    }
    if pbr.metallic_roughness_texture().is_some() {
        sink.warn("metallic-roughness textures are ignored (their factors are used)");
    }
    let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
    let spec = if m.index().is_none() {
        // No material: glTF's default is a rough white metal; a grey diffuse is what
        // importers (Blender's among them) show.
        MaterialSpec::Diffuse {
            albedo: ColorSpec::Constant(Rgb::splat(0.8)),
        }
    } else if transmission > 0.0 {
        if transmission < 1.0 {
            sink.warn("partial transmission is rendered as fully transparent glass");
        }
        MaterialSpec::Glass {
            ior: m.ior().unwrap_or(1.5),
            transmittance: base,
        }
    } else if metallic >= 0.5 && roughness < 0.5 {
        if metallic < 1.0 || roughness > 0.0 {
            sink.warn(
                "glossy metals (metallic ≥ 0.5, roughness < 0.5) are rendered as perfect mirrors",
            );
        }
        MaterialSpec::Mirror { reflectance: base }
    } else {
        if metallic > 0.0 {
            sink.warn(
                "rough or partly metallic surfaces are rendered as diffuse with their base colour",
            );
        }
        let albedo = match pbr.base_color_texture() {
            Some(info) => {
                if info.tex_coord() != 0 {
                    sink.warn("textures on texture coordinate sets other than 0 use set 0");
                }
                ColorSpec::Decoded {
                    texture: super::SharedTexture(texture(g, sink, &info.texture())?),
                    tint: base,
                }
            }
            None => ColorSpec::Constant(base),
        };
        MaterialSpec::Diffuse { albedo }
    };
    let emitted = Rgb::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
    if m.emissive_texture().is_some() {
        sink.warn("emissive textures are ignored (the emissive factor is used)");
    }
    let emission = (emitted.max_element() > 0.0).then_some(EmissionSpec::Radiance {
        radiance: emitted,
        two_sided: m.double_sided(),
    });
    Ok(ImportedMaterial {
        name,
        spec,
        emission,
    })
}

fn texture(g: &Opened, sink: &mut Sink, t: &gltf::Texture) -> Result<Arc<ImageTexture>> {
    let image = t.source();
    if let Some(done) = sink.textures.get(&image.index()) {
        return Ok(done.clone());
    }
    let label = g.path.join(format!("images[{}]", image.index()));
    let bytes = match image.source() {
        gltf::image::Source::View { view, .. } => {
            let buffer = g
                .buffers
                .get(view.buffer().index())
                .map_or(&[][..], Vec::as_slice);
            buffer
                .get(view.offset()..view.offset() + view.length())
                .ok_or_else(|| g.error(format!("image {} lies outside its buffer", image.index())))?
                .to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => {
            let dir = g.path.parent().unwrap_or(Path::new("")).to_owned();
            read_uri(&g.path, &dir, uri)?
        }
    };
    let decoded = Arc::new(crate::io::texture::decode_texture(&bytes, &label)?);
    sink.textures.insert(image.index(), decoded.clone());
    Ok(decoded)
}
