//! The original project's scene, per ../shared/seed/SEED-SCENE.md (Z up).

use crate::camera::CameraDesc;
use crate::error::Result;
use crate::material::{Dielectric, Lambertian, Material, Mirror};
use crate::math::{Rgb, Vec3};
use crate::scene::{Emission, Scene, SceneBuilder};
use std::f32::consts::PI;

/// Total power of the disk light in each channel, watts.
pub const LIGHT_POWER: f32 = 314.159;

fn lambert(b: &mut SceneBuilder, r: f32, g: f32, bl: f32) -> u32 {
    b.material(Material::Lambertian(Lambertian {
        albedo: Rgb::new(r, g, bl),
    }))
}

/// A vertical prism from z = 0 to `height` over a quadrilateral footprint: four sides and a top.
fn prism(b: &mut SceneBuilder, footprint: [(f32, f32); 4], height: f32, material: u32) {
    let lo = |i: usize| Vec3::new(footprint[i].0, footprint[i].1, 0.0);
    let hi = |i: usize| Vec3::new(footprint[i].0, footprint[i].1, height);
    b.quad([hi(0), hi(1), hi(2), hi(3)], material, None);
    for i in 0..4 {
        let j = (i + 1) % 4;
        b.quad([lo(i), lo(j), hi(j), hi(i)], material, None);
    }
}

pub fn build() -> Result<Scene> {
    let mut b = SceneBuilder::new("seed");
    let t = 16.0f32 / 45.0;
    b.camera(
        CameraDesc {
            position: Vec3::new(-2.75, -8.0, 2.75),
            look_at: Vec3::new(-2.75, 0.0, 2.75),
            up: Vec3::Z,
            fov_y_deg: 2.0 * t.atan().to_degrees(),
        },
        480,
        480,
    );
    let grey = lambert(&mut b, 0.4, 0.4, 0.4);
    let red = lambert(&mut b, 0.5, 0.0, 0.0);
    let green = lambert(&mut b, 0.0, 0.5, 0.0);
    let box_white = lambert(&mut b, 0.5, 0.5, 0.5);
    let black = lambert(&mut b, 0.0, 0.0, 0.0);
    let chrome = b.material(Material::Mirror(Mirror {
        reflectance: Rgb::ONE,
    }));
    let glass = b.material(Material::Dielectric(Dielectric {
        ior: 2.4,
        transmittance: Rgb::ONE,
    }));

    let (x0, x1, y0, y1, z1) = (-5.5f32, 0.0f32, -1.0f32, 5.5f32, 5.5f32);
    let v = Vec3::new;
    // Floor, ceiling, back wall, left (red) and right (green) walls, each facing into the room.
    b.quad(
        [
            v(x0, y0, 0.0),
            v(x1, y0, 0.0),
            v(x1, y1, 0.0),
            v(x0, y1, 0.0),
        ],
        grey,
        None,
    );
    b.quad(
        [v(x0, y0, z1), v(x0, y1, z1), v(x1, y1, z1), v(x1, y0, z1)],
        grey,
        None,
    );
    b.quad(
        [v(x0, y1, 0.0), v(x1, y1, 0.0), v(x1, y1, z1), v(x0, y1, z1)],
        grey,
        None,
    );
    b.quad(
        [v(x0, y0, 0.0), v(x0, y1, 0.0), v(x0, y1, z1), v(x0, y0, z1)],
        red,
        None,
    );
    b.quad(
        [v(x1, y0, 0.0), v(x1, y0, z1), v(x1, y1, z1), v(x1, y1, 0.0)],
        green,
        None,
    );

    prism(
        &mut b,
        [
            (-2.6476, 2.9665),
            (-4.2235, 2.4776),
            (-4.7124, 4.0535),
            (-3.1365, 4.5424),
        ],
        3.3,
        box_white,
    );
    prism(
        &mut b,
        [
            (-0.8235, 2.2446),
            (-1.2954, 0.6635),
            (-2.8765, 1.1354),
            (-2.4046, 2.7165),
        ],
        1.65,
        box_white,
    );
    b.sphere(v(-1.843823, 1.66519, 2.358279), 0.68959, glass, None);
    b.sphere(v(-3.882164, 3.51001, 3.889405), 0.58298, chrome, None);

    // Disk light of radius 1 facing down: L = Φ / (π · area).
    let radius = 1.0f32;
    let radiance = LIGHT_POWER / (PI * PI * radius * radius);
    b.disk(
        v(-2.78, 2.50351, 5.46605),
        -Vec3::Z,
        radius,
        black,
        Some(Emission {
            radiance: Rgb::splat(radiance),
            two_sided: false,
        }),
    );
    b.build()
}
