//! glTF 2.0 (.gltf with its buffers, or .glb): meshes with normals and two UV sets under the
//! node hierarchy, the first perspective camera, `KHR_lights_punctual` point, spot and
//! directional lights, and
//! metallic-roughness materials mapped onto ours (alpha masks and blending as coverage):
//! - `KHR_materials_transmission` > 0 → glass of index `KHR_materials_ior` (1.5), absorbing
//!   inside by `KHR_materials_volume`'s attenuation where its `thicknessFactor` > 0;
//! - metallic ≥ 0.5 and roughness < 0.5 → mirror tinted by the base colour;
//! - otherwise diffuse with the base colour (factor × texture), also for rough metals;
//! - emissive factor × `KHR_materials_emissive_strength` > 0 → an area light of that radiance.
//!
//! Whatever cannot be mapped is reported once per kind as a warning. Accessors are checked
//! against their buffers before anything is read, so a malformed file is an error, not a panic.
//! Animations are not rendered (the scene is shown as posed) and not read.

mod geometry;
mod material;

use geometry::read_parts;

use super::mesh::{MeshFile, file_error, read_bytes};
use super::source::Diagnostic;
use super::{
    CameraSpec, EnvironmentSpec, Intensity, LightSpec, Loaded, SceneDesc, ShapeKind, ShapeSpec, Sky,
};
use crate::error::{Error, Result};
use crate::math::{Rgb, Vec3};
use crate::texture::ImageTexture;
use base64::Engine;
use glam::Mat4;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Luminous efficacy used to turn glTF's photometric light units (candela) into watts.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Image height used when the file's camera gives only an aspect ratio.
pub const DEFAULT_HEIGHT: u32 = 512;

pub(super) struct Opened {
    pub path: PathBuf,
    pub doc: gltf::Document,
    pub buffers: Vec<Vec<u8>>,
    /// The document's JSON as it is, for what `gltf` does not hand out (the normal texture's
    /// `KHR_texture_transform`).
    pub raw: serde_json::Value,
}

/// What reading collects as it goes: warnings (once per kind) and decoded textures.
pub(super) struct Sink {
    pub path: PathBuf,
    pub warnings: BTreeSet<String>,
    /// Decoded images by (index, linear): colour and data textures decode differently.
    pub textures: HashMap<(usize, bool), Arc<ImageTexture>>,
}

impl Sink {
    pub(super) fn warn(&mut self, message: &str) {
        self.warnings
            .insert(format!("{}: {message}", self.path.display()));
    }
}

/// Radiance of the sky that lights a glTF file with no light of its own: white, so that a
/// surface of albedo ρ open to the whole sky shows about ρ, the look of a viewer's default.
pub const DEFAULT_SKY_RADIANCE: f32 = 1.0;

