//! The scene-level tables: camera, render settings, materials and their albedo textures.

use super::values::{self, Table, Value, array, color, float, floats, integer, str_of};
use crate::description::source::did_you_mean;
use crate::description::{CameraSpec, ColorSpec, ConductorSpec, ImageRef, MaterialSpec, PbrSpec};
use crate::error::{Error, Result};
use crate::material::{Attenuation, Dispersion, Metal};
use crate::math::{Rgb, Vec2, Vec3};
use crate::render::MAX_RESOLUTION;
use crate::settings::{self, RenderOptions};
use toml::de::DeValue;

pub(super) fn camera(t: &Table) -> Result<CameraSpec> {
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
            let w = integer(t.cx, &items[0], &what, u64::from(MAX_RESOLUTION))?;
            let h = integer(t.cx, &items[1], &what, u64::from(MAX_RESOLUTION))?;
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
    let (position, look_at) = (t.req_vec3("position")?, t.req_vec3("look_at")?);
    let up = t.opt_vec3("up")?.unwrap_or(Vec3::Y);
    let span = |key: &str| {
        t.get(key)
            .map_or(t.span.start..t.span.start + 1, |v| v.span())
    };
    let view = look_at - position;
    if view.length_squared() == 0.0 {
        return Err(t
            .cx
            .err(span("look_at"), "'look_at' must differ from 'position'"));
    }
    if view.cross(up).length_squared() <= 1e-12 * view.length_squared() * up.length_squared() {
        return Err(t.cx.err(
            span("up"),
            "'up' must not be parallel to the view direction (the default is [0, 1, 0]; a z-up scene needs up = [0, 0, 1])",
        ));
    }
    Ok(CameraSpec {
        position,
        look_at,
        up,
        fov_y_deg: fov,
        width,
        height,
    })
}

/// The `[render]` table: every key a setting of [`crate::settings::SETTINGS`] but the ranges
/// that split a render, read by the setting's own type and checked by its own range (not by
/// which integrator takes it: a scene's settings apply where they are taken).
pub(super) fn render(t: &Table) -> Result<RenderOptions> {
    let names: Vec<&str> = settings::SETTINGS.iter().map(|s| s.name).collect();
    t.allow(&names)?;
    let mut options = RenderOptions::default();
    for name in names {
        let Some(v) = t.get(name) else { continue };
        let what = t.label(name);
        if settings::setting(name).group == settings::Group::Splitting {
            return Err(t.cx.err(
                v.span(),
                format!("{what}: a part of a render is chosen per run (on the command line or by a job), not in a scene file"),
            ));
        }
        let set = match v.get_ref() {
            DeValue::String(text) => options.set_text(name, text),
            DeValue::Integer(_) => {
                let n = integer(t.cx, v, &what, u64::MAX >> 1)?;
                options.set_json(name, serde_json::Value::from(n))
            }
            DeValue::Float(f) => {
                // Read as written, so that a value written from an `f32` reads back exactly.
                let x = f.as_str().parse::<f64>().ok().filter(|x| x.is_finite());
                let x = x.ok_or_else(|| {
                    t.cx.err(v.span(), format!("{what} must be a finite number"))
                })?;
                options.set_json(name, serde_json::Value::from(x))
            }
            DeValue::Boolean(b) => options.set_json(name, serde_json::Value::Bool(*b)),
            DeValue::Array(items) => {
                let numbers = items
                    .iter()
                    .map(|i| integer(t.cx, i, &what, u64::MAX >> 1).map(serde_json::Value::from))
                    .collect::<Result<Vec<_>>>()?;
                options.set_json(name, serde_json::Value::Array(numbers))
            }
            other => {
                return Err(t.cx.err(
                    v.span(),
                    format!("{what} cannot be {}", values::kind(other)),
                ));
            }
        };
        set.and_then(|()| options.check_values())
            .map_err(|e| t.cx.err(v.span(), format!("{what}: {}", e.problem)))?;
    }
    Ok(options)
}

/// An optional string that must be one of `allowed`.
fn one_of(t: &Table, key: &str, allowed: &[&str]) -> Result<Option<String>> {
    let Some(v) = t.get(key) else {
        return Ok(None);
    };
    let name = str_of(t.cx, v, &t.label(key))?;
    if !allowed.contains(&name) {
        let hint = did_you_mean(name, allowed);
        return Err(t.cx.err(
            v.span(),
            format!(
                "unknown {key} '{name}'{hint} (expected one of: {})",
                allowed.join(", ")
            ),
        ));
    }
    Ok(Some(name.to_owned()))
}

