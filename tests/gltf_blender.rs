//! glTF files written by Blender's own exporter (`tests/fixtures/blender/`, made by
//! `make_fixtures.py` with bpy from PyPI): they load with their materials (metals as metals,
//! glass as rough glass, textures and normal maps attached), a file without lights renders
//! under the default sky with a warning, and the sun and the emissive quad light the others.

use crate::common;

use photon::description::gltf::DEFAULT_SKY_RADIANCE;
use photon::description::{LightSpec, load_scene};
use photon::light::Light;
use photon::material::Material;
use photon::math::{Ray, Rgb, Vec3};
use photon::scene::Scene;
use std::path::PathBuf;

fn fixture(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/blender")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// The material of the first surface straight down onto (x, z) from above.
fn material_below(scene: &Scene, x: f32, z: f32) -> Material {
    let hit = scene
        .intersect(
            &Ray::new(Vec3::new(x, 10.0, z), Vec3::new(0.0, -1.0, 0.0)),
            f32::INFINITY,
        )
        .expect("something below");
    scene.material_at(&hit)
}

#[test]
fn blender_materials_arrive_as_metal_glass_and_pbr() {
    let (scene, loaded) = load_scene(&fixture("metal-glass-nolight.glb")).expect("loads");
    // Gold: metallic 1, roughness 0.3 → α 0.09; glass: transmission 1, roughness 0.05 → rough
    // glass of α 0.0025; red: a dielectric of roughness 0.5.
    let spheres: Vec<Material> = [-2.5f32, 0.0, 2.5]
        .iter()
        .map(|&x| material_below(&scene, x, 0.0))
        .collect();
    let kinds: Vec<String> = spheres.iter().map(|m| format!("{m:?}")).collect();
    assert!(
        spheres
            .iter()
            .any(|m| matches!(m, Material::Pbr(p) if p.metallic == 1.0
            && (p.roughness - 0.3).abs() < 1e-6
            && (p.base_color.y - 0.77).abs() < 1e-3)),
        "a gold metal: {kinds:?}"
    );
    assert!(
        spheres
            .iter()
            .any(|m| matches!(m, Material::RoughDielectric(g)
            if (g.ior - 1.5).abs() < 1e-6 && (g.ggx.narrowest_alpha() - 0.0025).abs() < 1e-5)),
        "rough glass: {kinds:?}"
    );
    assert!(
        spheres
            .iter()
            .any(|m| matches!(m, Material::Pbr(p) if p.metallic == 0.0
            && (p.roughness - 0.5).abs() < 1e-6
            && p.base_color.x > 0.7 && p.base_color.y < 0.1)),
        "a red dielectric: {kinds:?}"
    );
    // No light in the file: the default sky, and a warning that says so and how to change it.
    assert!(matches!(
        loaded.desc.lights.as_slice(),
        [LightSpec::Environment(e)] if e.intensity == 1.0
    ));
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("no lights") && w.contains("--env")),
        "{:?}",
        loaded.warnings
    );
    assert!(matches!(scene.lights(), [Light::Environment(_)]));
    assert_eq!(
        scene.escaped(Vec3::Y, &photon::spectrum::Lambda::Rgb),
        photon::math::Rgb::splat(DEFAULT_SKY_RADIANCE)
    );
}

#[test]
fn blender_sun_and_emissive_quad_are_the_lights() {
    let (sun, loaded) = load_scene(&fixture("metal-glass-sun.glb")).expect("loads");
    assert!(
        matches!(sun.lights(), [Light::Directional(d)] if (d.direction - Vec3::new(0.354, -0.707, -0.612)).length() < 1e-2),
        "{:?}",
        loaded.desc.lights
    );
    // 2049 lux (3 W/m² in Blender) is 3 W/m² again.
    let Light::Directional(d) = &sun.lights()[0] else {
        unreachable!()
    };
    assert!(
        (d.irradiance.rgb().x - 3.0).abs() < 1e-3,
        "{}",
        d.irradiance.rgb()
    );
    let (area, _) = load_scene(&fixture("metal-glass-area.glb")).expect("loads");
    let quad = area
        .lights()
        .iter()
        .find_map(|l| match l {
            Light::Area(a) => Some(a),
            _ => None,
        })
        .expect("the emissive quad is an area light (Blender drops its area lamp)");
    // A 2 × 2 quad of radiance 10, one-sided: Φ = π L A.
    assert!((quad.power().x - 10.0 * std::f32::consts::PI * 4.0).abs() < 0.1);
    assert!(
        !area
            .lights()
            .iter()
            .any(|l| matches!(l, Light::Environment(_)))
    );
}

