//! The scene-level tables: camera, render settings, materials and their albedo textures.

use super::values::{Table, Value, array, color, float, floats, integer, str_of};
use crate::description::source::did_you_mean;
use crate::description::{
    CameraSpec, ColorSpec, GATHER_MODES, INTEGRATORS, KERNELS, MaterialSpec, RenderSpec,
};
use crate::error::{Error, Result};
use crate::film::PixelFilter;
use crate::math::{Rgb, Vec2, Vec3};
use crate::render::MAX_RESOLUTION;
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

pub(super) fn render(t: &Table) -> Result<RenderSpec> {
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
        "filter",
        "kernel",
        "gather",
        "k",
        "alpha",
        "photons_per_pass",
    ])?;
    let filter = match t.get("filter") {
        Some(v) => {
            let text = str_of(t.cx, v, &t.label("filter"))?;
            text.parse::<PixelFilter>()
                .map_err(|e| t.cx.err(v.span(), e))?;
            Some(text.to_owned())
        }
        None => None,
    };
    let alpha = t.opt_f32("alpha")?.map(f64::from);
    if let Some(a) = alpha
        && !(a > 0.0 && a < 1.0)
    {
        let span = t.get("alpha").map_or(0..0, |v| v.span());
        return Err(t.cx.err(span, "'alpha' must be between 0 and 1"));
    }
    const U32: u64 = u32::MAX as u64;
    Ok(RenderSpec {
        integrator: one_of(t, "integrator", INTEGRATORS)?,
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
        filter,
        kernel: one_of(t, "kernel", KERNELS)?,
        gather: one_of(t, "gather", GATHER_MODES)?,
        k: t.opt_int("k", 1 << 16)?,
        alpha,
        photons_per_pass: t.opt_int("photons_per_pass", 1 << 40)?,
    })
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
