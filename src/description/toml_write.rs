//! Writing a [`SceneDesc`] as a `.toml` scene file that [`super::toml_read`] reads back to an
//! equal description. Numbers are written in the shortest form that reads back to the same
//! `f32`, so a written scene renders bit-identically.

use super::{
    ColorSpec, ConductorSpec, EmissionSpec, ImageRef, Intensity, LightSpec, LightSpectrum,
    MaterialSpec, SceneDesc, ShapeKind, ShapeSpec, Sky, TransformStep,
};
use crate::error::{Error, Result};
use crate::material::Dispersion;
use crate::math::Vec3;
use std::fmt::Write;
use std::path::Path;

/// The scene as TOML text. File names are written relative to `out_dir` when the scene's own
/// directory is the same, else absolute.
pub fn to_toml(desc: &SceneDesc, out_dir: &Path) -> Result<String> {
    let mut w = Writer {
        out: String::new(),
        base_dir: desc.base_dir.clone(),
        out_dir: out_dir.to_owned(),
    };
    w.line(&format!(
        "# Photon scene '{}'. Format: docs/scene-format.md",
        desc.name
    ));
    w.kv("name", &string(&desc.name));
    if let Some(m) = &desc.medium {
        w.kv("medium", &string(m));
    }
    let c = &desc.camera;
    w.section("[camera]");
    w.kv("position", &vec3(c.position));
    w.kv("look_at", &vec3(c.look_at));
    w.kv("up", &vec3(c.up));
    w.kv("fov", &float(c.fov_y_deg));
    w.kv("resolution", &format!("[{}, {}]", c.width, c.height));
    w.render(desc);
    for (name, m) in &desc.materials {
        w.section(&format!("[materials.{}]", key(name)));
        match m {
            MaterialSpec::Diffuse { albedo } => {
                w.kv("type", "\"diffuse\"");
                let value = w.color_spec(albedo)?;
                w.kv("albedo", &value);
            }
            MaterialSpec::Mirror { reflectance } => {
                w.kv("type", "\"mirror\"");
                w.kv("reflectance", &vec3(*reflectance));
            }
            MaterialSpec::Glass {
                ior,
                transmittance,
                alpha,
                attenuation,
                dispersion,
            } => {
                w.kv("type", "\"glass\"");
                match *dispersion {
                    Dispersion::None => w.kv("ior", &float(*ior)),
                    Dispersion::Cauchy { a, b } => w.kv(
                        "cauchy",
                        &format!("{{ a = {}, b = {} }}", float(a), float(b)),
                    ),
                    Dispersion::Sellmeier { b, c } => w.kv(
                        "sellmeier",
                        &format!(
                            "{{ b = {}, c = {} }}",
                            vec3(Vec3::from_array(b)),
                            vec3(Vec3::from_array(c))
                        ),
                    ),
                }
                w.kv("transmittance", &vec3(*transmittance));
                if *alpha > 0.0 {
                    w.kv("alpha", &float(*alpha));
                }
                if let Some(a) = attenuation {
                    w.kv(
                        "attenuation",
                        &format!(
                            "{{ color = {}, distance = {} }}",
                            vec3(a.color),
                            float(a.distance)
                        ),
                    );
                }
            }
            MaterialSpec::Conductor { fresnel, alpha } => {
                w.kv("type", "\"conductor\"");
                match fresnel {
                    ConductorSpec::Metal(m) => w.kv("metal", &string(m.name())),
                    ConductorSpec::Ior { eta, k } => {
                        w.kv("eta", &vec3(*eta));
                        w.kv("k", &vec3(*k));
                    }
                    ConductorSpec::F0(f0) => w.kv("f0", &vec3(*f0)),
                }
                if alpha[0] == alpha[1] {
                    w.kv("alpha", &float(alpha[0]));
                } else {
                    w.kv(
                        "alpha",
                        &format!("[{}, {}]", float(alpha[0]), float(alpha[1])),
                    );
                }
            }
            MaterialSpec::Pbr(p) => {
                if p.coverage != crate::scene::Coverage::Opaque {
                    return Err(Error::InvalidScene(format!(
                        "material '{name}' is cut out or blended (glTF alphaMode), which a TOML scene cannot say; include the glTF file as a mesh instead"
                    )));
                }
                w.kv("type", "\"pbr\"");
                let base = w.color_spec(&p.base_color)?;
                w.kv("base_color", &base);
                w.kv("metallic", &float(p.metallic));
                w.kv("roughness", &float(p.roughness));
                if p.specular != 1.0 {
                    w.kv("specular", &float(p.specular));
                }
                if let Some(t) = &p.metallic_roughness {
                    let v = w.data_texture(t)?;
                    w.kv("metallic_roughness", &v);
                }
                if let Some((t, scale)) = &p.normal_map {
                    let v = w.data_texture(t)?;
                    w.kv("normal_map", &v);
                    w.kv("normal_scale", &float(*scale));
                }
            }
        }
    }
    for (name, m) in &desc.media {
        w.section(&format!("[media.{}]", key(name)));
        w.kv("sigma_a", &vec3(m.sigma_a));
        w.kv("sigma_s", &vec3(m.sigma_s));
        w.kv("g", &float(m.g));
        if let Some(g) = &m.grid {
            let v = w.path(&g.file);
            w.kv("grid", &v);
            w.kv("grid_name", &string(&g.name));
            if !g.transform.is_empty() {
                let steps: Vec<String> = g.transform.iter().map(step).collect();
                w.kv("transform", &format!("[{}]", steps.join(", ")));
            }
        }
    }
    for s in &desc.shapes {
        w.section("[[shapes]]");
        w.shape(s, false);
    }
    for l in &desc.lights {
        w.section("[[lights]]");
        match l {
            LightSpec::Point {
                position,
                intensity,
                spectrum,
            } => {
                w.kv("type", "\"point\"");
                w.kv("position", &vec3(*position));
                w.intensity(intensity);
                w.spectrum(spectrum);
            }
            LightSpec::Spot {
                position,
                look_at,
                intensity,
                angle_deg,
                falloff_deg,
                spectrum,
            } => {
                w.kv("type", "\"spot\"");
                w.kv("position", &vec3(*position));
                w.kv("look_at", &vec3(*look_at));
                w.intensity(intensity);
                w.kv("angle", &float(*angle_deg));
                w.kv("falloff", &float(*falloff_deg));
                w.spectrum(spectrum);
            }
            LightSpec::Directional {
                direction,
                irradiance,
                spectrum,
            } => {
                w.kv("type", "\"directional\"");
                w.kv("direction", &vec3(*direction));
                w.kv("irradiance", &vec3(*irradiance));
                w.spectrum(spectrum);
            }
            LightSpec::Area(s) => w.shape(s, true),
            LightSpec::Environment(e) => {
                w.kv("type", "\"environment\"");
                match &e.sky {
                    Sky::Uniform(r) => w.kv("radiance", &vec3(*r)),
                    Sky::File(f) => {
                        let v = w.path(f);
                        w.kv("file", &v);
                    }
                }
                w.kv("intensity", &float(e.intensity));
                w.kv("rotate", &float(e.rotate_deg));
            }
        }
    }
    Ok(w.out)
}

