//! The original project's scene (Z up), as its Blender file placed it
//! (`tests/fixtures/shared/seed/seed_scene.glb` is that file's glTF export), with the procedural
//! plant pot in the front-left corner.

use crate::description::{
    CameraSpec, EmissionSpec, LightSpec, MaterialSpec, SceneDesc, ShapeKind, ShapeSpec,
};
use crate::material::Dispersion;
use crate::math::{Rgb, Vec3};
use crate::modeling::pot::PotParams;

/// Total power of the disk light in each channel, watts.
pub const LIGHT_POWER: f32 = 314.159;

/// A vertical prism from z = 0 to `height` over a quadrilateral footprint: four sides and a top.
fn prism(d: &mut SceneDesc, footprint: [(f32, f32); 4], height: f32, material: &str) {
    let lo = |i: usize| Vec3::new(footprint[i].0, footprint[i].1, 0.0);
    let hi = |i: usize| Vec3::new(footprint[i].0, footprint[i].1, height);
    d.shape(
        ShapeKind::Quad {
            vertices: [hi(0), hi(1), hi(2), hi(3)],
        },
        material,
    );
    for i in 0..4 {
        let j = (i + 1) % 4;
        d.shape(
            ShapeKind::Quad {
                vertices: [lo(i), lo(j), hi(j), hi(i)],
            },
            material,
        );
    }
}

pub fn desc() -> SceneDesc {
    let t = 16.0f32 / 45.0;
    let mut d = SceneDesc::new(
        "seed",
        CameraSpec {
            position: Vec3::new(-2.75, -8.0, 2.75),
            look_at: Vec3::new(-2.75, 0.0, 2.75),
            up: Vec3::Z,
            fov_y_deg: 2.0 * t.atan().to_degrees(),
            width: 480,
            height: 480,
        },
    );
    let grey = d.diffuse("wall_grey", [0.4, 0.4, 0.4]);
    let red = d.diffuse("red", [0.5, 0.0, 0.0]);
    let green = d.diffuse("green", [0.0, 0.5, 0.0]);
    let box_white = d.diffuse("box_white", [0.5, 0.5, 0.5]);
    let chrome = d.material(
        "chrome",
        MaterialSpec::Mirror {
            reflectance: Rgb::ONE,
        },
    );
    let glass = d.material(
        "glass",
        MaterialSpec::Glass {
            ior: 2.4,
            transmittance: Rgb::ONE,
            alpha: 0.0,
            attenuation: None,
            dispersion: Dispersion::None,
        },
    );
    let clay = d.diffuse("terracotta", TERRACOTTA);
    let soil = d.diffuse("soil", SOIL);
    let leaf = d.diffuse("leaf", LEAF);

    let (x0, x1, y0, y1, z1) = (-5.5f32, 0.0f32, -1.0f32, 5.5f32, 5.5f32);
    let v = Vec3::new;
    let mut quad = |vertices: [Vec3; 4], material: &str| {
        d.shape(ShapeKind::Quad { vertices }, material);
    };
    // Floor, ceiling, back wall, left (red) and right (green) walls, each facing into the room.
    quad(
        [
            v(x0, y0, 0.0),
            v(x1, y0, 0.0),
            v(x1, y1, 0.0),
            v(x0, y1, 0.0),
        ],
        &grey,
    );
    quad(
        [v(x0, y0, z1), v(x0, y1, z1), v(x1, y1, z1), v(x1, y0, z1)],
        &grey,
    );
    quad(
        [v(x0, y1, 0.0), v(x1, y1, 0.0), v(x1, y1, z1), v(x0, y1, z1)],
        &grey,
    );
    quad(
        [v(x0, y0, 0.0), v(x0, y1, 0.0), v(x0, y1, z1), v(x0, y0, z1)],
        &red,
    );
    quad(
        [v(x1, y0, 0.0), v(x1, y0, z1), v(x1, y1, z1), v(x1, y1, 0.0)],
        &green,
    );

    prism(
        &mut d,
        [
            (-2.6476, 2.9665),
            (-4.2235, 2.4776),
            (-4.7124, 4.0535),
            (-3.1365, 4.5424),
        ],
        3.3,
        &box_white,
    );
    prism(
        &mut d,
        [
            (-0.8235, 2.2446),
            (-1.2954, 0.6635),
            (-2.8765, 1.1354),
            (-2.4046, 2.7165),
        ],
        1.65,
        &box_white,
    );
    let sphere = |center: Vec3, radius: f32| ShapeKind::Sphere { center, radius };
    d.shape(sphere(v(-1.843823, 1.66519, 2.358279), 0.68959), &glass);
    d.shape(sphere(v(-3.882164, 3.51001, 3.889405), 0.58298), &chrome);

    // The pot (lathe, solidify, two Catmull–Clark levels), its soil and eight NURBS leaves.
    let pot = PotParams::default();
    d.shape(
        ShapeKind::Pot {
            subdivisions: pot.subdivisions,
            seed: pot.seed,
            soil_material: Some(soil),
            leaf_material: Some(leaf),
        },
        &clay,
    );

    // A one-sided disk light of radius 1 facing down, given by its power (L = Φ / (π · area)).
    d.lights.push(LightSpec::Area(Box::new(ShapeSpec {
        kind: ShapeKind::Disk {
            center: v(-2.78, 2.50351, 5.46605),
            normal: -Vec3::Z,
            radius: 1.0,
        },
        media: None,
        material: None,
        transform: Vec::new(),
        emission: Some(EmissionSpec::Power {
            power: Rgb::splat(LIGHT_POWER),
            two_sided: false,
            spectrum: None,
        }),
    })));
    d
}

/// Terracotta, potting soil and succulent green: the original used 0.78 grey for all three.
pub const TERRACOTTA: [f32; 3] = [0.62, 0.33, 0.22];
pub const SOIL: [f32; 3] = [0.10, 0.07, 0.05];
pub const LEAF: [f32; 3] = [0.16, 0.38, 0.12];
