//! Reading `.toml` scene files (format: docs/scene-format.md) into a [`SceneDesc`].
//!
//! The document is parsed into TOML values that keep their byte spans, then walked by hand:
//! that way every error names the line and column of the offending key or value, unknown keys
//! get the nearest valid key as a suggestion, and referenced files are checked while their
//! span is still at hand.

use super::source::{Diagnostic, nearest};
use super::{
    CameraSpec, ColorSpec, EmissionSpec, INTEGRATORS, Intensity, LightSpec, MaterialSpec,
    RenderSpec, SceneDesc, ShapeKind, ShapeSpec, TransformStep,
};
use crate::error::{Error, Result};
use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::TriangleMesh;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// Largest scene file read, in bytes: beyond it a text scene is a mistake (meshes belong in
/// mesh files).
pub const MAX_FILE_BYTES: u64 = 256 << 20;

/// Read a scene file; relative paths in it are resolved against its directory.
pub fn read_file(path: &Path) -> Result<SceneDesc> {
    let size = std::fs::metadata(path)
        .map_err(|source| Error::Read {
            path: path.to_owned(),
            source,
        })?
        .len();
    if size > MAX_FILE_BYTES {
        return Err(Error::SceneFile(Box::new(Diagnostic::whole_file(
            path,
            format!(
                "the file is {size} bytes; scene files are limited to {MAX_FILE_BYTES} (put large meshes in .ply or .obj files)"
            ),
        ))));
    }
    let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
        path: path.to_owned(),
        source,
    })?;
    let base_dir = path.parent().map(Path::to_owned).unwrap_or_default();
    read_str(&text, path, &base_dir)
}

/// Read scene text; `path` names it in errors and `base_dir` resolves relative file names.
pub fn read_str(text: &str, path: &Path, base_dir: &Path) -> Result<SceneDesc> {
    let doc = DeTable::parse(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        let message = e.message().trim_end().to_owned();
        Error::SceneFile(Box::new(Diagnostic::at_span(
            path,
            text,
            span,
            format!("invalid TOML: {message}"),
        )))
    })?;
    let cx = Cx {
        path,
        text,
        base_dir,
    };
    let root = Table::new(&cx, doc.get_ref(), doc.span(), "the scene file");
    root.allow(&["name", "camera", "render", "materials", "shapes", "lights"])?;
    let name = match root.opt_str("name")? {
        Some(n) => n.to_owned(),
        None => path
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
    };
    let camera = match root.get("camera") {
        Some(v) => camera(&cx.table(v, "[camera]")?)?,
        None => {
            return Err(Error::SceneFile(Box::new(Diagnostic::whole_file(
                path,
                "the scene has no [camera] table (position and look_at are required)",
            ))));
        }
    };
    let render = match root.get("render") {
        Some(v) => render(&cx.table(v, "[render]")?)?,
        None => RenderSpec::default(),
    };
    let mut materials = Vec::new();
    if let Some(v) = root.get("materials") {
        let t = cx.table(v, "[materials]")?;
        for (key, value) in t.map.iter() {
            let what = format!("material '{}'", key.get_ref());
            materials.push((
                key.get_ref().to_string(),
                material(&cx.table(value, &what)?)?,
            ));
        }
    }
    let names: Vec<&str> = materials.iter().map(|(n, _)| n.as_str()).collect();
    let mut shapes = Vec::new();
    for (i, v) in root.array_of_tables("shapes")?.into_iter().enumerate() {
        let t = cx.table(v, &format!("shape {}", i + 1))?;
        shapes.push(shape(&t, &names, false)?);
    }
    let mut lights = Vec::new();
    for (i, v) in root.array_of_tables("lights")?.into_iter().enumerate() {
        let t = cx.table(v, &format!("light {}", i + 1))?;
        lights.push(light(&t, &names)?);
    }
    Ok(SceneDesc {
        name,
        camera,
        render,
        materials,
        shapes,
        lights,
        base_dir: base_dir.to_owned(),
    })
}

