//! Reading `.toml` scene files (format: docs/scene-format.md) into a [`SceneDesc`].
//!
//! The document is parsed into TOML values that keep their byte spans, then walked by hand:
//! that way every error names the line and column of the offending key or value, unknown keys
//! get the nearest valid key as a suggestion, and referenced files are checked while their
//! span is still at hand.

mod media;
mod scene;
mod shapes;
mod values;

use super::source::{Diagnostic, Origins};
use super::{LightSpec, SceneDesc};
use crate::error::{Error, Result};
use crate::settings::RenderOptions;
use scene::{camera, material, render};
use shapes::{light, shape};
use std::path::Path;
use toml::de::DeTable;
use values::{Cx, Table};

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
    let text = crate::io::input::read_text(path)?;
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
    let mut origins = Origins::in_file(path, text);
    root.allow(&[
        "name",
        "medium",
        "camera",
        "render",
        "materials",
        "media",
        "shapes",
        "lights",
    ])?;
    let name = match root.opt_str("name")? {
        Some(n) => n.to_owned(),
        None => path
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
    };
    let camera = match root.get("camera") {
        Some(v) => {
            let t = cx.table(v, "[camera]")?;
            origins.set_camera(t.span.clone());
            camera(&t)?
        }
        None => {
            return Err(Error::SceneFile(Box::new(Diagnostic::whole_file(
                path,
                "the scene has no [camera] table (position and look_at are required)",
            ))));
        }
    };
    let render = match root.get("render") {
        Some(v) => render(&cx.table(v, "[render]")?)?,
        None => RenderOptions::default(),
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
    let mut media = Vec::new();
    if let Some(v) = root.get("media") {
        let t = cx.table(v, "[media]")?;
        for (key, value) in t.map.iter() {
            let what = format!("medium '{}'", key.get_ref());
            media.push((
                key.get_ref().to_string(),
                media::medium(&cx.table(value, &what)?)?,
            ));
        }
    }
    let medium_names: Vec<&str> = media.iter().map(|(n, _)| n.as_str()).collect();
    let medium = root.name_ref("medium", &medium_names, "medium", "[media]")?;
    let names = shapes::Names {
        materials: &names,
        media: &medium_names,
    };
    let mut shapes = Vec::new();
    for (i, v) in root.array_of_tables("shapes")?.into_iter().enumerate() {
        let t = cx.table(v, &format!("shape {}", i + 1))?;
        origins.push_shape(t.span.clone());
        shapes.push(shape(&t, &names, false)?);
    }
    let mut lights = Vec::new();
    for (i, v) in root.array_of_tables("lights")?.into_iter().enumerate() {
        let t = cx.table(v, &format!("light {}", i + 1))?;
        let l = light(&t, names.materials)?;
        origins.push_light(t.span.clone());
        if matches!(l, LightSpec::Environment(_))
            && lights
                .iter()
                .any(|l| matches!(l, LightSpec::Environment(_)))
        {
            return Err(cx.err(
                t.span.start..t.span.start + 1,
                "a scene has at most one environment light; this is the second",
            ));
        }
        lights.push(l);
    }
    Ok(SceneDesc {
        name,
        camera,
        render,
        materials,
        shapes,
        lights,
        media,
        medium,
        base_dir: base_dir.to_owned(),
        origins,
        default_sky_warning: None,
    })
}
