//! TOML scene files: every documented example and every file in scenes/ reads and builds; the
//! built-ins survive a round trip through TOML bit for bit; transforms, light power and
//! textures mean what the documentation says.

use crate::common;

use photon::description::builtin::BUILTINS;
use photon::description::{SceneDesc, build::build, toml_read::read_str, toml_write::to_toml};
use photon::film::{Image, PixelFilter};
use photon::integrator::{Integrator, PhotonIntegrator, PhotonSettings};
use photon::material::Material;
use photon::math::{Ray, Rgb, Vec3};
use photon::photon::{PhotonConfig, trace_photons};
use photon::render::{RenderSettings, render};
use photon::scene::Scene;
use std::f32::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(text: &str) -> SceneDesc {
    read_str(text, Path::new("test.toml"), &repo().join("scenes"))
        .unwrap_or_else(|e| panic!("{e}\n--- in ---\n{text}"))
}

fn scene(text: &str) -> Scene {
    build(&read(text)).unwrap_or_else(|e| panic!("{e}\n--- in ---\n{text}"))
}

/// The ```toml blocks of the format documentation.
fn doc_examples() -> Vec<String> {
    let doc = std::fs::read_to_string(repo().join("docs/scene-format.md")).expect("doc");
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in doc.lines() {
        match (&mut current, line.trim_start()) {
            (None, "```toml") => current = Some(String::new()),
            (Some(b), "```") => {
                blocks.push(std::mem::take(b));
                current = None;
            }
            (Some(b), _) => {
                b.push_str(line);
                b.push('\n');
            }
            (None, _) => {}
        }
    }
    blocks
}

#[test]
fn every_documented_example_reads_and_builds() {
    let blocks = doc_examples();
    assert!(blocks.len() >= 15, "found only {} examples", blocks.len());
    let prelude = blocks
        .iter()
        .find(|b| b.contains("# prelude"))
        .expect("the doc has a prelude")
        .clone();
    for block in &blocks {
        let text = if block.contains("[camera]") {
            block.clone()
        } else {
            format!("{prelude}\n{block}")
        };
        let desc = read(&text);
        // A scene with nothing in it is legal to read; building needs something to render.
        if !desc.shapes.is_empty() || !desc.lights.is_empty() {
            scene(&text);
        }
    }
}

#[test]
fn every_documented_example_survives_a_round_trip_through_toml() {
    // Covers every shape, light, material, texture and transform form the writer knows.
    let blocks = doc_examples();
    let prelude = blocks
        .iter()
        .find(|b| b.contains("# prelude"))
        .expect("prelude")
        .clone();
    let scenes = repo().join("scenes");
    let mut all = String::new();
    for block in &blocks {
        let text = if block.contains("[camera]") {
            block.clone()
        } else {
            format!("{prelude}\n{block}")
        };
        let desc = read(&text);
        let written = to_toml(&desc, &scenes).expect("writes");
        let back = read_str(&written, Path::new("w.toml"), &scenes)
            .unwrap_or_else(|e| panic!("{e}\n--- written ---\n{written}"));
        assert_eq!(back, desc, "--- written ---\n{written}");
        all += &written;
    }
    for needle in [
        "[media.",
        "interior = ",
        "exterior = ",
        "\nmedium = ",
        "\"triangles\"",
        "matrix",
        "look_at = {",
        "checker",
        "texture",
        "\"pot\"",
        "\"directional\"",
        "\"spot\"",
        "emission = {",
        "attenuation = {",
    ] {
        assert!(all.contains(needle), "the examples never write {needle}");
    }
}

#[test]
fn every_example_scene_reads_builds_and_has_light() {
    let mut count = 0;
    for entry in std::fs::read_dir(repo().join("scenes")).expect("scenes/") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        count += 1;
        let desc =
            photon::description::toml_read::read_file(&path).unwrap_or_else(|e| panic!("{e}"));
        let s = build(&desc).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            s.total_power().min_element() > 0.0,
            "{} emits no light",
            path.display()
        );
    }
    assert!(count >= 5, "scenes/ has {count} scenes");
}

