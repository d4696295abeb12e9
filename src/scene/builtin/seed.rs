//! The original project's scene, per ../shared/seed/SEED-SCENE.md (Z up), with the procedural
//! plant pot in the front-left corner.

use crate::camera::CameraDesc;
use crate::error::Result;
use crate::material::{Dielectric, Lambertian, Material, Mirror};
use crate::math::{Rgb, Vec3};
use crate::modeling::PolyMesh;
use crate::modeling::pot::{PotParams, pot};
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

    add_pot(&mut b)?;

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

/// Terracotta, potting soil and succulent green: the original used 0.78 grey for all three.
const TERRACOTTA: [f32; 3] = [0.62, 0.33, 0.22];
const SOIL: [f32; 3] = [0.10, 0.07, 0.05];
const LEAF: [f32; 3] = [0.16, 0.38, 0.12];

fn add_smooth(b: &mut SceneBuilder, mesh: &PolyMesh, material: u32) -> Result<()> {
    let positions: Vec<Vec3> = mesh.positions.iter().map(|p| p.as_vec3()).collect();
    let normals: Vec<Vec3> = mesh.vertex_normals().iter().map(|n| n.as_vec3()).collect();
    b.smooth_mesh(
        &positions,
        &normals,
        &mesh.triangles(),
        glam::Affine3A::IDENTITY,
        material,
    )?;
    Ok(())
}

/// The pot (lathe, solidify, two Catmull–Clark levels), its soil and eight NURBS leaves.
fn add_pot(b: &mut SceneBuilder) -> Result<()> {
    let model = pot(&PotParams::default());
    let clay = lambert(b, TERRACOTTA[0], TERRACOTTA[1], TERRACOTTA[2]);
    let soil = lambert(b, SOIL[0], SOIL[1], SOIL[2]);
    let green = lambert(b, LEAF[0], LEAF[1], LEAF[2]);
    add_smooth(b, &model.body, clay)?;
    b.disk(
        model.soil_center.as_vec3(),
        Vec3::Z,
        model.soil_radius as f32,
        soil,
        None,
    );
    for leaf in &model.leaves {
        add_smooth(b, leaf, green)?;
    }
    Ok(())
}