struct Cx<'a> {
    path: &'a Path,
    text: &'a str,
    base_dir: &'a Path,
}

type Value<'i> = Spanned<DeValue<'i>>;

impl<'a> Cx<'a> {
    fn err(&self, span: Range<usize>, message: impl Into<String>) -> Error {
        Error::SceneFile(Box::new(Diagnostic::at_span(
            self.path, self.text, span, message,
        )))
    }

    fn table<'t, 'i>(&'t self, v: &'t Value<'i>, what: &str) -> Result<Table<'t, 'i>> {
        match v.get_ref() {
            DeValue::Table(map) => Ok(Table::new(self, map, v.span(), what)),
            other => Err(self.err(
                v.span(),
                format!("{what} must be a table, found {}", kind(other)),
            )),
        }
    }

    /// A file named in the scene, resolved and checked to exist.
    fn file(&self, v: &Value, what: &str) -> Result<PathBuf> {
        let name = str_of(self, v, what)?;
        let resolved = self.base_dir.join(name);
        if !resolved.is_file() {
            return Err(self.err(
                v.span(),
                format!(
                    "{what} '{name}' not found (looked for {})",
                    std::path::absolute(&resolved)
                        .unwrap_or(resolved.clone())
                        .display()
                ),
            ));
        }
        Ok(PathBuf::from(name))
    }
}

fn kind(v: &DeValue) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date-time",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

fn str_of<'v>(cx: &Cx, v: &'v Value, what: &str) -> Result<&'v str> {
    match v.get_ref() {
        DeValue::String(s) => Ok(s.as_ref()),
        other => Err(cx.err(
            v.span(),
            format!("{what} must be a string, found {}", kind(other)),
        )),
    }
}

fn number(cx: &Cx, v: &Value, what: &str) -> Result<f64> {
    let x = match v.get_ref() {
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
            .ok()
            .map(|i| i as f64),
        DeValue::Float(f) => f.as_str().parse::<f64>().ok(),
        other => {
            return Err(cx.err(
                v.span(),
                format!("{what} must be a number, found {}", kind(other)),
            ));
        }
    };
    match x {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(cx.err(v.span(), format!("{what} must be a finite number"))),
    }
}

/// A number read directly as `f32`, so that a value written from an `f32` reads back exactly.
fn float(cx: &Cx, v: &Value, what: &str) -> Result<f32> {
    let x = match v.get_ref() {
        DeValue::Float(f) => f.as_str().parse::<f32>().ok(),
        _ => Some(number(cx, v, what)? as f32),
    };
    match x {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(cx.err(v.span(), format!("{what} must be a finite number"))),
    }
}

fn integer(cx: &Cx, v: &Value, what: &str, max: u64) -> Result<u64> {
    let parsed = match v.get_ref() {
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix()).ok(),
        other => {
            return Err(cx.err(
                v.span(),
                format!("{what} must be a whole number, found {}", kind(other)),
            ));
        }
    };
    match parsed {
        Some(i) if i >= 0 && i as u64 <= max => Ok(i as u64),
        _ => Err(cx.err(
            v.span(),
            format!("{what} must be a whole number from 0 to {max}"),
        )),
    }
}

fn array<'v, 'i>(cx: &Cx, v: &'v Value<'i>, what: &str) -> Result<&'v [Value<'i>]> {
    match v.get_ref() {
        DeValue::Array(a) => Ok(a.as_ref()),
        other => Err(cx.err(
            v.span(),
            format!("{what} must be an array, found {}", kind(other)),
        )),
    }
}

