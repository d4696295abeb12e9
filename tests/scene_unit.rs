//! A scene renders the same whatever unit it was modelled in: the built-in Cornell box (0.56
//! units wide) against the same box at 2⁻¹⁰ of its size, as a half-metre box would be in a
//! scene modelled in kilometres. A power of two scales every coordinate and distance exactly,
//! so the two renders follow nearly the same paths, and their images may differ only where
//! something measured in absolute units (a surface offset) decides.
//!
//! The BVH's node test once skipped every box a ray left within 10⁻⁴ scene units of its
//! origin: this box at 2⁻¹⁰ rendered 11% dark in `path` and 10% in `sppm`.

use photon::description::build::build;
use photon::description::toml_read;
use photon::film::PixelFilter;
use photon::integrator::{Integrator, PathConfig};
use photon::math::Rgb;
use photon::progressive::{Method, ProgressiveConfig, ProgressiveState};
use photon::render::{RenderSettings, render};
use photon::scene::Scene;
use std::path::Path;

/// The keys of the scene file that hold lengths or positions.
const LENGTHS: [&str; 5] = ["vertices", "center", "radius", "position", "look_at"];

/// Every number on the lines of `text` that give lengths or positions, times `scale`.
fn scaled_numbers(text: &str, scale: f64) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let is_length = LENGTHS
            .iter()
            .any(|k| line.trim_start().starts_with(&format!("{k} =")));
        if !is_length {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        let (key, value) = line.split_once('=').expect("a key = value line");
        out.push_str(key);
        out.push('=');
        let mut number = String::new();
        for c in value.chars().chain(std::iter::once(' ')) {
            if c.is_ascii_digit() || matches!(c, '.' | '-' | 'e' | 'E' | '+') {
                number.push(c);
                continue;
            }
            if !number.is_empty() {
                let x: f64 = number.parse().expect("a number");
                out.push_str(&format!("{:?}", x * scale));
                number.clear();
            }
            out.push(c);
        }
        out.push('\n');
    }
    out
}

fn cornell(scale: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.toml");
    let text = std::fs::read_to_string(&path).expect("scenes/cornell.toml");
    let text = scaled_numbers(&text, scale).replace("[512, 512]", "[32, 32]");
    let desc = toml_read::read_str(&text, &path, path.parent().expect("folder")).expect("reads");
    build(&desc).expect("builds")
}

fn path_mean(scene: &Scene) -> Rgb {
    let settings = RenderSettings {
        seed: 7,
        filter: PixelFilter::Box,
        ..RenderSettings::new(32, 32, 128)
    };
    let integrator = Integrator::Path(PathConfig::default());
    render(scene, &integrator, &settings, &|_, _| {})
        .expect("renders")
        .image
        .mean()
}

fn sppm_mean(scene: &Scene) -> Rgb {
    let config = ProgressiveConfig {
        method: Method::Sppm,
        width: 32,
        height: 32,
        seed: 7,
        alpha: 2.0 / 3.0,
        photons_per_pass: 20_000,
        initial_radius: None,
        max_depth: 16,
        light_samples: 1,
        spectral: false,
    };
    let mut state = ProgressiveState::new(scene, config, 0).expect("valid");
    for _ in 0..8 {
        state.run_pass(scene).expect("pass");
    }
    state.image().mean()
}

#[test]
fn the_cornell_box_renders_the_same_at_a_thousandth_of_its_size() {
    let unit = cornell(1.0);
    let small = cornell(2f64.powi(-10));
    for (name, mean) in [
        ("path", path_mean as fn(&Scene) -> Rgb),
        ("sppm", sppm_mean),
    ] {
        let (want, got) = (mean(&unit), mean(&small));
        let ratio = got / want;
        eprintln!("{name}: {got} at 2⁻¹⁰ of the size, {want} at its own: {ratio}");
        assert!(
            (ratio - 1.0).abs().max_element() < 0.01,
            "{name}: the small box renders {ratio} of the unit one"
        );
    }
}
