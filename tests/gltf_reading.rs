//! glTF behaviours read from small files written here or kept in `tests/fixtures/gltf`:
//! texture transforms, coordinate sets and wrap modes (an arrow fixture read from rendered
//! pixels), alpha masks and blending for every kind of ray, the default sky, framing without
//! a camera, animations that are not read, refused indices of refraction, percent-encoded
//! URIs, `KHR_materials_volume` attenuation.

use crate::common;

use photon::description::build::build;
use photon::description::gltf::{import_scene, read_meshes};
use photon::description::{EnvironmentSpec, MaterialSpec, Sky, load_scene_edited};
use photon::film::Image;
use photon::integrator::{DirectConfig, Integrator};
use photon::material::Attenuation;
use photon::math::{Ray, Rgb, Vec3};
use photon::photon::{PhotonConfig, trace_photons};
use photon::render::{RenderSettings, render};
use photon::scene::Scene;
use serde_json::json;
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/gltf")
        .join(name)
}

fn direct_render(scene: &Scene, width: u32, height: u32) -> Image {
    let settings = RenderSettings {
        seed: 1,
        ..RenderSettings::new(width, height, 4)
    };
    render(
        scene,
        &Integrator::Direct(DirectConfig::default()),
        &settings,
        &|_, _| {},
    )
    .expect("renders")
    .image
}

/// The direction an arrow points in one band of the picture: from the centroid of its
/// magenta shaft to that of its blue head, in degrees clockwise from up.
fn arrow_direction(img: &Image, x0: u32, x1: u32) -> f32 {
    let (mut head, mut shaft) = ((Vec3::ZERO, 0.0f32), (Vec3::ZERO, 0.0f32));
    for y in 0..img.height {
        for x in x0..x1 {
            let c = img.pixels[(y * img.width + x) as usize];
            let at = Vec3::new(x as f32, y as f32, 0.0);
            if c.z > 0.5 && c.x < 0.2 && c.y < 0.2 {
                head = (head.0 + at, head.1 + 1.0);
            } else if c.x > 0.5 && c.z > 0.5 && c.y < 0.2 {
                shaft = (shaft.0 + at, shaft.1 + 1.0);
            }
        }
    }
    assert!(
        head.1 > 10.0 && shaft.1 > 10.0,
        "band {x0}..{x1}: {} head and {} shaft pixels",
        head.1,
        shaft.1
    );
    let d = head.0 / head.1 - shaft.0 / shaft.1;
    // Image rows grow downward: up is −y.
    d.x.atan2(-d.y).to_degrees()
}

fn angle_between(a: f32, b: f32) -> f32 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

#[test]
fn texture_transform_arrows_point_at_their_green_markers() {
    let loaded = import_scene(&fixture("texture-transform-arrows.gltf")).expect("imports");
    assert!(
        !loaded.warnings.iter().any(|w| w.contains("coordinate set")),
        "{:?}",
        loaded.warnings
    );
    let scene = build(&loaded.desc).expect("builds");
    // Five bands of 60 pixels, one quad each (see make_arrows.py): rotation 22.5° turns the
    // image clockwise; 90° with offset (0, 1) points right; TEXCOORD_1 holds that turn
    // already; the transform's texCoord 1 turns the second set once more (down); the emissive
    // texture's own transform (right).
    let img = direct_render(&scene, 300, 100);
    let expected = [22.5, 90.0, 90.0, 180.0, 90.0];
    for (band, want) in expected.iter().enumerate() {
        let x0 = band as u32 * 60;
        let got = arrow_direction(&img, x0, x0 + 60);
        assert!(
            angle_between(got, *want) < 6.0,
            "quad {}: the arrow points {got:.1}° clockwise from up, not {want}°",
            band + 1
        );
    }
    // The first quad's sampler clamps: past the image's right edge (its lower right corner
    // reads u' = 1.24) the grey border column repeats, not the image's left side.
    let hit = scene
        .intersect(
            &Ray::new(Vec3::new(-3.2 + 0.45, -0.45, 1.0), -Vec3::Z),
            f32::INFINITY,
        )
        .expect("quad 1");
    let grey = photon::io::texture::srgb_to_linear(128.0 / 255.0);
    match scene.material_at(&hit) {
        photon::material::Material::Pbr(p) => {
            assert!(
                (p.base_color - Rgb::splat(grey)).abs().max_element() < 1e-3,
                "{p:?}"
            );
        }
        other => panic!("{other:?}"),
    }
}