pub(super) fn material(t: &Table) -> Result<MaterialSpec> {
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
            t.allow(&[
                "type",
                "ior",
                "transmittance",
                "alpha",
                "attenuation",
                "glass",
                "abbe",
                "cauchy",
                "sellmeier",
            ])?;
            let ior = t.opt_f32("ior")?.unwrap_or(1.5);
            if ior <= 0.0 {
                return Err(t.cx.err(
                    t.get("ior").map_or(0..0, |v| v.span()),
                    "'ior' must be positive",
                ));
            }
            let dispersion = dispersion(t, ior)?;
            Ok(MaterialSpec::Glass {
                ior: dispersion.ior_d().unwrap_or(ior),
                transmittance: t.opt_color("transmittance")?.unwrap_or(Rgb::ONE),
                alpha: alphas(t, false)?[0],
                attenuation: attenuation(t)?,
                dispersion,
            })
        }
        "conductor" => {
            t.allow(&["type", "metal", "eta", "k", "f0", "alpha"])?;
            Ok(MaterialSpec::Conductor {
                fresnel: conductor_fresnel(t)?,
                alpha: alphas(t, true)?,
            })
        }
        "pbr" => {
            t.allow(&[
                "type",
                "base_color",
                "metallic",
                "roughness",
                "specular",
                "metallic_roughness",
                "normal_map",
                "normal_scale",
            ])?;
            let base_color = match t.get("base_color") {
                None => ColorSpec::Constant(Rgb::splat(0.8)),
                Some(v) => color_spec(t, v)?,
            };
            let data = |key: &str| -> Result<Option<ImageRef>> {
                t.get(key)
                    .map(|v| t.cx.file(v, &t.label(key)).map(ImageRef::File))
                    .transpose()
            };
            let normal_map = data("normal_map")?;
            if normal_map.is_none() && t.get("normal_scale").is_some() {
                return Err(t.cx.err(
                    t.get("normal_scale").map_or(0..0, |v| v.span()),
                    "'normal_scale' needs a 'normal_map'",
                ));
            }
            let normal_scale = t.opt_f32("normal_scale")?.unwrap_or(1.0);
            Ok(MaterialSpec::Pbr(PbrSpec {
                base_color,
                metallic: unit_interval(t, "metallic", 0.0)?,
                roughness: unit_interval(t, "roughness", 0.5)?,
                specular: unit_interval(t, "specular", 1.0)?,
                metallic_roughness: data("metallic_roughness")?,
                normal_map: normal_map.map(|n| (n, normal_scale)),
                coverage: crate::scene::Coverage::Opaque,
            }))
        }
        other => Err(bad_type(
            t,
            other,
            &["diffuse", "mirror", "glass", "conductor", "pbr"],
        )),
    }
}

/// Glass's absorption inside, `attenuation = { color = [r, g, b], distance = d }`: white light
/// that travels `d` inside comes out as `color` (`KHR_materials_volume`'s attenuation colour
/// and distance).
/// How a glass's index varies with wavelength: one of `glass` (a name), `abbe` (the Abbe
/// number, with `ior` the index at the d line), `cauchy = { a, b }` or `sellmeier = { b, c }`
/// (coefficients in micrometres, as catalogues give them). The last three give the index
/// themselves, so they refuse an `ior`.
fn dispersion(t: &Table, ior: f32) -> Result<Dispersion> {
    let given: Vec<&str> = ["glass", "abbe", "cauchy", "sellmeier"]
        .into_iter()
        .filter(|k| t.get(k).is_some())
        .collect();
    let Some(&key) = given.first() else {
        return Ok(Dispersion::None);
    };
    let v = t.required(key)?;
    if given.len() > 1 {
        return Err(t.cx.err(
            v.span(),
            format!(
                "{}: give one of glass, abbe, cauchy and sellmeier",
                t.label(key)
            ),
        ));
    }
    if key != "abbe"
        && let Some(i) = t.get("ior")
    {
        return Err(t.cx.err(
            i.span(),
            format!("{} gives the index itself; leave out 'ior'", t.label(key)),
        ));
    }
    let d = match key {
        "glass" => {
            let name = t.req_str("glass")?;
            Dispersion::named(name).ok_or_else(|| {
                let names: Vec<&str> = Dispersion::names().collect();
                t.cx.err(
                    v.span(),
                    format!(
                        "{}: unknown glass '{name}' (expected one of: {})",
                        t.label(key),
                        names.join(", ")
                    ),
                )
            })?
        }
        "abbe" => Dispersion::from_abbe(ior, t.positive("abbe")?),
        "cauchy" => {
            let c = t.cx.table(v, &t.label(key))?;
            c.allow(&["a", "b"])?;
            Dispersion::Cauchy {
                a: c.positive("a")?,
                b: c.opt_f32("b")?.unwrap_or(0.0),
            }
        }
        _ => {
            let s = t.cx.table(v, &t.label(key))?;
            s.allow(&["b", "c"])?;
            Dispersion::Sellmeier {
                b: s.req_vec3("b")?.to_array(),
                c: s.req_vec3("c")?.to_array(),
            }
        }
    };
    if !d.is_valid() {
        return Err(t.cx.err(
            v.span(),
            format!(
                "{} gives an index outside 1 to 5 somewhere from 360 to 830 nm",
                t.label(key)
            ),
        ));
    }
    Ok(d)
}