fn floats<const N: usize>(cx: &Cx, v: &Value, what: &str) -> Result<[f32; N]> {
    let items = array(cx, v, what)
        .map_err(|_| cx.err(v.span(), format!("{what} must be an array of {N} numbers")))?;
    if items.len() != N {
        return Err(cx.err(
            v.span(),
            format!("{what} must have {N} numbers, found {}", items.len()),
        ));
    }
    let mut out = [0.0; N];
    for (o, item) in out.iter_mut().zip(items) {
        *o = float(cx, item, what)?;
    }
    Ok(out)
}

fn vec3(cx: &Cx, v: &Value, what: &str) -> Result<Vec3> {
    Ok(Vec3::from_array(floats::<3>(cx, v, what)?))
}

/// A colour: `[r, g, b]`, or one number for grey. Components must not be negative.
fn color(cx: &Cx, v: &Value, what: &str) -> Result<Rgb> {
    let c = match v.get_ref() {
        DeValue::Array(_) => Vec3::from_array(floats::<3>(cx, v, what)?),
        DeValue::Integer(_) | DeValue::Float(_) => Vec3::splat(float(cx, v, what)?),
        other => {
            return Err(cx.err(
                v.span(),
                format!(
                    "{what} must be a colour [r, g, b] or a number, found {}",
                    kind(other)
                ),
            ));
        }
    };
    if c.min_element() < 0.0 {
        return Err(cx.err(v.span(), format!("{what} must not be negative")));
    }
    Ok(c)
}

/// A table being read: knows its keys, location and what to call itself in messages.
struct Table<'t, 'i> {
    cx: &'t Cx<'t>,
    map: &'t DeTable<'i>,
    span: Range<usize>,
    what: String,
}

impl<'t, 'i> Table<'t, 'i> {
    fn new(cx: &'t Cx<'t>, map: &'t DeTable<'i>, span: Range<usize>, what: &str) -> Self {
        Self {
            cx,
            map,
            span,
            what: what.to_owned(),
        }
    }