#[test]
fn the_built_in_scene_files_are_what_export_writes() {
    for name in ["seed", "cornell"] {
        let b = BUILTINS.iter().find(|b| b.name == name).expect("built-in");
        let written = to_toml(&(b.desc)(), &repo().join("scenes")).expect("export");
        let file = std::fs::read_to_string(repo().join(format!("scenes/{name}.toml")))
            .expect("scene file");
        assert_eq!(
            written, file,
            "scenes/{name}.toml is out of date: run `photon scenes --export {name} -o scenes/{name}.toml`"
        );
    }
}

fn small_render(scene: &Scene) -> Image {
    let config = PhotonConfig {
        photons: 20_000,
        global_photons: Some(5_000),
        ..PhotonConfig::default()
    };
    let maps = trace_photons(scene, &config, &|_, _| {}).expect("traces");
    let settings = PhotonSettings::for_scene(scene);
    let integrator = Integrator::Photon(Box::new(PhotonIntegrator::new(settings, Arc::new(maps))));
    let s = RenderSettings {
        seed: 3,
        filter: PixelFilter::Box,
        ..RenderSettings::new(24, 24, 1)
    };
    render(scene, &integrator, &s, &|_, _| {})
        .expect("renders")
        .image
}

#[test]
fn built_ins_round_trip_through_toml_to_the_identical_image() {
    for b in BUILTINS {
        let desc = (b.desc)();
        let text = to_toml(&desc, Path::new("")).expect("export");
        let mut back = read_str(&text, Path::new("x.toml"), Path::new("")).expect("reads back");
        back.base_dir = desc.base_dir.clone();
        assert_eq!(
            back, desc,
            "{}: the description changed in the round trip",
            b.name
        );
        let original = build(&desc).expect("builds");
        let reread = build(&back).expect("builds");
        assert_eq!(original.content_hash(), reread.content_hash(), "{}", b.name);
        let (a, c) = (small_render(&original), small_render(&reread));
        let bits = |i: &Image| -> Vec<u32> {
            i.pixels
                .iter()
                .flat_map(|p| p.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&a), bits(&c), "{}: images differ", b.name);
        assert!(
            a.pixels.iter().any(|p| p.max_element() > 0.0),
            "{}: black",
            b.name
        );
    }
}

const CAMERA: &str = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n";

#[test]
fn transforms_compose_scale_rotate_translate_in_order() {
    let s = scene(&format!(
        "{CAMERA}
[materials.m]
type = \"diffuse\"
[[shapes]]
type = \"box\"
min = [-0.5, -0.5, -0.5]
max = [0.5, 0.5, 0.5]
material = \"m\"
transform = {{ translate = [1, 1, 0], scale = [2, 1, 1], rotate = {{ axis = [0, 0, 1], angle = 90 }} }}
[[lights]]
type = \"point\"
position = [0, 0, 3]
power = 1
"
    ));
    // Scaled to 2×1×1 along x, turned 90° about z (now 1 wide, 2 tall), then moved by (1, 1, 0).
    let b = s.bounds();
    let close = |a: Vec3, e: Vec3| (a - e).abs().max_element() < 1e-5;
    assert!(close(b.min, Vec3::new(0.5, 0.0, -0.5)), "min {:?}", b.min);
    assert!(close(b.max, Vec3::new(1.5, 2.0, 0.5)), "max {:?}", b.max);

    // A list applies first to last: translate then rotate moves the box around the origin.
    let s = scene(&format!(
        "{CAMERA}
[materials.m]
type = \"diffuse\"
[[shapes]]
type = \"sphere\"
radius = 0.5
material = \"m\"
transform = [{{ translate = [2, 0, 0] }}, {{ rotate = {{ axis = [0, 0, 1], angle = 90 }} }}, {{ scale = 2 }}]
[[lights]]
type = \"point\"
position = [0, 0, 3]
power = 1
"
    ));
    let c = 0.5 * (s.bounds().min + s.bounds().max);
    assert!(close(c, Vec3::new(0.0, 4.0, 0.0)), "centre {c:?}");
    assert!((s.bounds().extent().x - 2.0).abs() < 1e-5);
}