fn attenuation(t: &Table) -> Result<Option<Attenuation>> {
    let Some(v) = t.get("attenuation") else {
        return Ok(None);
    };
    let a = t.cx.table(v, &t.label("attenuation"))?;
    a.allow(&["color", "distance"])?;
    let c = a.required("color")?;
    let color = color(t.cx, c, &a.label("color"))?;
    if color.max_element() > 1.0 {
        return Err(t.cx.err(
            c.span(),
            format!(
                "{} must be between 0 and 1 (absorption only removes light)",
                a.label("color")
            ),
        ));
    }
    Ok(Some(Attenuation {
        color,
        distance: a.positive("distance")?,
    }))
}

/// A number in [0, 1], or `default` when absent.
fn unit_interval(t: &Table, key: &str, default: f32) -> Result<f32> {
    let x = t.opt_f32(key)?.unwrap_or(default);
    if !(0.0..=1.0).contains(&x) {
        return Err(t.cx.err(
            t.get(key).map_or(0..0, |v| v.span()),
            format!("{} must be between 0 and 1", t.label(key)),
        ));
    }
    Ok(x)
}

/// `alpha`: one GGX roughness (default 0, smooth), or `[alpha_u, alpha_v]` where allowed; each
/// in [0, 1].
fn alphas(t: &Table, two: bool) -> Result<[f32; 2]> {
    let Some(v) = t.get("alpha") else {
        return Ok([0.0, 0.0]);
    };
    let label = t.label("alpha");
    let a = match v.get_ref() {
        DeValue::Array(_) if two => floats::<2>(t.cx, v, &label)?,
        _ => [float(t.cx, v, &label)?; 2],
    };
    if a.iter().any(|x| !(0.0..=1.0).contains(x)) {
        let expected = if two {
            "a number or [u, v], each"
        } else {
            "a number"
        };
        return Err(t.cx.err(
            v.span(),
            format!("{label} must be {expected} between 0 (smooth) and 1"),
        ));
    }
    Ok(a)
}

/// A conductor's reflectance: `metal = "gold"`, `eta` with `k`, or `f0`.
fn conductor_fresnel(t: &Table) -> Result<ConductorSpec> {
    let names: Vec<&str> = Metal::ALL.iter().map(|m| m.name()).collect();
    let metal = one_of(t, "metal", &names)?;
    let (eta, k, f0) = (t.opt_color("eta")?, t.opt_color("k")?, t.opt_color("f0")?);
    match (metal, eta, k, f0) {
        (Some(name), None, None, None) => Ok(ConductorSpec::Metal(
            Metal::ALL
                .into_iter()
                .find(|m| m.name() == name.as_str())
                .unwrap_or(Metal::Gold),
        )),
        (None, Some(eta), Some(k), None) => Ok(ConductorSpec::Ior { eta, k }),
        (None, None, None, Some(f0)) => {
            if f0.max_element() > 1.0 {
                return Err(t.cx.err(
                    t.get("f0").map_or(0..0, |v| v.span()),
                    "'f0' (reflectance at normal incidence) must not exceed 1",
                ));
            }
            Ok(ConductorSpec::F0(f0))
        }
        _ => Err(t.cx.err(
            t.span.start..t.span.start + 1,
            format!(
                "{} needs exactly one of 'metal' ({}), 'eta' with 'k', or 'f0'",
                t.what,
                names.join(", ")
            ),
        )),
    }
}

pub(super) fn bad_type(t: &Table, found: &str, expected: &[&str]) -> Error {
    let span = t.get("type").map_or(t.span.clone(), |v| v.span());
    let hint = did_you_mean(found, expected);
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
pub(super) fn color_spec(t: &Table, v: &Value) -> Result<ColorSpec> {
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