/// Floor (4 × 4, white, y = 0, facing up) under a 2 × 2 card at y = 1 whose texture is
/// transparent on its left half (x < 0) and opaque on its right, lit straight down by a sun
/// of irradiance π, seen from above.
fn card_file(name: &str, card_material: serde_json::Value) -> PathBuf {
    card_file_edited(name, card_material, |_| {})
}

/// [`card_file`] with its JSON changed by `edit` before it is written.
fn card_file_edited(
    name: &str,
    card_material: serde_json::Value,
    edit: impl FnOnce(&mut serde_json::Value),
) -> PathBuf {
    let (mut doc, bin) = card_document(card_material);
    edit(&mut doc);
    let path = common::temp_dir(&format!("gltf_reading-{name}")).join(name);
    std::fs::write(&path, common::glb(&doc, &bin)).expect("writes");
    path
}

fn card_document(card_material: serde_json::Value) -> (serde_json::Value, Vec<u8>) {
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut add = |bytes: Vec<u8>, accessor: serde_json::Value| {
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
        bin.extend(bytes);
        let mut a = accessor;
        a["bufferView"] = json!(views.len() - 1);
        accessors.push(a);
        accessors.len() - 1
    };
    let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let square = |h: f32, y: f32| floats(&[-h, y, h, h, y, h, h, y, -h, -h, y, -h]);
    let floor = add(
        square(2.0, 0.0),
        json!({"componentType": 5126, "count": 4, "type": "VEC3", "min": [-2.0, 0.0, -2.0], "max": [2.0, 0.0, 2.0]}),
    );
    let card = add(
        square(1.0, 1.0),
        json!({"componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, 1.0, -1.0], "max": [1.0, 1.0, 1.0]}),
    );
    let normals = add(
        floats(&[0.0, 1.0, 0.0].repeat(4)),
        json!({"componentType": 5126, "count": 4, "type": "VEC3"}),
    );
    let uvs = add(
        floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]),
        json!({"componentType": 5126, "count": 4, "type": "VEC2"}),
    );
    let indices = add(
        [0u16, 1, 2, 0, 2, 3]
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect(),
        json!({"componentType": 5123, "count": 6, "type": "SCALAR"}),
    );
    let mut png = Vec::new();
    let mut img = image::RgbaImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgba([255, 255, 255, 0]));
    img.put_pixel(1, 0, image::Rgba([255, 255, 255, 255]));
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("png");
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let image_view = views.len();
    views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": png.len()}));
    bin.extend(&png);
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let prim = |position: usize, material: u32| json!({"primitives": [{"attributes": {"POSITION": position, "NORMAL": normals, "TEXCOORD_0": uvs}, "indices": indices, "material": material}]});
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0 * std::f32::consts::PI}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "card", "mesh": 1},
            {"name": "sun", "rotation": [-h, 0.0, 0.0, h], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "camera", "camera": 0, "translation": [0.0, 6.0, 0.0], "rotation": [-h, 0.0, 0.0, h]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.0, "znear": 0.1}}],
        "samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}],
        "images": [{"bufferView": image_view, "mimeType": "image/png"}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [
            {"name": "floor", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0}},
            card_material
        ],
        "meshes": [prim(floor, 0), prim(card, 1)],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}]
    });
    (doc, bin)
}

fn card_scene(name: &str, card_material: serde_json::Value) -> Scene {
    let loaded = import_scene(&card_file(name, card_material)).expect("imports");
    build(&loaded.desc).expect("builds")
}

/// Where a ray straight down at (x, z) first meets the scene: 1 on the card, 0 on the floor.
fn height_seen(scene: &Scene, x: f32, z: f32) -> f32 {
    scene
        .intersect(&Ray::new(Vec3::new(x, 5.0, z), -Vec3::Y), f32::INFINITY)
        .expect("hits")
        .p
        .y
}

