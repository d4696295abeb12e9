//! The closed diffuse sphere: an analytic test scene. Inside a sphere of radius R and albedo ρ
//! lit by a point light of intensity I at its centre, the radiance leaving every wall point is
//! ρ I / (π R² (1 − ρ)): the direct irradiance I/R² is the same everywhere, and each bounce
//! adds the same again times ρ. With R = 1, ρ = 0.5, I = π it is exactly 1.

use crate::camera::CameraDesc;
use crate::error::Result;
use crate::material::{Lambertian, Material};
use crate::math::{Rgb, Vec3};
use crate::scene::{Scene, SceneBuilder};
use std::f32::consts::PI;

pub const RADIUS: f32 = 1.0;
pub const ALBEDO: f32 = 0.5;
pub const INTENSITY: f32 = PI;

/// The radiance every camera ray should see.
pub fn expected_radiance() -> f32 {
    ALBEDO * INTENSITY / (PI * RADIUS * RADIUS * (1.0 - ALBEDO))
}

pub fn build() -> Result<Scene> {
    let mut b = SceneBuilder::new("closed-sphere");
    b.camera(
        CameraDesc {
            position: Vec3::new(0.0, 0.0, -0.5),
            look_at: Vec3::new(0.0, 0.0, 1.0),
            up: Vec3::Y,
            fov_y_deg: 90.0,
        },
        32,
        32,
    );
    let wall = b.material(Material::Lambertian(Lambertian {
        albedo: Rgb::splat(ALBEDO),
    }));
    b.sphere(Vec3::ZERO, RADIUS, wall, None);
    b.point_light(Vec3::ZERO, Rgb::splat(INTENSITY));
    b.build()
}
