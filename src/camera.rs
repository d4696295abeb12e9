//! Pinhole camera.

use crate::math::{Ray, Vec2, Vec3};

/// A pinhole camera looking from `position` toward `look_at`.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_fov_y: f32,
    pub width: u32,
    pub height: u32,
}

/// How a camera is described: what a user writes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDesc {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
}

impl Camera {
    /// `None` if the view direction is degenerate or parallel to `up`, or the field of view
    /// is not in (0°, 180°).
    pub fn new(desc: &CameraDesc, width: u32, height: u32) -> Option<Self> {
        let forward = (desc.look_at - desc.position).try_normalize()?;
        // Right-handed: right = forward × up, so with +y up and looking down +z, +x is on the left.
        let right = forward.cross(desc.up).try_normalize()?;
        let up = right.cross(forward);
        if !(desc.fov_y_deg > 0.0 && desc.fov_y_deg < 180.0) || width == 0 || height == 0 {
            return None;
        }
        Some(Self {
            position: desc.position,
            forward,
            right,
            up,
            tan_half_fov_y: (0.5 * desc.fov_y_deg.to_radians()).tan(),
            width,
            height,
        })
    }

    /// The ray through the film position `film` in pixels: x from the left edge, y from the top.
    pub fn ray(&self, film: Vec2) -> Ray {
        let aspect = self.width as f32 / self.height as f32;
        let sx = (2.0 * film.x / self.width as f32 - 1.0) * self.tan_half_fov_y * aspect;
        let sy = (1.0 - 2.0 * film.y / self.height as f32) * self.tan_half_fov_y;
        Ray::new(
            self.position,
            (self.forward + sx * self.right + sy * self.up).normalize(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_camera_formula_is_reproduced() {
        // SEED-SCENE.md: d = normalize((2(i+0.5)/N − 1)·t, 1, (1 − 2(j+0.5)/N)·t), t = 16/45.
        let t = 16.0f32 / 45.0;
        let desc = CameraDesc {
            position: Vec3::new(-2.75, -8.0, 2.75),
            look_at: Vec3::new(-2.75, -7.0, 2.75),
            up: Vec3::Z,
            fov_y_deg: 2.0 * t.atan().to_degrees(),
        };
        let n = 480;
        let cam = Camera::new(&desc, n, n).expect("valid camera");
        for (i, j) in [(0u32, 0u32), (479, 0), (17, 300), (240, 240)] {
            let r = cam.ray(Vec2::new(i as f32 + 0.5, j as f32 + 0.5));
            let nf = n as f32;
            let want = Vec3::new(
                (2.0 * (i as f32 + 0.5) / nf - 1.0) * t,
                1.0,
                (1.0 - 2.0 * (j as f32 + 0.5) / nf) * t,
            )
            .normalize();
            assert!((r.dir - want).length() < 1e-5, "pixel ({i},{j})");
        }
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        let desc = CameraDesc {
            position: Vec3::ZERO,
            look_at: Vec3::Y,
            up: Vec3::Y,
            fov_y_deg: 40.0,
        };
        assert!(Camera::new(&desc, 10, 10).is_none());
        let ok = CameraDesc {
            up: Vec3::Z,
            ..desc
        };
        assert!(Camera::new(&ok, 0, 10).is_none());
        assert!(
            Camera::new(
                &CameraDesc {
                    fov_y_deg: 180.0,
                    ..ok
                },
                10,
                10
            )
            .is_none()
        );
    }
}