fn cut_out_card() -> serde_json::Value {
    json!({"name": "card", "alphaMode": "MASK", "alphaCutoff": 0.5, "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0, "baseColorTexture": {"index": 0}}})
}

#[test]
fn alpha_mask_cuts_the_card_for_camera_rays_shadow_rays_and_photons() {
    let scene = card_scene("mask.glb", cut_out_card());
    // Camera rays pass the transparent half and stop on the opaque one.
    for z in [-0.5, 0.0, 0.5] {
        assert!(height_seen(&scene, -0.5, z).abs() < 1e-4);
        assert!((height_seen(&scene, 0.5, z) - 1.0).abs() < 1e-4);
    }
    // Shadow rays from the floor up to the sun likewise.
    assert!(!scene.occluded(Vec3::new(-0.5, 1e-3, 0.0), Vec3::Y, 10.0));
    assert!(scene.occluded(Vec3::new(0.5, 1e-3, 0.0), Vec3::Y, 10.0));
    // Photons straight from the sun land on the floor under the hole as densely as on the
    // open floor, and none under the opaque half.
    let config = PhotonConfig {
        photons: 40_000,
        ..PhotonConfig::default()
    };
    let maps = trace_photons(&scene, &config, &|_, _| {}).expect("traces");
    let on_floor = |x0: f32, x1: f32| {
        maps.global
            .photons()
            .iter()
            .filter(|p| p.is_direct())
            .map(|p| p.position())
            .filter(|p| p.y.abs() < 1e-3 && (x0..x1).contains(&p.x) && p.z.abs() < 0.9)
            .count() as f64
    };
    let (hole, card, open) = (on_floor(-0.9, -0.1), on_floor(0.1, 0.9), on_floor(1.1, 1.9));
    assert_eq!(card, 0.0, "photons under the opaque half");
    assert!(open > 300.0, "{open} photons on the open floor");
    assert!(
        (hole / open - 1.0).abs() < 0.2,
        "under the hole {hole}, open {open}"
    );
}

#[test]
fn mask_alpha_is_the_factor_times_the_texture() {
    // Base colour alpha 0.4 times texture alpha 1 is under the cutoff 0.5: all of it is cut.
    let mut material = cut_out_card();
    material["pbrMetallicRoughness"]["baseColorFactor"] = json!([1.0, 1.0, 1.0, 0.4]);
    let scene = card_scene("mask-factor.glb", material);
    assert!(height_seen(&scene, 0.5, 0.0).abs() < 1e-4);
    assert!(!scene.occluded(Vec3::new(0.5, 1e-3, 0.0), Vec3::Y, 10.0));
}

#[test]
fn blended_card_stops_alpha_of_the_rays_the_same_ones_every_time() {
    let material = json!({"name": "card", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 0.3], "metallicFactor": 0.0}});
    let scene = card_scene("blend.glb", material);
    let blocked = |scene: &Scene| {
        let mut hits = Vec::new();
        for i in 0..60 {
            for j in 0..60 {
                let p = Vec3::new(-0.95 + i as f32 / 31.0, 1e-3, -0.95 + j as f32 / 31.0);
                hits.push(scene.occluded(p, Vec3::Y, 10.0));
            }
        }
        hits
    };
    let first = blocked(&scene);
    let share = first.iter().filter(|&&b| b).count() as f64 / first.len() as f64;
    assert!(
        (share - 0.3).abs() < 0.03,
        "{share} of the shadow rays blocked"
    );
    assert_eq!(first, blocked(&scene), "the same rays, the same answers");
    // Camera rays straight down likewise meet the card about 30% of the time.
    let mut on_card = 0;
    for i in 0..3600 {
        let (x, z) = (
            -0.95 + (i % 60) as f32 / 31.0,
            -0.95 + (i / 60) as f32 / 31.0,
        );
        if height_seen(&scene, x, z) > 0.5 {
            on_card += 1;
        }
    }
    assert!((on_card as f64 / 3600.0 - 0.3).abs() < 0.03, "{on_card}");
}

fn plain_card() -> serde_json::Value {
    json!({"name": "card", "pbrMetallicRoughness": {"metallicFactor": 0.0}})
}

fn emissive_card(radiance: f32) -> serde_json::Value {
    json!({"name": "card", "emissiveFactor": [radiance, radiance, radiance], "pbrMetallicRoughness": {"metallicFactor": 0.0}})
}

fn without_sun(doc: &mut serde_json::Value) {
    doc["scenes"][0]["nodes"] = json!([0, 1, 3]);
}

