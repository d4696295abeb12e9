//! glTF scenes: a glTF file written here byte by byte (transforms, camera, lights, glass,
//! mirror, emitter, embedded texture with a texture transform) and the Blender-exported seed
//! scene against the built-in one.

use crate::common;

use photon::description::build::build;
use photon::description::gltf::{LUMENS_PER_WATT, import_scene};
use photon::description::{Intensity, LightSpec};
use photon::film::{Image, PixelFilter};
use photon::integrator::{DirectConfig, Integrator};
use photon::light::Light;
use photon::material::Material;
use photon::math::{Ray, Rgb, Vec3};
use photon::render::{RenderSettings, render};
use photon::scene::Scene;
use serde_json::json;

/// A unit quad in the xy plane (z = 0) facing +z: positions, normals, UVs, indices.
fn quad_buffer() -> (Vec<u8>, serde_json::Value, serde_json::Value) {
    let mut bin = Vec::new();
    for p in [
        [-0.5f32, -0.5, 0.0],
        [0.5, -0.5, 0.0],
        [0.5, 0.5, 0.0],
        [-0.5, 0.5, 0.0],
    ] {
        p.iter().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for _ in 0..4 {
        [0.0f32, 0.0, 1.0]
            .iter()
            .for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for uv in [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]] {
        uv.iter().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    let views = json!([
        {"buffer": 0, "byteOffset": 0, "byteLength": 48},
        {"buffer": 0, "byteOffset": 48, "byteLength": 48},
        {"buffer": 0, "byteOffset": 96, "byteLength": 32},
        {"buffer": 0, "byteOffset": 128, "byteLength": 12}
    ]);
    let accessors = json!([
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, 0.0], "max": [0.5, 0.5, 0.0]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
    ]);
    (bin, views, accessors)
}

/// The test scene: four quads (glass, mirror, emitter, blue diffuse) under a parent node,
/// a camera, a point and a spot light.
fn test_gltf() -> Vec<u8> {
    let (mut bin, mut views, accessors) = quad_buffer();
    // A 2×1 PNG, red then green, for the textured quad.
    let mut png = Vec::new();
    let mut img = image::RgbImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    img.put_pixel(1, 0, image::Rgb([0, 255, 0]));
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("png");
    views
        .as_array_mut()
        .expect("views")
        .push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": png.len()}));
    bin.extend(&png);
    let prim = |m: u32| json!({"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": m}]});
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let doc = json!({
        "asset": {"version": "2.0", "generator": "photon tests"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_emissive_strength", "KHR_texture_transform", "KHR_materials_specular", "KHR_materials_dispersion"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 683.0},
            {"type": "spot", "intensity": 1366.0, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.5}}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 5, 6, 7, 8]}],
        "nodes": [
            {"name": "group", "translation": [0.0, 0.0, -1.0], "children": [1, 2, 3, 4]},
            {"name": "glass", "mesh": 0, "translation": [-1.5, 0.0, 0.0]},
            {"name": "mirror", "mesh": 1, "translation": [-0.5, 0.0, 0.0]},
            {"name": "lamp", "mesh": 2, "translation": [0.5, 0.0, 0.0], "scale": [0.5, 0.5, 0.5]},
            {"name": "blue", "mesh": 3, "translation": [1.5, 0.0, 0.0], "rotation": [0.0, 0.0, h, h]},
            {"name": "camera", "camera": 0, "translation": [0.0, 0.0, 4.0]},
            {"name": "bulb", "translation": [0.0, 3.0, 0.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "spot", "translation": [0.0, 2.0, 1.0], "rotation": [-h, 0.0, 0.0, h], "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"name": "textured", "mesh": 4, "translation": [3.0, 0.0, -1.0]}
        ],
        "images": [{"bufferView": 4, "mimeType": "image/png"}],
        "textures": [{"source": 0}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 2.0, "znear": 0.1}}],
        "materials": [
            {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0}, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.45}, "KHR_materials_dispersion": {"dispersion": 0.5}}},
            {"name": "mirror", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.0}},
            {"name": "lamp", "emissiveFactor": [1.0, 1.0, 1.0], "emissiveTexture": {"index": 0}, "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0}, "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0}}},
            {"name": "blue", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0], "metallicFactor": 0.0}, "alphaMode": "BLEND", "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}},
            {"name": "image", "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.0]}}}}}
        ],
        "meshes": [prim(0), prim(1), prim(2), prim(3), prim(4)],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}]
    });
    common::glb(&doc, &bin)
}

