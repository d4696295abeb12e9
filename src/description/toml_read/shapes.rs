//! Shapes, emission, inline meshes, transforms and lights.

use super::scene::bad_type;
use super::values::{Cx, Table, Value, array, float, floats, integer, vec3};
use crate::description::{
    EmissionSpec, EnvironmentSpec, ImageRef, Intensity, LightSpec, LightSpectrum, ShapeKind,
    ShapeSpec, Sky, TransformStep,
};
use crate::error::Result;
use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::TriangleMesh;
use toml::de::DeValue;

const SHAPE_TYPES: &[&str] = &["sphere", "disk", "quad", "box", "mesh", "triangles", "pot"];

/// Keys each shape type takes, besides the common ones.
pub(super) fn shape_keys(kind: &str) -> &'static [&'static str] {
    match kind {
        "sphere" => &["center", "radius"],
        "disk" => &["center", "normal", "radius"],
        "quad" => &["vertices"],
        "box" => &["min", "max"],
        "mesh" => &["file", "smooth"],
        "triangles" => &["positions", "indices", "normals", "uvs"],
        "pot" => &["subdivisions", "seed", "soil_material", "leaf_material"],
        _ => &[],
    }
}

/// The names a shape may refer to: the file's materials and media.
pub(super) struct Names<'a> {
    pub materials: &'a [&'a str],
    pub media: &'a [&'a str],
}

pub(super) fn shape(t: &Table, names: &Names, is_light: bool) -> Result<ShapeSpec> {
    let kind_name = t.req_str("type")?;
    if !SHAPE_TYPES.contains(&kind_name) {
        let mut all = SHAPE_TYPES.to_vec();
        if is_light {
            all.extend(["point", "spot", "directional"]);
        }
        return Err(bad_type(t, kind_name, &all));
    }
    let mut allowed = vec!["type", "material", "transform"];
    if is_light {
        allowed.extend(["radiance", "power", "two_sided", "texture"]);
        allowed.extend(SPECTRUM_KEYS);
    } else {
        allowed.extend(["emission", "interior", "exterior"]);
    }
    allowed.extend_from_slice(shape_keys(kind_name));
    t.allow(&allowed)?;
    let kind = match kind_name {
        "sphere" => ShapeKind::Sphere {
            center: t.opt_vec3("center")?.unwrap_or(Vec3::ZERO),
            radius: t.positive("radius")?,
        },
        "disk" => ShapeKind::Disk {
            center: t.opt_vec3("center")?.unwrap_or(Vec3::ZERO),
            normal: nonzero(t, "normal", Vec3::Z)?,
            radius: t.positive("radius")?,
        },
        "quad" => {
            let v = t.required("vertices")?;
            let what = t.label("vertices");
            let items = array(t.cx, v, &what)?;
            if items.len() != 4 {
                return Err(t.cx.err(v.span(), format!("{what} must list 4 points")));
            }
            let mut vertices = [Vec3::ZERO; 4];
            for (o, item) in vertices.iter_mut().zip(items) {
                *o = vec3(t.cx, item, &what)?;
            }
            ShapeKind::Quad { vertices }
        }
        "box" => {
            let (min, max) = (t.req_vec3("min")?, t.req_vec3("max")?);
            if !min.cmplt(max).all() {
                return Err(t.cx.err(
                    t.span.start..t.span.start + 1,
                    format!("{}: 'min' must be below 'max' on every axis", t.what),
                ));
            }
            ShapeKind::Box { min, max }
        }
        "mesh" => ShapeKind::MeshFile {
            file: t.cx.file(t.required("file")?, "mesh file")?,
            smooth: t.opt_bool("smooth")?.unwrap_or(true),
        },
        "triangles" => ShapeKind::Triangles(inline_mesh(t)?),
        _ => ShapeKind::Pot {
            subdivisions: t.opt_int("subdivisions", 4)?.unwrap_or(2) as u32,
            seed: t.opt_int("seed", i64::MAX as u64)?.unwrap_or(0),
            soil_material: t.material_ref("soil_material", names.materials)?,
            leaf_material: t.material_ref("leaf_material", names.materials)?,
        },
    };
    let material = t.material_ref("material", names.materials)?;
    let media = super::media::sides(t, names.media)?;
    let emission = if is_light {
        Some(emission(t)?)
    } else {
        match t.get("emission") {
            Some(v) => {
                let et = t.cx.table(v, &t.label("emission"))?;
                et.allow(&[
                    "radiance",
                    "power",
                    "two_sided",
                    "texture",
                    "temperature",
                    "illuminant",
                ])?;
                Some(emission(&et)?)
            }
            None => None,
        }
    };
    let invisible_boundary = media.as_ref().is_some_and(|m| m.interior.is_some());
    let needs_material = !is_light
        && emission.is_none()
        && !invisible_boundary
        && !matches!(kind, ShapeKind::MeshFile { .. });
    if needs_material && material.is_none() {
        return Err(t.cx.err(
            t.span.start..t.span.start + 1,
            format!(
                "{} needs a 'material' (or an 'interior' medium, to be an invisible boundary)",
                t.what
            ),
        ));
    }
    let transform = match t.get("transform") {
        Some(v) => transform(t.cx, v)?,
        None => Vec::new(),
    };
    Ok(ShapeSpec {
        kind,
        material,
        transform,
        emission,
        media,
    })
}