fn has_default_sky(loaded: &photon::description::Loaded) -> bool {
    loaded
        .desc
        .lights
        .iter()
        .any(|l| matches!(l, photon::description::LightSpec::Environment(_)))
}

#[test]
fn a_faint_emitter_does_not_keep_the_default_sky_away_and_a_bright_one_does() {
    // The card (4 m²) glowing at 0.05 emits 0.2π W against the 20π W a white sky sends onto
    // the file's 20 m²: 1%, a glowing detail. At 5 it emits as much as the sky: a lamp.
    let faint = import_scene(&card_file_edited(
        "faint.glb",
        emissive_card(0.05),
        without_sun,
    ))
    .expect("imports");
    assert!(has_default_sky(&faint));
    let warning = faint
        .warnings
        .iter()
        .find(|w| w.contains("white sky"))
        .expect("a warning says why");
    assert!(
        warning.contains("1.0%") && warning.contains("too little"),
        "{warning}"
    );
    let bright = import_scene(&card_file_edited(
        "bright.glb",
        emissive_card(5.0),
        without_sun,
    ))
    .expect("imports");
    assert!(!has_default_sky(&bright), "{:?}", bright.warnings);
    assert!(!bright.warnings.iter().any(|w| w.contains("white sky")));
}

#[test]
fn the_default_sky_warning_goes_when_the_sky_is_given() {
    let path = card_file_edited("sky.glb", plain_card(), without_sun);
    let name = path.to_str().expect("utf-8");
    let (_, loaded) = load_scene_edited(name, |_| Ok(())).expect("loads");
    assert!(loaded.warnings.iter().any(|w| w.contains("white sky")));
    // As --env does: the user's own sky, even one equal to the default.
    let (scene, loaded) = load_scene_edited(name, |desc| {
        desc.set_environment(EnvironmentSpec {
            sky: Sky::Uniform(Rgb::ONE),
            intensity: 1.0,
            rotate_deg: 0.0,
        });
        Ok(())
    })
    .expect("loads");
    assert!(
        !loaded.warnings.iter().any(|w| w.contains("white sky")),
        "{:?}",
        loaded.warnings
    );
    assert!(scene.environment().is_some());
}

#[test]
fn a_file_without_a_camera_is_framed_from_above_the_front() {
    // Without its camera the card scene is a floor and a card, both horizontal: seen from
    // +z alone they were edge-on, and the middle of the picture missed them.
    let path = card_file_edited("no-camera.glb", plain_card(), |doc| {
        doc["scenes"][0]["nodes"] = json!([0, 1, 2]);
    });
    let loaded = import_scene(&path).expect("imports");
    assert!(
        loaded.warnings.iter().any(|w| w.contains("above")),
        "{:?}",
        loaded.warnings
    );
    let c = loaded.desc.camera;
    let view = (c.look_at - c.position).normalize();
    let elevation = (-view.y).asin().to_degrees();
    assert!((elevation - 25.0).abs() < 0.5, "{elevation}° above");
    assert!(view.z < 0.0, "looks toward −z, from the front");
    let scene = build(&loaded.desc).expect("builds");
    // The view's middle passes the card's front edge and meets the floor behind it; a ray
    // a little higher meets the card.
    let hit = |d: Vec3| scene.intersect(&Ray::new(c.position, d.normalize()), f32::INFINITY);
    assert!(hit(view).expect("the middle sees the floor").p.y.abs() < 1e-4);
    let higher = view + 0.1 * Vec3::Y;
    assert!((hit(higher).expect("above the middle").p.y - 1.0).abs() < 1e-4);
}

#[test]
fn animations_with_pointer_targets_are_skipped_with_a_warning() {
    // KHR_animation_pointer: a channel's target names no node, only a JSON pointer.
    let path = card_file_edited("animated.glb", plain_card(), |doc| {
        doc["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_animation_pointer"]);
        doc["animations"] = json!([{
            "channels": [{"sampler": 0, "target": {"path": "pointer", "extensions": {"KHR_animation_pointer": {"pointer": "/nodes/1/translation"}}}}],
            "samplers": [{"input": 2, "output": 3}]
        }]);
    });
    let loaded = import_scene(&path).expect("a valid file is read");
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("animations are not rendered")),
        "{:?}",
        loaded.warnings
    );
    assert!((height_seen(&build(&loaded.desc).expect("builds"), 0.5, 0.0) - 1.0).abs() < 1e-4);
}