fn embedded_texture() -> Error {
    Error::InvalidScene(
        "a texture embedded in a glTF file cannot be written to a TOML scene; include the glTF file as a mesh instead".into(),
    )
}

struct Writer {
    out: String,
    base_dir: std::path::PathBuf,
    out_dir: std::path::PathBuf,
}

/// `f32` in its shortest round-trip form, always with a `.` or exponent so TOML reads a float.
/// The key and value that give a light's spectrum.
fn spectrum_kv(s: &Option<LightSpectrum>) -> Option<(&'static str, String)> {
    Some(match (*s)? {
        LightSpectrum::Blackbody(k) => ("temperature", float(k)),
        LightSpectrum::D65 => ("illuminant", string("D65")),
        LightSpectrum::A => ("illuminant", string("A")),
    })
}

fn float(x: f32) -> String {
    format!("{x:?}")
}

fn vec3(v: Vec3) -> String {
    format!("[{}, {}, {}]", float(v.x), float(v.y), float(v.z))
}

fn string(s: &str) -> String {
    toml::Value::String(s.to_owned()).to_string()
}

/// A table key, quoted unless it is a bare key.
fn key(name: &str) -> String {
    let bare = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare { name.to_owned() } else { string(name) }
}

impl Writer {
    fn line(&mut self, s: &str) {
        self.out.push_str(s);
        self.out.push('\n');
    }