#[test]
fn gltf_scene_imports_geometry_camera_lights_and_materials() {
    let dir = common::temp_dir("gltf");
    let path = dir.join("test.glb");
    std::fs::write(&path, test_gltf()).expect("write");
    let loaded = import_scene(&path).expect("imports");
    let d = &loaded.desc;
    // Camera: at the node's position, looking down −z, 512 high with the 2:1 aspect ratio.
    assert_eq!(d.camera.position, Vec3::new(0.0, 0.0, 4.0));
    assert!((d.camera.look_at - Vec3::new(0.0, 0.0, 3.0)).length() < 1e-6);
    assert!((d.camera.fov_y_deg - 0.8f32.to_degrees()).abs() < 1e-4);
    assert_eq!((d.camera.width, d.camera.height), (1024, 512));
    // Lights: candela / 683 = W/sr, colour applied; the spot turned to point down.
    assert_eq!(d.lights.len(), 2);
    match &d.lights[0] {
        LightSpec::Point {
            position,
            intensity: Intensity::Intensity(i),
            ..
        } => {
            assert_eq!(*position, Vec3::new(0.0, 3.0, 0.0));
            assert!(
                (*i - Rgb::new(1.0, 0.5, 0.25) * 683.0 / LUMENS_PER_WATT)
                    .abs()
                    .max_element()
                    < 1e-6
            );
        }
        other => panic!("{other:?}"),
    }
    match &d.lights[1] {
        LightSpec::Spot {
            position,
            look_at,
            intensity: Intensity::Intensity(i),
            angle_deg,
            falloff_deg,
            ..
        } => {
            assert_eq!(*position, Vec3::new(0.0, 2.0, 1.0));
            assert!(
                (*look_at - *position - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-5,
                "{look_at:?}"
            );
            assert!((i.x - 2.0).abs() < 1e-6);
            assert!((angle_deg - 0.5f32.to_degrees()).abs() < 1e-4);
            assert!((falloff_deg - 0.2f32.to_degrees()).abs() < 1e-4);
        }
        other => panic!("{other:?}"),
    }
    // The blue quad blends with alpha 1: it is there for every ray, and nothing is warned.
    assert!(
        !loaded.warnings.iter().any(|w| w.contains("alpha")),
        "{:?}",
        loaded.warnings
    );

    let s = build(d).expect("builds");
    // Geometry: each quad where its nodes put it (parent at z = −1, children along x).
    let probe = |x: f32, y: f32| {
        s.intersect(
            &Ray::new(Vec3::new(x, y, 1.0), Vec3::new(0.0, 0.0, -1.0)),
            f32::INFINITY,
        )
    };
    for x in [-1.5, -0.5, 1.5] {
        let h = probe(x, 0.0).expect("quad");
        assert!((h.p.z + 1.0).abs() < 1e-5, "quad at z = −1, got {:?}", h.p);
    }
    assert!(
        probe(0.1, 0.0).is_none(),
        "gap between the mirror and the lamp"
    );
    assert!(probe(0.5 + 0.3, 0.0).is_none(), "the lamp is scaled to 0.5");
    assert!(
        matches!(s.material_at(&probe(-1.5, 0.0).expect("glass")), Material::Dielectric(d) if (d.ior - 1.45).abs() < 1e-6)
    );
    // A polished metal: the glTF material itself, with a delta specular lobe.
    assert!(
        matches!(s.material_at(&probe(-0.5, 0.0).expect("mirror")), Material::Pbr(m) if (m.base_color.x - 0.9).abs() < 1e-6 && m.metallic == 1.0 && m.lobes().is_specular())
    );
    // glTF's default roughness is 1; KHR_materials_specular's factor 0 takes the coat away,
    // leaving a diffuse surface.
    let blue = s.material_at(&probe(1.5, 0.0).expect("blue"));
    assert!(
        matches!(blue, Material::Pbr(p) if p.base_color == Rgb::new(0.2, 0.4, 0.6) && p.metallic == 0.0 && p.roughness == 1.0 && p.specular == 0.0)
    );
    assert_eq!(blue.lobes(), photon::material::Lobes::DIFFUSE_REFLECTION);
    // The rotated blue quad keeps facing +z; its normal is turned by the node's rotation.
    assert!((probe(1.5, 0.0).expect("blue").ns - Vec3::Z).length() < 1e-5);
    // The textured quad: the 2×1 image across it, shifted half a width by the texture
    // transform (left half green, right half red), read at texel centres.
    let texel = |x: f32| match s.material_at(&probe(x, 0.0).expect("textured quad")) {
        Material::Pbr(p) => p.base_color,
        other => panic!("{other:?}"),
    };
    assert_eq!(texel(2.75), Rgb::new(0.0, 1.0, 0.0));
    assert_eq!(texel(3.25), Rgb::new(1.0, 0.0, 0.0));
    // The emissive quad (0.5 × 0.5, one-sided) is an area light of radiance 5 times its
    // emissive texture (the red-green image: each a triangle wave of mean ½ across u, no blue).
    let area = s
        .lights()
        .iter()
        .find_map(|l| match l {
            Light::Area(a) => Some(a),
            _ => None,
        })
        .expect("emissive mesh light");
    assert!((area.area() - 0.25).abs() < 1e-5);
    let full = 5.0 * std::f32::consts::PI * 0.25;
    let p = area.power();
    assert!(
        (p.x / full - 0.5).abs() < 0.01 && (p.y / full - 0.5).abs() < 0.01 && p.z == 0.0,
        "{p}"
    );
    assert_eq!(s.lights().len(), 3);
}

fn direct_render(scene: &Scene, size: u32) -> Image {
    let integrator = Integrator::Direct(DirectConfig::default());
    let s = RenderSettings {
        seed: 1,
        filter: PixelFilter::Box,
        ..RenderSettings::new(size, size, 4)
    };
    render(scene, &integrator, &s, &|_, _| {})
        .expect("renders")
        .image
}

fn mean(img: &Image, x0: u32, x1: u32, y0: u32, y1: u32) -> Rgb {
    let mut sum = Rgb::ZERO;
    for y in y0..y1 {
        for x in x0..x1 {
            sum += img.pixels[(y * img.width + x) as usize];
        }
    }
    sum / ((x1 - x0) * (y1 - y0)) as f32
}

#[test]
fn blender_seed_scene_renders_with_the_seed_framing_and_walls() {
    let path = common::shared_dir().join("seed/seed_scene.glb");
    let loaded = import_scene(&path).expect("imports the Blender export");
    // Blender writes KHR_materials_volume and _specular, both read (no warning): the glass's
    // volume has a thickness and no attenuation, so it stays clear, and the specular factor 0
    // it gives its diffuse surfaces is used.
    assert!(
        !loaded
            .warnings
            .iter()
            .any(|w| w.contains("KHR_materials_volume")),
        "{:?}",
        loaded.warnings
    );
    assert!(
        !loaded
            .warnings
            .iter()
            .any(|w| w.contains("KHR_materials_specular")),
        "{:?}",
        loaded.warnings
    );
    let seed = photon::description::builtin::desc("seed").expect("built-in");
    // glTF is y-up: (x, y, z) in the file is (x, −z, y) in the seed's z-up frame.
    let c = &loaded.desc.camera;
    let zup = |v: Vec3| Vec3::new(v.x, -v.z, v.y);
    assert!(
        (zup(c.position) - seed.camera.position).length() < 1e-4,
        "{:?}",
        c.position
    );
    assert!(
        (zup(c.look_at - c.position).normalize()
            - (seed.camera.look_at - seed.camera.position).normalize())
        .length()
            < 1e-5
    );
    assert!(
        (c.fov_y_deg - seed.camera.fov_y_deg).abs() < 0.01,
        "fov {}",
        c.fov_y_deg
    );
    let glb = build(&loaded.desc).expect("builds");
    let builtin = build(&seed).expect("builds");
    // The disk light is a tessellated emissive mesh of radiance Φ / π²: power within 2%.
    let (p, q) = (glb.total_power().x, builtin.total_power().x);
    assert!((p / q - 1.0).abs() < 0.02, "light power {p} vs {q}");
    let n = 48;
    let (a, b) = (direct_render(&glb, n), direct_render(&builtin, n));
    // Left wall red, right wall green, back wall grey, in both and alike.
    for (img, what) in [(&a, "glb"), (&b, "built-in")] {
        let left = mean(img, 0, 4, 10, 38);
        let right = mean(img, n - 4, n, 10, 38);
        let back = mean(img, 18, 30, 6, 12);
        assert!(
            left.x > 5.0 * left.y.max(1e-4) && left.x > 5.0 * left.z.max(1e-4),
            "{what}: left wall {left:?}"
        );
        assert!(
            right.y > 5.0 * right.x.max(1e-4) && right.y > 5.0 * right.z.max(1e-4),
            "{what}: right wall {right:?}"
        );
        assert!(
            (back.x - back.y).abs() < 0.1 * back.x && back.x > 0.0,
            "{what}: back wall {back:?}"
        );
    }
    for (x0, x1, y0, y1) in [
        (0, 4, 10, 38),
        (n - 4, n, 10, 38),
        (18, 30, 6, 12),
        (30, 44, 40, 48),
    ] {
        let (ma, mb) = (mean(&a, x0, x1, y0, y1), mean(&b, x0, x1, y0, y1));
        let ratio = ma.max_element() / mb.max_element();
        assert!(
            (ratio - 1.0).abs() < 0.1,
            "region ({x0}..{x1}, {y0}..{y1}): {ma:?} vs {mb:?}"
        );
    }
}