pub(super) fn nonzero(t: &Table, key: &str, default: Vec3) -> Result<Vec3> {
    let v = t.opt_vec3(key)?.unwrap_or(default);
    if v.length_squared() == 0.0 {
        let span = t.get(key).map_or(t.span.clone(), |v| v.span());
        return Err(t.cx.err(span, format!("{} must not be zero", t.label(key))));
    }
    Ok(v)
}

pub(super) fn emission(t: &Table) -> Result<EmissionSpec> {
    let two_sided = t.opt_bool("two_sided")?.unwrap_or(false);
    let texture = t
        .get("texture")
        .map(|v| t.cx.file(v, &t.label("texture")).map(ImageRef::File))
        .transpose()?;
    if texture.is_some() && t.get("power").is_some() {
        return Err(t.cx.err(
            t.get("texture").map_or(0..0, |v| v.span()),
            "an emission 'texture' multiplies 'radiance'; give 'radiance', not 'power'",
        ));
    }
    match (t.opt_color("radiance")?, t.opt_color("power")?) {
        (Some(radiance), None) => Ok(EmissionSpec::Radiance {
            radiance,
            two_sided,
            texture,
            spectrum: light_spectrum(t, "radiance", radiance)?,
        }),
        (None, Some(power)) => Ok(EmissionSpec::Power {
            power,
            two_sided,
            spectrum: light_spectrum(t, "power", power)?,
        }),
        (Some(_), Some(_)) => Err(t.cx.err(
            t.get("power").map_or(0..0, |v| v.span()),
            format!("{} gives both 'radiance' and 'power'; give one", t.what),
        )),
        (None, None) => Err(t.cx.err(
            t.span.start..t.span.start + 1,
            format!("{} needs 'radiance' (W·m⁻²·sr⁻¹) or 'power' (W)", t.what),
        )),
    }
}

/// The keys that give a light's colour as a spectrum instead of RGB.
pub(super) const SPECTRUM_KEYS: [&str; 2] = ["temperature", "illuminant"];