    fn section(&mut self, header: &str) {
        self.out.push('\n');
        self.line(header);
    }

    fn kv(&mut self, k: &str, v: &str) {
        let _ = writeln!(self.out, "{k} = {v}");
    }

    fn path(&self, file: &Path) -> String {
        let full = self.base_dir.join(file);
        let shown = if self.base_dir == self.out_dir || file.is_absolute() {
            file.to_owned()
        } else {
            std::path::absolute(&full).unwrap_or(full)
        };
        string(&shown.to_string_lossy())
    }

    /// `[render]`: every setting given, as its own type writes it (numbers bare, names and
    /// filters as strings, ranges as arrays).
    fn render(&mut self, desc: &SceneDesc) {
        let serde_json::Value::Object(given) =
            serde_json::to_value(&desc.render).expect("settings are plain data")
        else {
            return;
        };
        if given.is_empty() {
            return;
        }
        self.section("[render]");
        for (key, value) in given {
            let text = match &value {
                serde_json::Value::String(s) => string(s),
                other => other.to_string().replace(',', ", "),
            };
            self.kv(&key, &text);
        }
    }

    fn color_spec(&self, c: &ColorSpec) -> Result<String> {
        Ok(match c {
            ColorSpec::Constant(c) => vec3(*c),
            ColorSpec::Image { file, tint } => {
                format!(
                    "{{ texture = {}, tint = {} }}",
                    self.path(file),
                    vec3(*tint)
                )
            }
            ColorSpec::Checker { even, odd, scale } => format!(
                "{{ checker = {{ even = {}, odd = {}, scale = [{}, {}] }} }}",
                vec3(*even),
                vec3(*odd),
                float(scale.x),
                float(scale.y)
            ),
            ColorSpec::Decoded { .. } => return Err(embedded_texture()),
        })
    }

    fn data_texture(&self, t: &ImageRef) -> Result<String> {
        match t {
            ImageRef::File(f) => Ok(self.path(f)),
            ImageRef::Decoded(_) => Err(embedded_texture()),
        }
    }

    fn intensity(&mut self, i: &Intensity) {
        match i {
            Intensity::Intensity(c) => self.kv("intensity", &vec3(*c)),
            Intensity::Power(c) => self.kv("power", &vec3(*c)),
        }
    }

    fn spectrum(&mut self, s: &Option<LightSpectrum>) {
        if let Some((k, v)) = spectrum_kv(s) {
            self.kv(k, &v);
        }
    }

    fn shape(&mut self, s: &ShapeSpec, is_light: bool) {
        self.shape_kind(&s.kind);
        if let Some(m) = &s.material {
            self.kv("material", &string(m));
        }
        if let Some(sides) = &s.media {
            if let Some(m) = &sides.interior {
                self.kv("interior", &string(m));
            }
            if let Some(m) = &sides.exterior {
                self.kv("exterior", &string(m));
            }
        }
        if !s.transform.is_empty() {
            let steps: Vec<String> = s.transform.iter().map(step).collect();
            self.kv("transform", &format!("[{}]", steps.join(", ")));
        }
        if let Some(e) = &s.emission {
            let (k, c, two_sided, texture, spectrum) = match e {
                EmissionSpec::Radiance {
                    radiance,
                    two_sided,
                    texture,
                    spectrum,
                } => (
                    "radiance",
                    *radiance,
                    *two_sided,
                    texture.as_ref(),
                    spectrum,
                ),
                EmissionSpec::Power {
                    power,
                    two_sided,
                    spectrum,
                } => ("power", *power, *two_sided, None, spectrum),
            };
            // A texture embedded in a glTF file cannot be written; it is left out (warned
            // about by `to_toml`'s caller through the material, which cannot be written either).
            let texture = texture.and_then(|t| match t {
                ImageRef::File(f) => Some(format!(", texture = {}", self.path(f))),
                ImageRef::Decoded(_) => None,
            });
            let texture = texture.unwrap_or_default();
            if is_light {
                self.kv(k, &vec3(c));
                self.kv("two_sided", &two_sided.to_string());
                if let Some(t) = texture.strip_prefix(", texture = ") {
                    self.kv("texture", t);
                }
                self.spectrum(spectrum);
            } else {
                let spectrum = spectrum_kv(spectrum)
                    .map(|(k, v)| format!(", {k} = {v}"))
                    .unwrap_or_default();
                self.kv(
                    "emission",
                    &format!(
                        "{{ {k} = {}, two_sided = {two_sided}{texture}{spectrum} }}",
                        vec3(c)
                    ),
                );
            }
        }
    }

