//! The environment light a front end gives or changes on top of a scene's own: a sky (an
//! equirectangular image or a uniform radiance) replacing the scene's, its rotation about +y
//! and its intensity. The command line's `--env`, `--env-rotate` and `--env-intensity`, a
//! checkpoint's and a job's [`EnvSettings`] are applied here.

use super::{EnvironmentSpec, SceneDesc, Sky};
use crate::error::{Error, Result, SettingError};
use crate::io::checkpoint::EnvSettings;
use crate::math::Rgb;
use std::path::Path;

fn refuse(name: &'static str, value: impl ToString, problem: impl Into<String>) -> Error {
    Error::Setting(SettingError {
        name,
        value: Some(value.to_string()),
        problem: problem.into(),
    })
}

/// Apply `env` to `desc`. Returns a warning when a setting has no effect.
pub fn apply(desc: &mut SceneDesc, env: &EnvSettings) -> Result<Option<String>> {
    if let Some(i) = env.intensity
        && !(i >= 0.0 && i.is_finite())
    {
        return Err(refuse("env_intensity", i, "must be a finite number ≥ 0"));
    }
    if let Some(r) = env.rotate_deg
        && !r.is_finite()
    {
        return Err(refuse(
            "env_rotate",
            r,
            "must be a finite number of degrees",
        ));
    }
    if let Some(value) = &env.sky {
        let sky = parse_sky(value).map_err(|problem| refuse("env", value, problem))?;
        desc.set_environment(EnvironmentSpec {
            sky,
            intensity: 1.0,
            rotate_deg: 0.0,
        });
    }
    let changed = [
        ("env_rotate", env.rotate_deg),
        ("env_intensity", env.intensity),
    ];
    let Some(&(name, Some(value))) = changed.iter().find(|(_, v)| v.is_some()) else {
        return Ok(None);
    };
    let Some(e) = desc.environment_mut() else {
        return Err(refuse(
            name,
            value,
            "changes the scene's environment light, and the scene has none: give a sky too",
        ));
    };
    if let Some(r) = env.rotate_deg {
        e.rotate_deg = r;
    }
    if let Some(i) = env.intensity {
        e.intensity = i;
    }
    Ok(
        (matches!(e.sky, Sky::Uniform(_)) && env.rotate_deg.is_some())
            .then(|| "rotating a uniform sky has no effect".to_owned()),
    )
}

/// Whether `value` is a colour (`R,G,B` or one number) rather than an image file.
pub fn is_colour(value: &str) -> bool {
    value.split(',').all(|p| p.trim().parse::<f32>().is_ok())
}

/// `R,G,B` or one number: a uniform sky; anything else: an image file (made absolute, since
/// the scene's own files are relative to the scene).
pub fn parse_sky(value: &str) -> std::result::Result<Sky, String> {
    if is_colour(value) {
        let n: Vec<f32> = value.split(',').flat_map(|p| p.trim().parse()).collect();
        let rgb = match n[..] {
            [x] => Rgb::splat(x),
            [r, g, b] => Rgb::new(r, g, b),
            _ => return Err("a colour is R,G,B or one number".into()),
        };
        if !rgb.is_finite() || rgb.min_element() < 0.0 {
            return Err("a sky's radiance must be finite and not negative".into());
        }
        return Ok(Sky::Uniform(rgb));
    }
    let path = Path::new(value);
    if crate::io::image::EnvironmentFormat::from_path(path).is_none() {
        return Err("not a colour R,G,B, nor an image with extension .exr, .hdr or .pfm".into());
    }
    if !path.is_file() {
        return Err("no such file".into());
    }
    std::path::absolute(path)
        .map(Sky::File)
        .map_err(|e| e.to_string())
}

/// `env` as a checkpoint or job keeps it: a sky file's path made absolute (so a resume from
/// another folder finds it), a colour as given.
pub fn portable(env: &EnvSettings) -> EnvSettings {
    let sky = env.sky.as_ref().map(|v| {
        if is_colour(v) {
            v.clone()
        } else {
            std::path::absolute(v).map_or_else(|_| v.clone(), |p| p.to_string_lossy().into_owned())
        }
    });
    EnvSettings { sky, ..env.clone() }
}