/// A light's `temperature` (kelvin: a blackbody) or `illuminant` ("D65", "A"), if it has one;
/// then its brightness, `key`'s value `rgb`, must be one number (grey).
fn light_spectrum(t: &Table, key: &str, rgb: Rgb) -> Result<Option<LightSpectrum>> {
    let spectrum = match (t.get("temperature"), t.get("illuminant")) {
        (None, None) => return Ok(None),
        (Some(_), Some(v)) => {
            return Err(t.cx.err(
                v.span(),
                format!(
                    "{} gives both 'temperature' and 'illuminant'; give one",
                    t.what
                ),
            ));
        }
        (Some(v), None) => {
            let k = t.positive("temperature")?;
            if !LightSpectrum::KELVIN.contains(&k) {
                return Err(t.cx.err(
                    v.span(),
                    format!(
                        "{} must be between {} and {} kelvin",
                        t.label("temperature"),
                        LightSpectrum::KELVIN.start(),
                        LightSpectrum::KELVIN.end()
                    ),
                ));
            }
            LightSpectrum::Blackbody(k)
        }
        (None, Some(v)) => {
            let name = t.req_str("illuminant")?;
            LightSpectrum::named(name).ok_or_else(|| {
                t.cx.err(
                    v.span(),
                    format!(
                        "{}: unknown illuminant '{name}' (expected D65 or A)",
                        t.label("illuminant")
                    ),
                )
            })?
        }
    };
    if rgb.x != rgb.y || rgb.y != rgb.z {
        return Err(t.cx.err(
            t.get(key).map_or(0..0, |v| v.span()),
            format!(
                "{} is the brightness of a light whose colour is its spectrum: give one number",
                t.label(key)
            ),
        ));
    }
    Ok(Some(spectrum))
}

pub(super) fn inline_mesh(t: &Table) -> Result<TriangleMesh> {
    let list = |key: &str| -> Result<&[Value]> {
        match t.get(key) {
            Some(v) => array(t.cx, v, &t.label(key)),
            None => Ok(&[]),
        }
    };
    let what = |key: &str| t.label(key);
    let positions = list("positions")?
        .iter()
        .map(|v| vec3(t.cx, v, &what("positions")))
        .collect::<Result<Vec<_>>>()?;
    let normals = list("normals")?
        .iter()
        .map(|v| vec3(t.cx, v, &what("normals")))
        .collect::<Result<Vec<_>>>()?;
    let uvs = list("uvs")?
        .iter()
        .map(|v| floats::<2>(t.cx, v, &what("uvs")).map(Vec2::from_array))
        .collect::<Result<Vec<_>>>()?;
    let mut triangles = Vec::new();
    for v in t
        .required("indices")
        .and_then(|v| array(t.cx, v, &what("indices")))?
    {
        let items = array(t.cx, v, &what("indices"))?;
        if items.len() != 3 {
            return Err(t
                .cx
                .err(v.span(), "each entry of 'indices' must be [a, b, c]"));
        }
        let mut tri = [0u32; 3];
        for (o, item) in tri.iter_mut().zip(items) {
            let i = integer(t.cx, item, &what("indices"), u32::MAX as u64)?;
            if i as usize >= positions.len() {
                return Err(t.cx.err(
                    item.span(),
                    format!(
                        "vertex index {i} is out of range: there are {} positions",
                        positions.len()
                    ),
                ));
            }
            *o = i as u32;
        }
        triangles.push(tri);
    }
    for (key, len) in [("normals", normals.len()), ("uvs", uvs.len())] {
        if len != 0 && len != positions.len() {
            return Err(t.cx.err(
                t.get(key).map_or(0..0, |v| v.span()),
                format!(
                    "'{key}' has {len} entries for {} positions",
                    positions.len()
                ),
            ));
        }
    }
    Ok(TriangleMesh {
        positions,
        normals,
        uvs,
        second_uvs: Vec::new(),
        tangents: Vec::new(),
        triangles,
    })
}

