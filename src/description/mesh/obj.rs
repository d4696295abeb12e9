//! Wavefront OBJ with MTL materials (Kd, Ke, Ni, illum, map_Kd), read by `tobj`. `tobj` does not
//! say where a problem is, so on error the text is scanned again to find the offending line.

use super::{ImportedMaterial, MeshFile, MeshPart, file_error, read_bytes};
use crate::description::source::Diagnostic;
use crate::description::{ColorSpec, EmissionSpec, MaterialSpec};
use crate::error::{Error, Result};
use crate::material::Dispersion;
use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::TriangleMesh;
use std::path::Path;

pub fn read(path: &Path) -> Result<MeshFile> {
    let bytes = read_bytes(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    check_obj(path, &text)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut warnings = Vec::new();
    // The material library is read through the input policy and checked line by line before
    // `tobj` parses it: `tobj` panics on `Kd 1 2` and says nothing of where a problem is.
    let mtl_error = std::cell::RefCell::new(None);
    let (models, materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |mtl| {
        let mtl_path = dir.join(mtl);
        let checked = crate::io::input::read_file(&mtl_path).and_then(|bytes| {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            check_mtl(&mtl_path, &text)
        });
        match checked {
            Ok(text) => tobj::load_mtl_buf(&mut text.as_bytes()),
            Err(e) => {
                let not_found = matches!(&e, Error::Read { source, .. } if source.kind() == std::io::ErrorKind::NotFound);
                if !not_found {
                    *mtl_error.borrow_mut() = Some(e);
                }
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    })
    .map_err(|e| locate(path, &text, &e))?;
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    let materials = match materials {
        Ok(m) => m,
        Err(e) => {
            warnings.push(format!(
                "{}: its material library could not be read ({e}); the scene's material is used",
                path.display()
            ));
            Vec::new()
        }
    };
    let mut parts = Vec::with_capacity(models.len());
    for model in models {
        let m = &model.mesh;
        let positions: Vec<Vec3> = m
            .positions
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect();
        let normals = if m.normals.len() == m.positions.len() {
            m.normals
                .chunks_exact(3)
                .map(|n| Vec3::new(n[0], n[1], n[2]))
                .collect()
        } else {
            Vec::new()
        };
        let uvs = if m.texcoords.len() / 2 == positions.len() {
            m.texcoords
                .chunks_exact(2)
                .map(|t| Vec2::new(t[0], t[1]))
                .collect()
        } else {
            Vec::new()
        };
        let triangles = m
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let material = m
            .material_id
            .and_then(|i| materials.get(i))
            .map(|mtl| convert(mtl, &mut warnings));
        parts.push(MeshPart {
            name: model.name,
            mesh: TriangleMesh {
                positions,
                normals,
                uvs,
                second_uvs: Vec::new(),
                tangents: Vec::new(),
                triangles,
            },
            material,
        });
    }
    warnings.dedup();
    Ok(MeshFile { parts, warnings })
}

/// MTL to our materials: illum 5 (or 3) is a mirror, illum 4, 6, 7 or 9 glass of index Ni;
/// anything else is diffuse with Kd or map_Kd. Ke > 0 makes the surface an emitter of that
/// radiance.
fn convert(m: &tobj::Material, warnings: &mut Vec<String>) -> ImportedMaterial {
    let rgb = |c: Option<[f32; 3]>, default: Rgb| c.map_or(default, Rgb::from_array);
    let spec = match m.illumination_model {
        Some(3 | 5) => MaterialSpec::Mirror {
            reflectance: rgb(m.specular, Rgb::ONE),
        },
        Some(4 | 6 | 7 | 9) => MaterialSpec::Glass {
            ior: m.optical_density.unwrap_or(1.5),
            transmittance: Rgb::ONE,
            alpha: 0.0,
            attenuation: None,
            dispersion: Dispersion::None,
        },
        _ => MaterialSpec::Diffuse {
            albedo: match &m.diffuse_texture {
                // A texture replaces Kd (as in pbrt and Blender's importer).
                Some(t) => ColorSpec::Image {
                    file: t.into(),
                    tint: Rgb::ONE,
                },
                None => ColorSpec::Constant(rgb(m.diffuse, Rgb::splat(0.8))),
            },
        },
    };
    if m.normal_texture.is_some() || m.specular_texture.is_some() {
        warnings
            .push("OBJ: bump, normal and specular maps are not supported and were ignored".into());
    }
    let emission = m
        .emissive
        .map(Rgb::from_array)
        .filter(|e| e.max_element() > 0.0)
        .map(|radiance| EmissionSpec::Radiance {
            radiance,
            two_sided: false,
            texture: None,
            spectrum: None,
        });
    ImportedMaterial {
        name: m.name.clone(),
        spec,
        emission,
    }
}

/// Check an MTL file's numeric statements before `tobj` reads them, and return the text with
/// one-number colours written out as three (the format allows `Kd 0.5`; `tobj` panicked on it,
/// and on `Kd 1 2`, as fuzzing found): colours take one number or three, scalars one, `illum`
/// an integer; every number finite.
fn check_mtl(path: &Path, text: &str) -> Result<String> {
    let mut normalised = String::with_capacity(text.len());
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            normalised.push_str(raw);
            normalised.push('\n');
            continue;
        };
        let args: Vec<&str> = words.collect();
        let at = |msg: String| line_error(path, text, i + 1, msg);
        let numbers = || args.iter().map(|a| a.parse::<f32>()).collect::<Vec<_>>();
        let finite = |n: &[std::result::Result<f32, _>]| {
            n.iter().all(|x| x.as_ref().is_ok_and(|v| v.is_finite()))
        };
        match keyword {
            "Ka" | "Kd" | "Ks" | "Ke" | "Tf" => {
                let n = numbers();
                if !(n.len() == 1 || n.len() == 3) || !finite(&n) {
                    return at(format!(
                        "expected a colour: {keyword} r g b (or one number), finite"
                    ));
                }
                if n.len() == 1 {
                    normalised.push_str(&format!("{keyword} {0} {0} {0}\n", args[0]));
                    continue;
                }
            }
            "Ns" | "Ni" | "d" | "Tr" => {
                let n = numbers();
                if n.len() != 1 || !finite(&n) {
                    return at(format!("expected one finite number after {keyword}"));
                }
            }
            "illum" if args.len() != 1 || args[0].parse::<u32>().is_err() => {
                return at("expected an illumination model: illum N (0 to 10)".into());
            }
            _ => {}
        }
        normalised.push_str(raw);
        normalised.push('\n');
    }
    Ok(normalised)
}

/// An error at line `line` of a file, with the line shown.
fn line_error<T>(path: &Path, text: &str, line: usize, msg: String) -> Result<T> {
    Err(Error::SceneFile(Box::new(Diagnostic::at_line(
        path, text, line, msg,
    ))))
}

/// Turn a `tobj` error into a located diagnostic by finding the first line that causes it.
fn locate(path: &Path, text: &str, e: &tobj::LoadError) -> Error {
    match check_obj(path, text) {
        Err(located) => located,
        Ok(()) => file_error(path, format!("cannot read the OBJ file: {e}")),
    }
}

/// Check an OBJ file's statements before `tobj` reads them: positions, normals and texture
/// coordinates are finite numbers, and every face has three or more vertices whose indices
/// exist (`tobj` accepted `v nan 0 0`, and a face of two vertices vanished without a word).
fn check_obj(path: &Path, text: &str) -> Result<()> {
    let (mut v, mut vt, mut vn) = (0i64, 0i64, 0i64);
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.collect();
        let numbers_ok = |min: usize| {
            args.len() >= min
                && args
                    .iter()
                    .all(|a| a.parse::<f32>().is_ok_and(f32::is_finite))
        };
        let at = |msg: String| line_error(path, text, i + 1, msg);
        match keyword {
            "v" if !numbers_ok(3) => {
                return at("expected a vertex position: v x y z (finite numbers)".into());
            }
            "vn" if !numbers_ok(3) => {
                return at("expected a normal: vn x y z (finite numbers)".into());
            }
            "vt" if !numbers_ok(1) => {
                return at("expected texture coordinates: vt u v (finite numbers)".into());
            }
            "v" => v += 1,
            "vn" => vn += 1,
            "vt" => vt += 1,
            "f" => {
                if args.len() < 3 {
                    return at(format!(
                        "a face needs at least 3 vertices, this one has {}",
                        args.len()
                    ));
                }
                let counts = [
                    (v, "vertex", "vertices"),
                    (vt, "texture coordinate", "texture coordinates"),
                    (vn, "normal", "normals"),
                ];
                for a in &args {
                    for (slot, part) in a.split('/').enumerate() {
                        if part.is_empty() && slot > 0 {
                            continue;
                        }
                        let (Some(&(count, what, plural)), Ok(index)) =
                            (counts.get(slot), part.parse::<i64>())
                        else {
                            return at(format!(
                                "'{a}' is not a face vertex; expected v, v/vt, v//vn or v/vt/vn indices"
                            ));
                        };
                        let resolved = if index < 0 { count + index + 1 } else { index };
                        if index == 0 || resolved < 1 || resolved > count {
                            return at(format!(
                                "{what} index {index} is out of range: {count} {plural} are defined before this line"
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}