#[test]
fn an_index_of_refraction_that_is_not_positive_is_refused() {
    // 1e39 is past f32: it reads as infinity.
    for ior in [json!(0.0), json!(-1.5), json!(1e39)] {
        let glass = json!({"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": ior}}});
        let path = card_file(&format!("ior-{ior}.glb"), glass);
        let Err(e) = import_scene(&path) else {
            panic!("ior {ior} was accepted");
        };
        let e = e.to_string();
        assert!(e.contains("index of refraction must be positive"), "{e}");
    }
}

/// A glass card with `KHR_materials_volume` set to `volume`.
fn glass_card(volume: serde_json::Value) -> serde_json::Value {
    json!({"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0}, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_volume": volume}})
}

/// The glass's attenuation as read, and the file's warnings.
fn glass_attenuation(name: &str, volume: serde_json::Value) -> (Option<Attenuation>, Vec<String>) {
    let path = card_file(name, glass_card(volume));
    let loaded = import_scene(&path).expect("imports");
    let attenuation = read_meshes(&path)
        .expect("reads")
        .parts
        .iter()
        .find_map(|p| match p.material.as_ref().map(|m| &m.spec) {
            Some(MaterialSpec::Glass { attenuation, .. }) => Some(*attenuation),
            _ => None,
        })
        .expect("a glass");
    (attenuation, loaded.warnings)
}

#[test]
fn volume_attenuation_is_read_where_the_mesh_encloses_a_volume() {
    // thicknessFactor > 0: a volume, absorbing as its attenuation says, with no warning.
    let (a, warnings) = glass_attenuation(
        "volume.glb",
        json!({"thicknessFactor": 0.5, "attenuationColor": [0.5, 0.8, 1.0], "attenuationDistance": 2.0}),
    );
    assert_eq!(
        a,
        Some(Attenuation {
            color: Rgb::new(0.5, 0.8, 1.0),
            distance: 2.0
        })
    );
    assert!(
        !warnings.iter().any(|w| w.contains("KHR_materials_volume")),
        "{warnings:?}"
    );
    // The extension's defaults (colour 1, distance ∞) are clear glass.
    let (a, _) = glass_attenuation("clear.glb", json!({"thicknessFactor": 0.5}));
    assert_eq!(a, None);
    let (a, _) = glass_attenuation(
        "far.glb",
        json!({"thicknessFactor": 0.5, "attenuationColor": [0.5, 0.8, 1.0]}),
    );
    assert_eq!(a, None);
    // thicknessFactor 0 (the default) is thin-walled: no volume to absorb in, and a warning.
    let (a, warnings) = glass_attenuation(
        "thin.glb",
        json!({"attenuationColor": [0.5, 0.8, 1.0], "attenuationDistance": 2.0}),
    );
    assert_eq!(a, None);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("thicknessFactor 0") && w.contains("without absorption")),
        "{warnings:?}"
    );
}

#[test]
fn volume_attenuation_outside_the_extensions_ranges_is_refused() {
    for (name, volume) in [
        (
            "zero-distance.glb",
            json!({"thicknessFactor": 1.0, "attenuationDistance": 0.0}),
        ),
        (
            "bright.glb",
            json!({"thicknessFactor": 1.0, "attenuationColor": [1.5, 1.0, 1.0], "attenuationDistance": 1.0}),
        ),
    ] {
        let Err(e) = import_scene(&card_file(name, glass_card(volume))) else {
            panic!("{name} was accepted");
        };
        let e = e.to_string();
        assert!(e.contains("KHR_materials_volume attenuation"), "{e}");
    }
}

#[test]
fn uris_are_percent_decoded() {
    // glTF stores relative paths as URI references: `card%281%29.bin` is `card(1).bin`.
    let (mut doc, bin) = card_document(plain_card());
    doc["buffers"][0]["uri"] = json!("card%281%29%20b.bin");
    let dir = common::temp_dir("gltf_reading-uri");
    std::fs::write(dir.join("card(1) b.bin"), &bin).expect("writes");
    let path = dir.join("card.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).expect("json")).expect("writes");
    let loaded = import_scene(&path).expect("the buffer is found");
    assert!((height_seen(&build(&loaded.desc).expect("builds"), 0.5, 0.0) - 1.0).abs() < 1e-4);
}