#[test]
fn analytic_shapes_refuse_non_uniform_scales() {
    let desc = read(&format!(
        "{CAMERA}
[materials.m]
type = \"diffuse\"
[[shapes]]
type = \"sphere\"
radius = 1
material = \"m\"
transform = {{ scale = [1, 2, 1] }}
"
    ));
    let e = build(&desc).err().expect("refused").to_string();
    assert!(e.contains("uniform"), "{e}");
}

#[test]
fn lights_given_by_power_emit_that_power() {
    let s = scene(&format!(
        "{CAMERA}
[[lights]]
type = \"quad\"
vertices = [[0, 0, 0], [0.6, 0, 0], [0.6, 0.6, 0], [0, 0.6, 0]]
power = [10, 20, 30]

[[lights]]
type = \"sphere\"
center = [3, 0, 0]
radius = 0.25
power = 5
two_sided = false

[[lights]]
type = \"point\"
position = [0, 2, 0]
power = 7

[[lights]]
type = \"spot\"
position = [0, 2, 0]
look_at = [0, 0, 0]
power = 11
angle = 40
falloff = 10
"
    ));
    let p = s.total_power();
    let others = 5.0 + 7.0 + 11.0;
    let expected = Vec3::new(10.0 + others, 20.0 + others, 30.0 + others);
    assert!(
        (p - expected).abs().max_element() < 1e-3 * expected.max_element(),
        "power {p:?}, expected {expected:?}"
    );
    // Radiance of the quad: Φ / (π A).
    let quad = s
        .lights()
        .iter()
        .find_map(|l| match l {
            photon::light::Light::Area(a) if (a.area() - 0.36).abs() < 1e-4 => Some(a),
            _ => None,
        })
        .expect("the quad light");
    let l = quad.emitted(Vec3::Z, Vec3::Z, &photon::spectrum::Lambda::Rgb);
    assert!((l.x - 10.0 / (PI * 0.36)).abs() < 1e-3, "radiance {l:?}");
    // A point light's intensity is Φ / 4π.
    let point = s.lights().iter().find_map(|l| match l {
        photon::light::Light::Point(p) => Some(p),
        _ => None,
    });
    assert!((point.expect("point").intensity.rgb().x - 7.0 / (4.0 * PI)).abs() < 1e-6);
}

fn albedo_at(s: &Scene, origin: Vec3, dir: Vec3) -> Rgb {
    let hit = s
        .intersect(&Ray::new(origin, dir), f32::INFINITY)
        .expect("hit");
    match s.material_at(&hit) {
        Material::Lambertian(l) => l.albedo,
        other => panic!("expected a diffuse material, got {other:?}"),
    }
}