/// `transform = { … }` or `transform = [{ … }, { … }]`, applied first to last. Within one
/// table: scale, then rotate, then translate; `matrix` and `look_at` stand alone.
pub(super) fn transform(cx: &Cx, v: &Value) -> Result<Vec<TransformStep>> {
    let tables: Vec<&Value> = match v.get_ref() {
        DeValue::Array(a) => a.iter().collect(),
        _ => vec![v],
    };
    let mut steps = Vec::new();
    for tv in tables {
        let t = cx.table(tv, "'transform'")?;
        t.allow(&["translate", "rotate", "scale", "matrix", "look_at"])?;
        let alone = ["matrix", "look_at"];
        for key in alone {
            if t.get(key).is_some() && t.map.len() > 1 {
                return Err(cx.err(
                    tv.span(),
                    format!("'{key}' must be alone in its transform table; list steps as transform = [{{ … }}, {{ … }}]"),
                ));
            }
        }
        if let Some(s) = t.get("scale") {
            steps.push(TransformStep::Scale(match s.get_ref() {
                DeValue::Array(_) => vec3(cx, s, "'scale'")?,
                _ => Vec3::splat(float(cx, s, "'scale'")?),
            }));
        }
        if let Some(r) = t.get("rotate") {
            let rt = cx.table(r, "'rotate'")?;
            rt.allow(&["axis", "angle"])?;
            steps.push(TransformStep::Rotate {
                axis: nonzero(&rt, "axis", Vec3::Z)?,
                degrees: float(cx, rt.required("angle")?, "'angle'")?,
            });
        }
        if let Some(tr) = t.get("translate") {
            steps.push(TransformStep::Translate(vec3(cx, tr, "'translate'")?));
        }
        if let Some(m) = t.get("matrix") {
            let items = array(cx, m, "'matrix'")?;
            let flat: Vec<&Value> = if items.len() == 4 {
                items
                    .iter()
                    .map(|r| array(cx, r, "'matrix' row"))
                    .collect::<Result<Vec<_>>>()?
                    .into_iter()
                    .flatten()
                    .collect()
            } else {
                items.iter().collect()
            };
            if flat.len() != 16 {
                return Err(cx.err(
                    m.span(),
                    "'matrix' must have 16 numbers (4 rows of 4, row-major)",
                ));
            }
            let mut a = [0.0f32; 16];
            for (o, x) in a.iter_mut().zip(flat) {
                *o = float(cx, x, "'matrix'")?;
            }
            if a[12..] != [0.0, 0.0, 0.0, 1.0] {
                return Err(cx.err(
                    m.span(),
                    "the last row of 'matrix' must be [0, 0, 0, 1] (no projective transforms)",
                ));
            }
            steps.push(TransformStep::Matrix(a));
        }
        if let Some(l) = t.get("look_at") {
            let lt = cx.table(l, "'look_at'")?;
            lt.allow(&["from", "to", "up"])?;
            steps.push(TransformStep::LookAt {
                from: lt.req_vec3("from")?,
                to: lt.req_vec3("to")?,
                up: lt.opt_vec3("up")?.unwrap_or(Vec3::Y),
            });
        }
    }
    Ok(steps)
}

/// [`light_spectrum`] of a point or spot light's intensity or power.
fn intensity_spectrum(t: &Table, i: Intensity) -> Result<Option<LightSpectrum>> {
    match i {
        Intensity::Intensity(c) => light_spectrum(t, "intensity", c),
        Intensity::Power(c) => light_spectrum(t, "power", c),
    }
}