    /// Refuse keys outside `allowed`, suggesting the nearest one.
    fn allow(&self, allowed: &[&str]) -> Result<()> {
        for key in self.map.keys() {
            let k = key.get_ref().as_ref();
            if !allowed.contains(&k) {
                let hint = match nearest(k, allowed) {
                    Some(n) => format!("; did you mean '{n}'?"),
                    None => String::new(),
                };
                return Err(self.cx.err(
                    key.span(),
                    format!(
                        "unknown key '{k}' in {}{hint} (expected one of: {})",
                        self.what,
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn get(&self, key: &str) -> Option<&'t Value<'i>> {
        self.map.get(key)
    }

    fn label(&self, key: &str) -> String {
        format!("'{key}' in {}", self.what)
    }

    fn required(&self, key: &str) -> Result<&'t Value<'i>> {
        self.get(key).ok_or_else(|| {
            // Point at the table's first line: its header or opening brace.
            let start = self.span.start;
            self.cx
                .err(start..start + 1, format!("{} needs '{key}'", self.what))
        })
    }

    fn opt_str(&self, key: &str) -> Result<Option<&'t str>> {
        self.get(key)
            .map(|v| str_of(self.cx, v, &self.label(key)))
            .transpose()
    }

    fn req_str(&self, key: &str) -> Result<&'t str> {
        str_of(self.cx, self.required(key)?, &self.label(key))
    }

    fn opt_f32(&self, key: &str) -> Result<Option<f32>> {
        self.get(key)
            .map(|v| float(self.cx, v, &self.label(key)))
            .transpose()
    }

    fn positive(&self, key: &str) -> Result<f32> {
        let v = self.required(key)?;
        let x = float(self.cx, v, &self.label(key))?;
        if x <= 0.0 {
            return Err(self
                .cx
                .err(v.span(), format!("{} must be positive", self.label(key))));
        }
        Ok(x)
    }

    fn opt_int(&self, key: &str, max: u64) -> Result<Option<u64>> {
        self.get(key)
            .map(|v| integer(self.cx, v, &self.label(key), max))
            .transpose()
    }

    fn opt_bool(&self, key: &str) -> Result<Option<bool>> {
        self.get(key)
            .map(|v| match v.get_ref() {
                DeValue::Boolean(b) => Ok(*b),
                other => Err(self.cx.err(
                    v.span(),
                    format!(
                        "{} must be true or false, found {}",
                        self.label(key),
                        kind(other)
                    ),
                )),
            })
            .transpose()
    }

    fn req_vec3(&self, key: &str) -> Result<Vec3> {
        vec3(self.cx, self.required(key)?, &self.label(key))
    }

    fn opt_vec3(&self, key: &str) -> Result<Option<Vec3>> {
        self.get(key)
            .map(|v| vec3(self.cx, v, &self.label(key)))
            .transpose()
    }

    fn opt_color(&self, key: &str) -> Result<Option<Rgb>> {
        self.get(key)
            .map(|v| color(self.cx, v, &self.label(key)))
            .transpose()
    }

    /// `[[key]]` entries (or an inline array of tables); none if the key is absent.
    fn array_of_tables(&self, key: &str) -> Result<Vec<&'t Value<'i>>> {
        match self.get(key) {
            None => Ok(Vec::new()),
            Some(v) => Ok(
                array(self.cx, v, &format!("'{key}' (write [[{key}]] tables)"))?
                    .iter()
                    .collect(),
            ),
        }
    }

    /// A material name that must be defined in `[materials]`.
    fn material_ref(&self, key: &str, names: &[&str]) -> Result<Option<String>> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let name = str_of(self.cx, v, &self.label(key))?;
        if !names.contains(&name) {
            let hint = match nearest(name, names) {
                Some(n) => format!("; did you mean '{n}'?"),
                None if names.is_empty() => "; the file defines no [materials]".into(),
                None => format!(" (defined: {})", names.join(", ")),
            };
            return Err(self.cx.err(
                v.span(),
                format!("material '{name}' is not defined in [materials]{hint}"),
            ));
        }
        Ok(Some(name.to_owned()))
    }
}

fn camera(t: &Table) -> Result<CameraSpec> {
    t.allow(&["position", "look_at", "up", "fov", "resolution"])?;
    let (width, height) = match t.get("resolution") {
        Some(v) => {
            let what = t.label("resolution");
            let items = array(t.cx, v, &what)?;
            if items.len() != 2 {
                return Err(t
                    .cx
                    .err(v.span(), format!("{what} must be [width, height]")));
            }
            let w = integer(t.cx, &items[0], &what, 1 << 16)?;
            let h = integer(t.cx, &items[1], &what, 1 << 16)?;
            if w == 0 || h == 0 {
                return Err(t.cx.err(v.span(), format!("{what} must be at least 1×1")));
            }
            (w as u32, h as u32)
        }
        None => (512, 512),
    };
    let fov = t.opt_f32("fov")?.unwrap_or(40.0);
    if !(fov > 0.0 && fov < 180.0) {
        let span = t.get("fov").map_or(t.span.clone(), |v| v.span());
        return Err(t.cx.err(span, "'fov' must be between 0 and 180 degrees"));
    }
    Ok(CameraSpec {
        position: t.req_vec3("position")?,
        look_at: t.req_vec3("look_at")?,
        up: t.opt_vec3("up")?.unwrap_or(Vec3::Y),
        fov_y_deg: fov,
        width,
        height,
    })
}

fn render(t: &Table) -> Result<RenderSpec> {
    t.allow(&[
        "integrator",
        "spp",
        "seed",
        "max_depth",
        "light_samples",
        "photons",
        "caustic_photons",
        "radius",
        "gather_rays",
        "passes",
        "time",
    ])?;
    let integrator = match t.get("integrator") {
        Some(v) => {
            let name = str_of(t.cx, v, &t.label("integrator"))?;
            if !INTEGRATORS.contains(&name) {
                return Err(t.cx.err(
                    v.span(),
                    format!(
                        "unknown integrator '{name}' (expected one of: {})",
                        INTEGRATORS.join(", ")
                    ),
                ));
            }
            Some(name.to_owned())
        }
        None => None,
    };
    const U32: u64 = u32::MAX as u64;
    Ok(RenderSpec {
        integrator,
        spp: t.opt_int("spp", U32)?.map(|x| x as u32),
        seed: t.opt_int("seed", i64::MAX as u64)?,
        max_depth: t.opt_int("max_depth", 1 << 16)?.map(|x| x as u32),
        light_samples: t.opt_int("light_samples", 1 << 16)?.map(|x| x as u32),
        photons: t.opt_int("photons", 1 << 40)?,
        caustic_photons: t.opt_int("caustic_photons", 1 << 40)?,
        radius: t.opt_f32("radius")?,
        gather_rays: t.opt_int("gather_rays", 1 << 16)?.map(|x| x as u32),
        passes: t.opt_int("passes", 1 << 40)?,
        time: t.opt_f32("time")?.map(f64::from),
    })
}

fn material(t: &Table) -> Result<MaterialSpec> {
    let kind = t.req_str("type")?;
    match kind {
        "diffuse" => {
            t.allow(&["type", "albedo"])?;
            let albedo = match t.get("albedo") {
                None => ColorSpec::Constant(Rgb::splat(0.8)),
                Some(v) => color_spec(t, v)?,
            };
            Ok(MaterialSpec::Diffuse { albedo })
        }
        "mirror" => {
            t.allow(&["type", "reflectance"])?;
            Ok(MaterialSpec::Mirror {
                reflectance: t.opt_color("reflectance")?.unwrap_or(Rgb::ONE),
            })
        }
        "glass" => {
            t.allow(&["type", "ior", "transmittance"])?;
            let ior = t.opt_f32("ior")?.unwrap_or(1.5);
            if ior <= 0.0 {
                return Err(t.cx.err(
                    t.get("ior").map_or(0..0, |v| v.span()),
                    "'ior' must be positive",
                ));
            }
            Ok(MaterialSpec::Glass {
                ior,
                transmittance: t.opt_color("transmittance")?.unwrap_or(Rgb::ONE),
            })
        }
        other => Err(bad_type(t, other, &["diffuse", "mirror", "glass"])),
    }
}

fn bad_type(t: &Table, found: &str, expected: &[&str]) -> Error {
    let span = t.get("type").map_or(t.span.clone(), |v| v.span());
    let hint = match nearest(found, expected) {
        Some(n) => format!("; did you mean '{n}'?"),
        None => String::new(),
    };
    t.cx.err(
        span,
        format!(
            "unknown type '{found}' for {}{hint} (expected one of: {})",
            t.what,
            expected.join(", ")
        ),
    )
}

/// An albedo: a colour, `{ texture = "file.png", tint = … }` or `{ checker = … }`.
fn color_spec(t: &Table, v: &Value) -> Result<ColorSpec> {
    let DeValue::Table(_) = v.get_ref() else {
        return Ok(ColorSpec::Constant(color(t.cx, v, &t.label("albedo"))?));
    };
    let inner = t.cx.table(v, &t.label("albedo"))?;
    if inner.get("texture").is_some() {
        inner.allow(&["texture", "tint"])?;
        let file = t.cx.file(inner.required("texture")?, "texture")?;
        return Ok(ColorSpec::Image {
            file,
            tint: inner.opt_color("tint")?.unwrap_or(Rgb::ONE),
        });
    }
    if let Some(c) = inner.get("checker") {
        inner.allow(&["checker"])?;
        let c = t.cx.table(c, "the checker texture")?;
        c.allow(&["even", "odd", "scale"])?;
        let scale = match c.get("scale") {
            None => Vec2::splat(8.0),
            Some(v) => match v.get_ref() {
                DeValue::Array(_) => Vec2::from_array(floats::<2>(t.cx, v, "'scale'")?),
                _ => Vec2::splat(float(t.cx, v, "'scale'")?),
            },
        };
        return Ok(ColorSpec::Checker {
            even: c.opt_color("even")?.unwrap_or(Rgb::splat(0.8)),
            odd: c.opt_color("odd")?.unwrap_or(Rgb::splat(0.2)),
            scale,
        });
    }
    Err(t.cx.err(
        v.span(),
        "an albedo table must be { texture = \"file.png\" } or { checker = { … } }",
    ))
}

const SHAPE_TYPES: &[&str] = &["sphere", "disk", "quad", "box", "mesh", "triangles", "pot"];

/// Keys each shape type takes, besides the common ones.
fn shape_keys(kind: &str) -> &'static [&'static str] {
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

fn shape(t: &Table, names: &[&str], is_light: bool) -> Result<ShapeSpec> {
    let kind_name = t.req_str("type")?;
    if !SHAPE_TYPES.contains(&kind_name) {
        let mut all = SHAPE_TYPES.to_vec();
        if is_light {
            all.extend(["point", "spot"]);
        }
        return Err(bad_type(t, kind_name, &all));
    }
    let mut allowed = vec!["type", "material", "transform"];
    if is_light {
        allowed.extend(["radiance", "power", "two_sided"]);
    } else {
        allowed.push("emission");
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
            soil_material: t.material_ref("soil_material", names)?,
            leaf_material: t.material_ref("leaf_material", names)?,
        },
    };
    let material = t.material_ref("material", names)?;
    let emission = if is_light {
        Some(emission(t)?)
    } else {
        match t.get("emission") {
            Some(v) => {
                let et = t.cx.table(v, &t.label("emission"))?;
                et.allow(&["radiance", "power", "two_sided"])?;
                Some(emission(&et)?)
            }
            None => None,
        }
    };
    let needs_material =
        !is_light && emission.is_none() && !matches!(kind, ShapeKind::MeshFile { .. });
    if needs_material && material.is_none() {
        return Err(t.cx.err(
            t.span.start..t.span.start + 1,
            format!("{} needs a 'material'", t.what),
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
    })
}

fn nonzero(t: &Table, key: &str, default: Vec3) -> Result<Vec3> {
    let v = t.opt_vec3(key)?.unwrap_or(default);
    if v.length_squared() == 0.0 {
        let span = t.get(key).map_or(t.span.clone(), |v| v.span());
        return Err(t.cx.err(span, format!("{} must not be zero", t.label(key))));
    }
    Ok(v)
}

fn emission(t: &Table) -> Result<EmissionSpec> {
    let two_sided = t.opt_bool("two_sided")?.unwrap_or(false);
    match (t.opt_color("radiance")?, t.opt_color("power")?) {
        (Some(radiance), None) => Ok(EmissionSpec::Radiance {
            radiance,
            two_sided,
        }),
        (None, Some(power)) => Ok(EmissionSpec::Power { power, two_sided }),
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

fn inline_mesh(t: &Table) -> Result<TriangleMesh> {
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
        triangles,
    })
}

/// `transform = { … }` or `transform = [{ … }, { … }]`, applied first to last. Within one
/// table: scale, then rotate, then translate; `matrix` and `look_at` stand alone.
fn transform(cx: &Cx, v: &Value) -> Result<Vec<TransformStep>> {
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

fn light(t: &Table, names: &[&str]) -> Result<LightSpec> {
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
            t.allow(&["type", "position", "intensity", "power"])?;
            Ok(LightSpec::Point {
                position: t.req_vec3("position")?,
                intensity: intensity(t)?,
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
            Ok(LightSpec::Spot {
                position: t.req_vec3("position")?,
                look_at: t.req_vec3("look_at")?,
                intensity: intensity(t)?,
                angle_deg: angle,
                falloff_deg: falloff,
            })
        }
        _ => Ok(LightSpec::Area(shape(t, names, true)?)),
    }
}