    fn triangles(&mut self, m: &crate::scene::TriangleMesh) {
        self.kv("type", "\"triangles\"");
        let list = |items: Vec<String>| format!("[\n  {},\n]", items.join(",\n  "));
        self.kv(
            "positions",
            &list(m.positions.iter().map(|&p| vec3(p)).collect()),
        );
        let tris = m
            .triangles
            .iter()
            .map(|t| format!("[{}, {}, {}]", t[0], t[1], t[2]))
            .collect();
        self.kv("indices", &list(tris));
        if !m.normals.is_empty() {
            self.kv(
                "normals",
                &list(m.normals.iter().map(|&n| vec3(n)).collect()),
            );
        }
        if !m.uvs.is_empty() {
            let uvs = m
                .uvs
                .iter()
                .map(|u| format!("[{}, {}]", float(u.x), float(u.y)))
                .collect();
            self.kv("uvs", &list(uvs));
        }
    }

    fn shape_kind(&mut self, kind: &ShapeKind) {
        match kind {
            ShapeKind::Sphere { center, radius } => {
                self.kv("type", "\"sphere\"");
                self.kv("center", &vec3(*center));
                self.kv("radius", &float(*radius));
            }
            ShapeKind::Disk {
                center,
                normal,
                radius,
            } => {
                self.kv("type", "\"disk\"");
                self.kv("center", &vec3(*center));
                self.kv("normal", &vec3(*normal));
                self.kv("radius", &float(*radius));
            }
            ShapeKind::Quad { vertices } => {
                self.kv("type", "\"quad\"");
                let v: Vec<String> = vertices.iter().map(|&p| vec3(p)).collect();
                self.kv("vertices", &format!("[{}]", v.join(", ")));
            }
            ShapeKind::Box { min, max } => {
                self.kv("type", "\"box\"");
                self.kv("min", &vec3(*min));
                self.kv("max", &vec3(*max));
            }
            ShapeKind::MeshFile { file, smooth } => {
                self.kv("type", "\"mesh\"");
                let p = self.path(file);
                self.kv("file", &p);
                self.kv("smooth", &smooth.to_string());
            }
            ShapeKind::Triangles(m) => self.triangles(m),
            ShapeKind::Pot {
                subdivisions,
                seed,
                soil_material,
                leaf_material,
            } => {
                self.kv("type", "\"pot\"");
                self.kv("subdivisions", &subdivisions.to_string());
                self.kv("seed", &seed.to_string());
                if let Some(m) = soil_material {
                    self.kv("soil_material", &string(m));
                }
                if let Some(m) = leaf_material {
                    self.kv("leaf_material", &string(m));
                }
            }
        }
    }
}

fn step(s: &TransformStep) -> String {
    match *s {
        TransformStep::Translate(t) => format!("{{ translate = {} }}", vec3(t)),
        TransformStep::Rotate { axis, degrees } => format!(
            "{{ rotate = {{ axis = {}, angle = {} }} }}",
            vec3(axis),
            float(degrees)
        ),
        TransformStep::Scale(s) => format!("{{ scale = {} }}", vec3(s)),
        TransformStep::Matrix(m) => {
            let rows: Vec<String> = m
                .chunks(4)
                .map(|r| {
                    let r: Vec<String> = r.iter().map(|&x| float(x)).collect();
                    format!("[{}]", r.join(", "))
                })
                .collect();
            format!("{{ matrix = [{}] }}", rows.join(", "))
        }
        TransformStep::LookAt { from, to, up } => format!(
            "{{ look_at = {{ from = {}, to = {}, up = {} }} }}",
            vec3(from),
            vec3(to),
            vec3(up)
        ),
    }
}