pub(super) fn light(t: &Table, names: &[&str]) -> Result<LightSpec> {
    let kind = t.req_str("type")?;
    let intensity = |t: &Table| -> Result<Intensity> {
        match (t.opt_color("intensity")?, t.opt_color("power")?) {
            (Some(i), None) => Ok(Intensity::Intensity(i)),
            (None, Some(p)) => Ok(Intensity::Power(p)),
            _ => Err(t.cx.err(
                t.span.start..t.span.start + 1,
                format!("{} needs one of 'intensity' (W/sr) or 'power' (W)", t.what),
            )),
        }
    };
    match kind {
        "point" => {
            t.allow(&[
                "type",
                "position",
                "intensity",
                "power",
                "temperature",
                "illuminant",
            ])?;
            let intensity = intensity(t)?;
            Ok(LightSpec::Point {
                position: t.req_vec3("position")?,
                intensity,
                spectrum: intensity_spectrum(t, intensity)?,
            })
        }
        "spot" => {
            t.allow(&[
                "type",
                "position",
                "look_at",
                "intensity",
                "power",
                "angle",
                "falloff",
                "temperature",
                "illuminant",
            ])?;
            let angle = t.opt_f32("angle")?.unwrap_or(30.0);
            if !(angle > 0.0 && angle <= 90.0) {
                return Err(t.cx.err(
                    t.get("angle").map_or(0..0, |v| v.span()),
                    "'angle' (the cone's half-angle) must be in (0, 90] degrees",
                ));
            }
            let falloff = t.opt_f32("falloff")?.unwrap_or(5.0);
            if !(0.0..=angle).contains(&falloff) {
                return Err(t.cx.err(
                    t.get("falloff").map_or(0..0, |v| v.span()),
                    "'falloff' must be between 0 and 'angle' degrees",
                ));
            }
            let (position, look_at) = (t.req_vec3("position")?, t.req_vec3("look_at")?);
            if (look_at - position).length_squared() == 0.0 {
                let span = t.get("look_at").map_or(0..0, |v| v.span());
                return Err(t.cx.err(
                    span,
                    "'look_at' must differ from 'position' (it sets the spot's direction)",
                ));
            }
            let intensity = intensity(t)?;
            Ok(LightSpec::Spot {
                position,
                look_at,
                intensity,
                angle_deg: angle,
                falloff_deg: falloff,
                spectrum: intensity_spectrum(t, intensity)?,
            })
        }
        "directional" => {
            t.allow(&[
                "type",
                "direction",
                "irradiance",
                "temperature",
                "illuminant",
            ])?;
            let irradiance = t.opt_color("irradiance")?.ok_or_else(|| {
                t.cx.err(
                    t.span.start..t.span.start + 1,
                    format!("{} needs 'irradiance' (W/m²)", t.what),
                )
            })?;
            Ok(LightSpec::Directional {
                direction: nonzero(t, "direction", -Vec3::Z)?,
                irradiance,
                spectrum: light_spectrum(t, "irradiance", irradiance)?,
            })
        }
        "environment" => environment(t),
        _ => {
            let names = Names {
                materials: names,
                media: &[],
            };
            Ok(LightSpec::Area(Box::new(shape(t, &names, true)?)))
        }
    }
}

/// `type = "environment"`: `radiance` (uniform) or `file` (equirectangular image), with
/// `intensity` and `rotate`.
fn environment(t: &Table) -> Result<LightSpec> {
    t.allow(&["type", "radiance", "file", "intensity", "rotate"])?;
    let sky = match (t.opt_color("radiance")?, t.get("file")) {
        (Some(r), None) => Sky::Uniform(r),
        (None, Some(v)) => {
            let file = t.cx.file(v, &t.label("file"))?;
            if crate::io::image::EnvironmentFormat::from_path(&file).is_none() {
                return Err(t.cx.err(
                    v.span(),
                    "an environment map must be an OpenEXR (.exr), Radiance (.hdr) or PFM (.pfm) image",
                ));
            }
            Sky::File(file)
        }
        _ => {
            return Err(t.cx.err(
                t.span.start..t.span.start + 1,
                format!(
                    "{} needs one of 'radiance' (a uniform sky) or 'file' (an image)",
                    t.what
                ),
            ));
        }
    };
    let intensity = t.opt_f32("intensity")?.unwrap_or(1.0);
    if intensity < 0.0 {
        return Err(t.cx.err(
            t.get("intensity").map_or(0..0, |v| v.span()),
            "'intensity' must not be negative",
        ));
    }
    Ok(LightSpec::Environment(EnvironmentSpec {
        sky,
        intensity,
        rotate_deg: t.opt_f32("rotate")?.unwrap_or(0.0),
    }))
}
