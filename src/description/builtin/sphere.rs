//! The closed diffuse sphere: an analytic test scene. Inside a sphere of radius R and albedo ρ
//! lit by a point light of intensity I at its centre, the radiance leaving every wall point is
//! ρ I / (π R² (1 − ρ)): the direct irradiance I/R² is the same everywhere, and each bounce
//! adds the same again times ρ. With R = 1, ρ = 0.5, I = π it is exactly 1.

use crate::description::{CameraSpec, Intensity, LightSpec, SceneDesc, ShapeKind};
use crate::math::{Rgb, Vec3};
use std::f32::consts::PI;

pub const RADIUS: f32 = 1.0;
pub const ALBEDO: f32 = 0.5;
pub const INTENSITY: f32 = PI;

/// The radiance every camera ray should see.
pub fn expected_radiance() -> f32 {
    ALBEDO * INTENSITY / (PI * RADIUS * RADIUS * (1.0 - ALBEDO))
}

pub fn desc() -> SceneDesc {
    let mut d = SceneDesc::new(
        "closed-sphere",
        CameraSpec {
            position: Vec3::new(0.0, 0.0, -0.5),
            look_at: Vec3::new(0.0, 0.0, 1.0),
            up: Vec3::Y,
            fov_y_deg: 90.0,
            width: 32,
            height: 32,
        },
    );
    let wall = d.diffuse("wall", [ALBEDO; 3]);
    d.shape(
        ShapeKind::Sphere {
            center: Vec3::ZERO,
            radius: RADIUS,
        },
        &wall,
    );
    d.lights.push(LightSpec::Point {
        position: Vec3::ZERO,
        intensity: Intensity::Intensity(Rgb::splat(INTENSITY)),
        spectrum: None,
    });
    d
}