/// Import a whole glTF scene: meshes, camera, lights.
pub fn import_scene(path: &Path) -> Result<Loaded> {
    let (g, mut sink) = open(path)?;
    let nodes = scene_nodes(&g)?;
    let mut camera = None;
    let mut lights = Vec::new();
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
            if !color.is_finite() || color.min_element() < 0.0 {
                return Err(g.error(format!(
                    "light {} has colour {:?} and intensity {}: both must be finite and not negative",
                    light.index(),
                    light.color(),
                    light.intensity()
                )));
            }
            let position = world.transform_point3(Vec3::ZERO);
            let forward = world.transform_vector3(-Vec3::Z);
            if light.range().is_some() {
                sink.warn("light ranges are ignored (lights fall off with the inverse square)");
            }
            match light.kind() {
                gltf::khr_lights_punctual::Kind::Point => lights.push(LightSpec::Point {
                    position,
                    intensity: Intensity::Intensity(color),
                    spectrum: None,
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
                    spectrum: None,
                }),
                // Illuminance in lux (lm/m²) → irradiance in W/m².
                gltf::khr_lights_punctual::Kind::Directional => {
                    lights.push(LightSpec::Directional {
                        direction: forward,
                        irradiance: color,
                        spectrum: None,
                    })
                }
            }
        }
    }
    // Read the meshes now, so that errors and warnings come out at load time.
    let mut meshes = read_parts(&g, &mut sink, &nodes)?;
    let camera = match camera {
        Some(c) => c,
        None => {
            sink.warn(&format!(
                "the file has no perspective camera; the scene is framed from the front (+z), {FRAMING_ELEVATION_DEG}° above"
            ));
            frame_camera(&meshes)
        }
    };
    let mut default_sky_warning = None;
    if lights.is_empty() {
        let (emitted, sky) = emitted_and_sky_power(&meshes);
        let reason = if emitted <= 0.0 {
            Some("the file has no lights and no emissive materials".to_owned())
        } else if emitted < EMITTERS_LIGHT_SCENE * sky {
            Some(format!(
                "the file has no lights, and its emissive surfaces emit {emitted:.3} W (luminance), {:.1}% of the {sky:.3} W a white sky of radiance {DEFAULT_SKY_RADIANCE} sends onto its surfaces: too little to light it",
                100.0 * emitted / sky
            ))
        } else {
            None
        };
        if let Some(reason) = reason {
            let warning = format!(
                "{}: {reason} (Blender keeps its world lighting out of glTF), so it is lit by a uniform white sky of radiance {DEFAULT_SKY_RADIANCE}; give your own with --env FILE|R,G,B",
                path.display()
            );
            default_sky_warning = Some(warning.clone());
            sink.warnings.insert(warning);
            lights.push(LightSpec::Environment(EnvironmentSpec {
                sky: Sky::Uniform(Rgb::splat(DEFAULT_SKY_RADIANCE)),
                intensity: 1.0,
                rotate_deg: 0.0,
            }));
        }
    }
    let name = path
        .file_stem()
        .map_or_else(|| "gltf".into(), |s| s.to_string_lossy().into_owned());
    let mut desc = SceneDesc::new(&name, camera);
    desc.base_dir = path.parent().map(Path::to_owned).unwrap_or_default();
    desc.origins = crate::description::source::Origins::in_binary_file(path);
    desc.shapes.push(ShapeSpec {
        kind: ShapeKind::MeshFile {
            file: PathBuf::from(path.file_name().unwrap_or_default()),
            smooth: true,
        },
        media: None,
        material: None,
        transform: Vec::new(),
        emission: None,
    });
    desc.lights = lights;
    desc.default_sky_warning = default_sky_warning;
    meshes.warnings.extend(sink.warnings);
    meshes.warnings.sort();
    meshes.warnings.dedup();
    let warnings = std::mem::take(&mut meshes.warnings);
    let mut cache = super::mesh::MeshCache::new();
    cache.insert(
        desc.base_dir.join(path.file_name().unwrap_or_default()),
        std::sync::Arc::new(meshes),
    );
    Ok(Loaded {
        desc,
        warnings,
        meshes: cache,
    })
}

/// Read every mesh of the file's default scene, node transforms applied.
pub fn read_meshes(path: &Path) -> Result<MeshFile> {
    let (g, mut sink) = open(path)?;
    let nodes = scene_nodes(&g)?;
    read_parts(&g, &mut sink, &nodes)
}

impl Opened {
    pub(super) fn error(&self, message: impl Into<String>) -> Error {
        file_error(&self.path, message)
    }
}