#[test]
fn blender_textures_and_normal_map_are_applied() {
    let (scene, _) = load_scene(&fixture("textured-pbr.glb")).expect("loads");
    // The upright quad at x ≈ 1.3 faces +z; its texture u runs to the right. Its metallic-
    // roughness map is metal on the left half, roughness 0.1 at the top to 0.9 at the bottom;
    // its normal map tilts normals by n ∝ (−0.6 cos 8πu, 0, 1) in tangent space.
    let mut hits = Vec::new();
    for i in 0..120 {
        for j in 0..120 {
            let (x, y) = (0.0 + 0.022 * i as f32, -0.5 + 0.03 * j as f32);
            let ray = Ray::new(Vec3::new(x, y, 10.0), Vec3::new(0.0, 0.0, -1.0));
            if let Some(hit) = scene.intersect(&ray, f32::INFINITY)
                && hit.ng.z.abs() > 0.99
                && let Material::Pbr(p) = scene.material_at(&hit)
            {
                let (_, frame) = scene.surface(&hit, Vec3::Z, &mut photon::spectrum::Lambda::Rgb);
                hits.push((hit.p, p, frame.n));
            }
        }
    }
    assert!(hits.len() > 1000, "{} hits on the quad", hits.len());
    let x_min = hits.iter().map(|h| h.0.x).fold(f32::MAX, f32::min);
    let x_max = hits.iter().map(|h| h.0.x).fold(f32::MIN, f32::max);
    let (y_min, y_max) = (
        hits.iter().map(|h| h.0.y).fold(f32::MAX, f32::min),
        hits.iter().map(|h| h.0.y).fold(f32::MIN, f32::max),
    );
    for (p, m, n) in &hits {
        let u = (p.x - x_min) / (x_max - x_min);
        let v_down = (y_max - p.y) / (y_max - y_min);
        if (0.05..0.45).contains(&u) {
            assert!(
                m.metallic > 0.95,
                "metal on the left at u {u}: {}",
                m.metallic
            );
        } else if (0.55..0.95).contains(&u) {
            assert!(
                m.metallic < 0.05,
                "dielectric on the right at u {u}: {}",
                m.metallic
            );
        }
        if (0.05..0.95).contains(&v_down) {
            let want = 0.1 + 0.8 * v_down;
            assert!(
                (m.roughness - want).abs() < 0.06,
                "roughness {} at {v_down} down the quad, want {want}",
                m.roughness
            );
        }
        // The normal map: tilted toward −u (−x) where cos 8πu = 1, toward +u where −1.
        let tilt = -0.6 * (8.0 * std::f32::consts::PI * u).cos() / 1.36f32.sqrt();
        if (0.05..0.95).contains(&u) {
            assert!(
                (n.x - tilt).abs() < 0.12,
                "normal {n} at u {u}: x should be about {tilt}"
            );
        }
    }
}

