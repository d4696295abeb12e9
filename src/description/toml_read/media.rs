//! Participating media: `[media.NAME]` tables and the shapes that bound them.

use super::values::Table;
use crate::description::{GridSpec, MediaSides, MediumSpec};
use crate::error::Result;
use crate::math::Rgb;

/// A medium, given by its coefficients (`sigma_a`, `sigma_s`) or, as Mitsuba writes it, by
/// its single-scattering `albedo` and `density` (σt), with the Henyey–Greenstein `g`.
pub(super) fn medium(t: &Table) -> Result<MediumSpec> {
    t.allow(&[
        "sigma_a",
        "sigma_s",
        "albedo",
        "density",
        "g",
        "grid",
        "grid_name",
        "transform",
    ])?;
    let by_coefficients = t.get("sigma_a").is_some() || t.get("sigma_s").is_some();
    let by_albedo = t.get("albedo").is_some() || t.get("density").is_some();
    let at_start = t.span.start..t.span.start + 1;
    if by_coefficients && by_albedo {
        return Err(t.cx.err(
            at_start,
            format!(
                "{} gives both sigma_a/sigma_s and albedo/density; give one pair",
                t.what
            ),
        ));
    }
    let (sigma_a, sigma_s) = if by_albedo {
        let albedo = t.opt_color("albedo")?.unwrap_or(Rgb::ONE);
        if albedo.max_element() > 1.0 {
            let v = t.get("albedo").map_or(at_start.clone(), |v| v.span());
            return Err(t
                .cx
                .err(v, format!("{} must be at most 1", t.label("albedo"))));
        }
        let density = t.opt_color("density")?.unwrap_or(Rgb::ONE);
        (density * (Rgb::ONE - albedo), density * albedo)
    } else {
        (
            t.opt_color("sigma_a")?.unwrap_or(Rgb::ZERO),
            t.opt_color("sigma_s")?.unwrap_or(Rgb::ZERO),
        )
    };
    let g = t.opt_f32("g")?.unwrap_or(0.0);
    if !(g > -1.0 && g < 1.0) {
        let v = t.get("g").map_or(at_start, |v| v.span());
        return Err(t.cx.err(
            v,
            format!(
                "{} must be between -1 and 1 (exclusive): -1 scatters straight back, 1 straight on",
                t.label("g")
            ),
        ));
    }
    Ok(MediumSpec {
        sigma_a,
        sigma_s,
        g,
        grid: grid(t)?,
    })
}

/// `grid = "FILE"` with its optional `grid_name` (default "density") and `transform`.
fn grid(t: &Table) -> Result<Option<GridSpec>> {
    let Some(file) = t.get("grid") else {
        for key in ["grid_name", "transform"] {
            if let Some(v) = t.get(key) {
                return Err(t.cx.err(
                    v.span(),
                    format!("{} places a grid: give 'grid' too", t.label(key)),
                ));
            }
        }
        return Ok(None);
    };
    Ok(Some(GridSpec {
        file: t.cx.file(file, &t.label("grid"))?,
        name: t.opt_str("grid_name")?.unwrap_or("density").to_owned(),
        transform: match t.get("transform") {
            Some(v) => super::shapes::transform(t.cx, v)?,
            None => Vec::new(),
        },
    }))
}

/// A shape's `interior` and `exterior` media, if it names either.
pub(super) fn sides(t: &Table, media: &[&str]) -> Result<Option<MediaSides>> {
    let interior = t.name_ref("interior", media, "medium", "[media]")?;
    let exterior = t.name_ref("exterior", media, "medium", "[media]")?;
    Ok((interior.is_some() || exterior.is_some()).then_some(MediaSides { interior, exterior }))
}