fn open(path: &Path) -> Result<(Opened, Sink)> {
    let bytes = read_bytes(path)?;
    check_glb_header(path, &bytes)?;
    let mut warnings = BTreeSet::new();
    let (raw, mut without_animations) = raw_json(&bytes);
    let has_animations = without_animations
        .as_object_mut()
        .and_then(|o| o.remove("animations"))
        .is_some();
    if has_animations {
        warnings.insert(format!(
            "{}: animations are not rendered (the scene is shown as posed) and are not read",
            path.display()
        ));
    }
    let gltf = match gltf::Gltf::from_slice_without_validation(&bytes) {
        Ok(g) => g,
        // `gltf` 1.4 cannot read some valid animations (a `KHR_animation_pointer` channel
        // targets no node); they are not rendered, so the file is read without them.
        Err(gltf::Error::Deserialize(_)) if has_animations => {
            match serde_json::from_value::<gltf::json::Root>(without_animations) {
                Ok(root) => gltf::Gltf {
                    document: gltf::Document::from_json_without_validation(root),
                    blob: gltf::binary::Glb::from_slice(&bytes)
                        .ok()
                        .and_then(|glb| glb.bin.map(|b| b.into_owned())),
                },
                Err(_) => {
                    let e = gltf::Gltf::from_slice_without_validation(&bytes).err();
                    return Err(e.map_or_else(
                        || file_error(path, "cannot read glTF"),
                        |e| gltf_error(path, &bytes, e),
                    ));
                }
            }
        }
        Err(e) => return Err(gltf_error(path, &bytes, e)),
    };
    let json = gltf.document.into_json();
    check_attribute_references(path, &json)?;
    let gltf = gltf::Gltf {
        document: gltf::Document::from_json(json).map_err(|e| gltf_error(path, &bytes, e))?,
        blob: gltf.blob,
    };
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
    for ext in gltf.document.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            warnings.insert(format!(
                "{}: required extension {ext} is not supported; the scene may look wrong",
                path.display()
            ));
        }
    }
    for ext in gltf.document.extensions_used() {
        if SUPPORTED_EXTENSIONS.contains(&ext) {
            continue;
        }
        let what = PARTLY_MAPPED
            .iter()
            .find(|(name, _)| *name == ext)
            .map_or("is ignored", |(_, what)| what);
        warnings.insert(format!("{}: extension {ext} {what}", path.display()));
    }
    Ok((
        Opened {
            path: path.to_owned(),
            doc: gltf.document,
            buffers,
            raw,
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
    "KHR_texture_transform",
    "KHR_materials_specular",
    "KHR_materials_volume",
    "KHR_materials_dispersion",
];
/// Extensions Blender writes routinely, with what of them we cannot show.
const PARTLY_MAPPED: &[(&str, &str)] = &[];

/// A GLB's declared length must cover its 12-byte header and fit the file: `gltf` 1.4
/// subtracts the header size from it unchecked.
fn check_glb_header(path: &Path, bytes: &[u8]) -> Result<()> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let declared = bytes
        .get(8..12)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    match declared {
        Some(n) if (12..=bytes.len()).contains(&n) => Ok(()),
        Some(n) => Err(file_error(
            path,
            format!(
                "the GLB header declares {n} bytes, but the file has {} (and a header is 12)",
                bytes.len()
            ),
        )),
        None => Err(file_error(path, "truncated GLB header")),
    }
}

/// Accessor indices named by mesh attributes and indices must exist. `gltf-json` 1.4's
/// validation indexes the POSITION accessor before checking that it exists, and panics on a
/// file that names one past the end, so this runs first.
fn check_attribute_references(path: &Path, json: &gltf::json::Root) -> Result<()> {
    let count = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (k, p) in mesh.primitives.iter().enumerate() {
            let named = p
                .attributes
                .values()
                .chain(p.indices.as_ref())
                .map(|i| i.value());
            if let Some(bad) = named.into_iter().find(|&i| i >= count) {
                return Err(file_error(
                    path,
                    format!(
                        "mesh {m} primitive {k} names accessor {bad}, but the file has {count} accessors"
                    ),
                ));
            }
        }
    }
    Ok(())
}

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

pub(super) fn read_uri(path: &Path, dir: &Path, uri: &str) -> Result<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .ok_or_else(|| file_error(path, "a data URI is not base64-encoded"))?;
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| file_error(path, format!("a data URI is not valid base64: {e}")));
    }
    let file = dir.join(percent_decode(uri));
    crate::io::input::read_file(&file)
        .map_err(|e| file_error(path, format!("cannot read the buffer or image: {e}")))
}

/// Nodes of the default (or first) scene with their world transforms, depth first.
/// Most node placements a scene's hierarchy may make, and most triangles its meshes may
/// make placed: about 6 GB of scene at 120 bytes a triangle.
const MAX_NODE_INSTANCES: usize = 1_000_000;
const MAX_INSTANCED_TRIANGLES: u64 = 50_000_000;