#[test]
fn checker_and_image_textures_follow_the_quad_coordinates() {
    let dir = common::temp_dir("textures");
    // 2×2 sRGB image: top row red, white; bottom row black, mid-grey 128.
    let mut img = image::RgbImage::new(2, 2);
    img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    img.put_pixel(1, 0, image::Rgb([255, 255, 255]));
    img.put_pixel(0, 1, image::Rgb([0, 0, 0]));
    img.put_pixel(1, 1, image::Rgb([128, 128, 128]));
    img.save(dir.join("t.png")).expect("png");
    let text = format!(
        "{CAMERA}
[materials.checker]
type = \"diffuse\"
albedo = {{ checker = {{ even = [1, 1, 1], odd = [0, 0, 0], scale = 2 }} }}
[materials.image]
type = \"diffuse\"
albedo = {{ texture = \"t.png\", tint = [1, 1, 0.5] }}
[[shapes]]
type = \"quad\"
vertices = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
material = \"checker\"
[[shapes]]
type = \"quad\"
vertices = [[2, 0, 0], [3, 0, 0], [3, 1, 0], [2, 1, 0]]
material = \"image\"
[[lights]]
type = \"point\"
position = [0, 0, 3]
power = 1
"
    );
    let desc = read_str(&text, &dir.join("t.toml"), &dir).expect("reads");
    let s = build(&desc).expect("builds");
    let down = -Vec3::Z;
    let at = |x: f32, y: f32| albedo_at(&s, Vec3::new(x, y, 1.0), down);
    // Checker: 2 squares per unit, (0, 0) even.
    assert_eq!(at(0.25, 0.25), Rgb::ONE);
    assert_eq!(at(0.75, 0.25), Rgb::ZERO);
    assert_eq!(at(0.75, 0.75), Rgb::ONE);
    // Image: v up, so the top row of the file is at y near 1; sRGB 128 decodes to 0.2158.
    let red = at(2.25, 0.75);
    assert!(
        (red - Rgb::new(1.0, 0.0, 0.0)).abs().max_element() < 1e-5,
        "{red:?}"
    );
    let white = at(2.75, 0.75);
    assert!(
        (white - Rgb::new(1.0, 1.0, 0.5)).abs().max_element() < 1e-5,
        "{white:?}"
    );
    let grey = at(2.75, 0.25);
    assert!(
        (grey.x - 0.2158).abs() < 1e-3 && (grey.z - 0.1079).abs() < 1e-3,
        "{grey:?}"
    );
    assert_eq!(at(2.25, 0.25), Rgb::ZERO);

    // JPEG textures decode the same way (lossy: within a few percent of a flat colour).
    image::RgbImage::from_pixel(8, 8, image::Rgb([200, 100, 50]))
        .save(dir.join("flat.jpg"))
        .expect("jpeg");
    let text = text
        .replace("t.png", "flat.jpg")
        .replace("tint = [1, 1, 0.5]", "tint = 1");
    let s = build(&read_str(&text, &dir.join("t.toml"), &dir).expect("reads")).expect("builds");
    let c = albedo_at(&s, Vec3::new(2.5, 0.5, 1.0), down);
    let want = Rgb::new(0.5776, 0.1270, 0.0319);
    assert!((c - want).abs().max_element() < 0.02, "{c:?} vs {want:?}");
}

#[test]
fn command_line_settings_override_the_scene_and_the_scene_overrides_defaults() {
    let desc = read(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nresolution = [40, 30]\n[render]\nintegrator = \"path\"\nspp = 3\nseed = 9\n",
    );
    assert_eq!(
        desc.render.integrator,
        Some(photon::settings::IntegratorKind::Path)
    );
    assert_eq!((desc.render.spp, desc.render.seed), (Some(3), Some(9)));
    assert_eq!((desc.camera.width, desc.camera.height), (40, 30));
}

/// A scene file renders whole: the ranges that split a render are chosen per run, and a
/// scene's counts are bounded like the command line's.
#[test]
fn a_scene_cannot_choose_a_part_of_its_render_or_an_endless_one() {
    let head = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n[render]\n";
    for (render, needle) in [
        ("sample_range = [0, 2]\n", "chosen per run"),
        ("pass_range = [0, 2]\n", "chosen per run"),
        ("max_depth = 100000\n", "must be at most 65536"),
        ("gather_rays = 100000\n", "must be at most 65536"),
    ] {
        let text = format!("{head}{render}");
        let e = read_str(&text, Path::new("test.toml"), &repo().join("scenes"))
            .expect_err(render)
            .to_string();
        assert!(e.contains("test.toml:5:") && e.contains(needle), "{e}");
    }
}
