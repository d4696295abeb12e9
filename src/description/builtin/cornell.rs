//! The Cornell box validation scene (Y up, metres): the Cornell Program of Computer Graphics'
//! measured geometry, used verbatim, as in the Mitsuba 3 reference
//! (`tests/fixtures/shared/scenes/cornell-box/reference.exr`).

use crate::description::{
    CameraSpec, EmissionSpec, LightSpec, MaterialSpec, SceneDesc, ShapeKind, ShapeSpec,
};
use crate::material::Dispersion;
use crate::math::{Rgb, Vec3};

type Quad = [[f32; 3]; 4];

const FLOOR: Quad = [
    [0.5528, 0.0, 0.0],
    [0.0, 0.0, 0.0],
    [0.0, 0.0, 0.5592],
    [0.5496, 0.0, 0.5592],
];
const CEILING: Quad = [
    [0.5560, 0.5488, 0.0],
    [0.5560, 0.5488, 0.5592],
    [0.0, 0.5488, 0.5592],
    [0.0, 0.5488, 0.0],
];
const BACK_WALL: Quad = [
    [0.5496, 0.0, 0.5592],
    [0.0, 0.0, 0.5592],
    [0.0, 0.5488, 0.5592],
    [0.5560, 0.5488, 0.5592],
];
const GREEN_WALL: Quad = [
    [0.0, 0.0, 0.5592],
    [0.0, 0.0, 0.0],
    [0.0, 0.5488, 0.0],
    [0.0, 0.5488, 0.5592],
];
const RED_WALL: Quad = [
    [0.5528, 0.0, 0.0],
    [0.5496, 0.0, 0.5592],
    [0.5560, 0.5488, 0.5592],
    [0.5560, 0.5488, 0.0],
];

const SHORT_BLOCK: [Quad; 5] = [
    [
        [0.1300, 0.1650, 0.0650],
        [0.0820, 0.1650, 0.2250],
        [0.2400, 0.1650, 0.2720],
        [0.2900, 0.1650, 0.1140],
    ],
    [
        [0.2900, 0.0000, 0.1140],
        [0.2900, 0.1650, 0.1140],
        [0.2400, 0.1650, 0.2720],
        [0.2400, 0.0000, 0.2720],
    ],
    [
        [0.1300, 0.0000, 0.0650],
        [0.1300, 0.1650, 0.0650],
        [0.2900, 0.1650, 0.1140],
        [0.2900, 0.0000, 0.1140],
    ],
    [
        [0.0820, 0.0000, 0.2250],
        [0.0820, 0.1650, 0.2250],
        [0.1300, 0.1650, 0.0650],
        [0.1300, 0.0000, 0.0650],
    ],
    [
        [0.2400, 0.0000, 0.2720],
        [0.2400, 0.1650, 0.2720],
        [0.0820, 0.1650, 0.2250],
        [0.0820, 0.0000, 0.2250],
    ],
];

const TALL_BLOCK: [Quad; 5] = [
    [
        [0.4230, 0.3300, 0.2470],
        [0.2650, 0.3300, 0.2960],
        [0.3140, 0.3300, 0.4560],
        [0.4720, 0.3300, 0.4060],
    ],
    [
        [0.4230, 0.0000, 0.2470],
        [0.4230, 0.3300, 0.2470],
        [0.4720, 0.3300, 0.4060],
        [0.4720, 0.0000, 0.4060],
    ],
    [
        [0.4720, 0.0000, 0.4060],
        [0.4720, 0.3300, 0.4060],
        [0.3140, 0.3300, 0.4560],
        [0.3140, 0.0000, 0.4560],
    ],
    [
        [0.3140, 0.0000, 0.4560],
        [0.3140, 0.3300, 0.4560],
        [0.2650, 0.3300, 0.2960],
        [0.2650, 0.0000, 0.2960],
    ],
    [
        [0.2650, 0.0000, 0.2960],
        [0.2650, 0.3300, 0.2960],
        [0.4230, 0.3300, 0.2470],
        [0.4230, 0.0000, 0.2470],
    ],
];

/// Lowered 1 mm below the ceiling so it is not coplanar with it; faces −y.
const LIGHT: Quad = [
    [0.3430, 0.5478, 0.2270],
    [0.3430, 0.5478, 0.3320],
    [0.2130, 0.5478, 0.3320],
    [0.2130, 0.5478, 0.2270],
];

/// Emitted radiance of the light, W·m⁻²·sr⁻¹ per channel.
pub const LIGHT_RADIANCE: [f32; 3] = [17.0, 12.0, 4.0];

fn quad(q: &Quad) -> ShapeKind {
    ShapeKind::Quad {
        vertices: q.map(Vec3::from_array),
    }
}

pub fn desc() -> SceneDesc {
    let mut d = SceneDesc::new(
        "cornell",
        CameraSpec {
            position: Vec3::new(0.278, 0.273, -0.8),
            look_at: Vec3::new(0.278, 0.273, 0.0),
            up: Vec3::Y,
            fov_y_deg: 39.3076,
            width: 512,
            height: 512,
        },
    );
    let white = d.diffuse("white", [0.725, 0.71, 0.68]);
    let red = d.diffuse("red", [0.63, 0.065, 0.05]);
    let green = d.diffuse("green", [0.14, 0.45, 0.091]);
    let glass = d.material(
        "glass",
        MaterialSpec::Glass {
            ior: 1.5,
            transmittance: Rgb::ONE,
            alpha: 0.0,
            attenuation: None,
            dispersion: Dispersion::None,
        },
    );
    let mirror = d.material(
        "mirror",
        MaterialSpec::Mirror {
            reflectance: Rgb::ONE,
        },
    );
    for q in [&FLOOR, &CEILING, &BACK_WALL] {
        d.shape(quad(q), &white);
    }
    d.shape(quad(&GREEN_WALL), &green);
    d.shape(quad(&RED_WALL), &red);
    for q in SHORT_BLOCK.iter().chain(TALL_BLOCK.iter()) {
        d.shape(quad(q), &white);
    }
    let sphere = |center: Vec3| ShapeKind::Sphere {
        center,
        radius: 0.08,
    };
    d.shape(sphere(Vec3::new(0.1855, 0.245, 0.169)), &glass);
    d.shape(sphere(Vec3::new(0.3685, 0.41, 0.35125)), &mirror);
    d.lights.push(LightSpec::Area(Box::new(ShapeSpec {
        kind: quad(&LIGHT),
        media: None,
        material: None,
        transform: Vec::new(),
        emission: Some(EmissionSpec::Radiance {
            radiance: Rgb::from_array(LIGHT_RADIANCE),
            two_sided: false,
            texture: None,
            spectrum: None,
        }),
    })));
    d
}