fn scene_nodes(g: &Opened) -> Result<Vec<(gltf::Node<'_>, Mat4)>> {
    let Some(scene) = g.doc.default_scene().or_else(|| g.doc.scenes().next()) else {
        return Err(g.error("the file has no scene"));
    };
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node, Mat4, usize)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    stack.reverse();
    // Nodes may share children, so a small file can instance a mesh 2⁴⁰ times (a 2 KB file
    // took 3.2 GB before aborting): instances and the triangles they make are counted as the
    // hierarchy is walked, and refused past the limits.
    let mut triangles = 0u64;
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(g.error("the node hierarchy is deeper than 256 levels (a cycle?)"));
        }
        if out.len() >= MAX_NODE_INSTANCES {
            return Err(g.error(format!(
                "the node hierarchy places more than {MAX_NODE_INSTANCES} nodes (nodes that share children instance them again and again)"
            )));
        }
        if let Some(mesh) = node.mesh() {
            triangles += mesh
                .primitives()
                .map(|p| {
                    let n = p
                        .indices()
                        .map(|a| a.count())
                        .or_else(|| p.get(&gltf::Semantic::Positions).map(|a| a.count()));
                    n.unwrap_or(0) as u64 / 3
                })
                .sum::<u64>();
            if triangles > MAX_INSTANCED_TRIANGLES {
                return Err(g.error(format!(
                    "the node hierarchy instances more than {MAX_INSTANCED_TRIANGLES} triangles (nodes that share children instance their meshes again and again)"
                )));
            }
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

/// How far above the horizon a file without a camera is seen from, degrees: from the front
/// and above, as glTF viewers frame a model, so that a floor is seen from above, not edge-on.
pub const FRAMING_ELEVATION_DEG: f32 = 25.0;

/// A camera in front (+z) and [`FRAMING_ELEVATION_DEG`] above the middle of the meshes,
/// looking at it, far enough to see them all.
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
    let (sin, cos) = FRAMING_ELEVATION_DEG.to_radians().sin_cos();
    CameraSpec {
        position: centre + Vec3::new(0.0, sin, cos) * distance,
        look_at: centre,
        up: Vec3::Y,
        fov_y_deg: fov,
        width: DEFAULT_HEIGHT,
        height: DEFAULT_HEIGHT,
    }
}

/// The document's JSON (a GLB's JSON chunk), and a copy to edit; `Null` where it is not JSON
/// (then `gltf`'s own reader reports the error, located).
fn raw_json(bytes: &[u8]) -> (serde_json::Value, serde_json::Value) {
    let json: &[u8] = if bytes.starts_with(b"glTF") {
        match gltf::binary::Glb::from_slice(bytes) {
            Ok(glb) => return both(serde_json::from_slice(&glb.json).ok()),
            Err(_) => &[],
        }
    } else {
        bytes
    };
    both(serde_json::from_slice(json).ok())
}

fn both(value: Option<serde_json::Value>) -> (serde_json::Value, serde_json::Value) {
    let value = value.unwrap_or_default();
    (value.clone(), value)
}

/// A URI reference's path with every `%XX` escape decoded (RFC 3986 §2.1; glTF 2.0 §3.5.2
/// stores relative paths as URI references, so `tex%281%29.png` names `tex(1).png`). A `%`
/// not followed by two hex digits is kept as it is.
pub(super) fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |k: usize| bytes.get(k).and_then(|&b| (b as char).to_digit(16));
        match (bytes[i], hex(i + 1), hex(i + 2)) {
            (b'%', Some(hi), Some(lo)) => {
                out.push((hi * 16 + lo) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Share of a white sky's power above which a file's emissive surfaces are taken to light
/// it: a ceiling light of a room emits tens of percent of it, the glowing details of a model
/// (DamagedHelmet's) about one.
pub const EMITTERS_LIGHT_SCENE: f32 = 0.05;

/// Luminous power (luminance-weighted watts) the file's emissive surfaces emit, π ∫ L dA per
/// emitting side (the emissive texture's mean standing for its values over the surface),
/// and what a uniform sky of [`DEFAULT_SKY_RADIANCE`] sends onto the same surfaces were
/// they all open to it: π L per unit area, over every surface of the file.
fn emitted_and_sky_power(meshes: &MeshFile) -> (f32, f32) {
    let mut emitted = 0.0;
    let mut area_total = 0.0;
    for part in &meshes.parts {
        let m = &part.mesh;
        let area: f32 = m
            .triangles
            .iter()
            .filter(|t| t.iter().all(|&i| (i as usize) < m.positions.len()))
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        area_total += area;
        let Some(super::EmissionSpec::Radiance {
            radiance,
            two_sided,
            texture,
            ..
        }) = part.material.as_ref().and_then(|m| m.emission.as_ref())
        else {
            continue;
        };
        let texture_mean = match texture {
            Some(super::ImageRef::Decoded(t)) if !t.image.texels.is_empty() => {
                t.image.texels.iter().copied().sum::<Rgb>() / t.image.texels.len() as f32
            }
            _ => Rgb::ONE,
        };
        let sides = if *two_sided { 2.0 } else { 1.0 };
        emitted +=
            std::f32::consts::PI * crate::math::luminance(*radiance * texture_mean) * area * sides;
    }
    let sky = std::f32::consts::PI * DEFAULT_SKY_RADIANCE * area_total;
    (emitted, sky)
}