/// `photon render` of a fixture at a tiny size into `out`, with `extra` flags.
fn render_fixture(
    dir: &std::path::Path,
    name: &str,
    extra: &[&str],
    out: &std::path::Path,
) -> String {
    let fixture = fixture(name);
    let out = out.to_str().expect("utf-8");
    let mut args = vec![
        "render",
        &fixture,
        "--width",
        "24",
        "--height",
        "18",
        "--spp",
        "2",
        "--photons",
        "20000",
        "--caustic-photons",
        "20000",
        "-q",
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    let o = common::photon(&args, dir);
    let err = common::stderr(&o);
    assert!(o.status.success(), "{name}: {err}");
    err
}

/// End to end, as a user would: each file renders from the command line; the one without
/// lights warns and is lit (not black), and `--env` replaces its sky.
#[test]
fn blender_files_render_from_the_command_line() {
    let dir = common::temp_dir("gltf-blender");
    for name in [
        "metal-glass-nolight.glb",
        "metal-glass-sun.glb",
        "metal-glass-area.glb",
        "textured-pbr.glb",
    ] {
        let out = dir.join(name.replace(".glb", ".exr"));
        let err = render_fixture(&dir, name, &[], &out);
        let mean = photon::io::image::read_image(&out)
            .expect("reads")
            .mean()
            .max_element();
        assert!(mean > 0.05, "{name} is lit: mean {mean}");
        if name.contains("nolight") {
            assert!(err.contains("uniform white sky"), "{err}");
        }
    }
    // A dimmer sky through --env: the image follows.
    let bright = dir.join("metal-glass-nolight.exr");
    let dim = dir.join("dim.exr");
    render_fixture(&dir, "metal-glass-nolight.glb", &["--env", "0.25"], &dim);
    let (b, d) = (
        photon::io::image::read_image(&bright)
            .expect("reads")
            .mean(),
        photon::io::image::read_image(&dim).expect("reads").mean(),
    );
    let ratio = d.x / b.x;
    assert!(
        (ratio - 0.25).abs() < 0.03,
        "quarter the sky, quarter the light: {ratio}"
    );
}

/// The same scene exported with Blender's MikkTSpace tangents (`TANGENT`): the normal map
/// bends the normals as it does with the tangents Photon makes from the UVs, on the flat quad
/// and on the sphere (where MikkTSpace's per-vertex tangents and ours per triangle differ only
/// by their smoothing).
#[test]
fn blender_tangents_agree_with_tangents_from_the_uvs() {
    let (own, _) = load_scene(&fixture("textured-pbr.glb")).expect("loads");
    let (file, _) = load_scene(&fixture("textured-pbr-tangents.glb")).expect("loads");
    let mut compared = 0;
    let mut worst = 0.0f32;
    for i in 0..80 {
        for j in 0..60 {
            let (x, y) = (-2.4 + 0.06 * i as f32, 0.05 + 0.04 * j as f32);
            let ray = Ray::new(Vec3::new(x, y, 10.0), Vec3::new(0.0, 0.0, -1.0));
            let (Some(a), Some(b)) = (
                own.intersect(&ray, f32::INFINITY),
                file.intersect(&ray, f32::INFINITY),
            ) else {
                continue;
            };
            // Horizontal rays above the ground meet only the textured sphere and quad.
            let (na, nb) = (
                own.surface(&a, -ray.dir, &mut photon::spectrum::Lambda::Rgb)
                    .1
                    .n,
                file.surface(&b, -ray.dir, &mut photon::spectrum::Lambda::Rgb)
                    .1
                    .n,
            );
            worst = worst.max(1.0 - na.dot(nb));
            compared += 1;
        }
    }
    assert!(compared > 500, "{compared} points on the textured objects");
    // cos 8°: per-vertex against per-triangle tangents on a 32 × 16 sphere.
    assert!(
        worst < 1.0 - 0.99,
        "normals differ by up to {}°",
        (1.0 - worst).acos().to_degrees()
    );
}

/// Blender's Volume Absorption (colour (0.5, 0.8, 1), density 0.5) and the glTF output's
/// thickness 2 arrive as `KHR_materials_volume` attenuation colour (0.5, 0.8, 1) over 2 m; a
/// path that crosses the sphere (radius 1) meets its far side with every branch scaled by
/// colour^(length / 2), the length in world units (the tessellated sphere is a little
/// shorter than 2 through its poles).
#[test]
fn blender_volume_absorption_attenuates_paths_inside_the_glass() {
    let (scene, loaded) = load_scene(&fixture("glass-volume.glb")).expect("loads");
    assert!(
        !loaded
            .warnings
            .iter()
            .any(|w| w.contains("KHR_materials_volume")),
        "{:?}",
        loaded.warnings
    );
    let down = Vec3::new(0.0, -1.0, 0.0);
    let top = scene
        .intersect(&Ray::new(Vec3::new(0.05, 10.0, 0.03), down), f32::INFINITY)
        .expect("hits the sphere");
    assert!((top.p.y - 2.0).abs() < 0.02, "the sphere's top: {}", top.p);
    let (outside, _) = scene.surface(&top, -down, &mut photon::spectrum::Lambda::Rgb);
    let Material::Dielectric(entering) = outside else {
        panic!("smooth glass: {outside:?}");
    };
    assert!((entering.ior - 1.45).abs() < 1e-6);
    assert_eq!(entering.segment, Rgb::ONE, "nothing is absorbed outside");
    let inside = Ray::new(top.offset_origin(down), down);
    let bottom = scene
        .intersect(&inside, f32::INFINITY)
        .expect("hits the far side");
    assert!((bottom.t - 2.0).abs() < 0.02, "a diameter: {}", bottom.t);
    let (met, _) = scene.surface(&bottom, -down, &mut photon::spectrum::Lambda::Rgb);
    let Material::Dielectric(leaving) = met else {
        panic!("smooth glass: {met:?}");
    };
    let expected = Rgb::new(
        0.5f32.powf(bottom.t / 2.0),
        0.8f32.powf(bottom.t / 2.0),
        1.0,
    );
    assert!(
        (leaving.segment - expected).abs().max_element() < 1e-5,
        "{} vs {expected}",
        leaving.segment
    );
}
