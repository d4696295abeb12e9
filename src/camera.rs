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

    /// The direction the camera looks along.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// Distance from the pinhole to the image plane measured in pixels: the plane on which
    /// every pixel has unit area.
    pub fn image_plane_distance(&self) -> f32 {
        0.5 * self.height as f32 / self.tan_half_fov_y
    }

    /// The film position (in pixels, as [`Camera::ray`] takes it) that sees `p`, if `p` is in
    /// front of the camera and inside the image.
    pub fn raster(&self, p: Vec3) -> Option<Vec2> {
        let d = p - self.position;
        let z = d.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let aspect = self.width as f32 / self.height as f32;
        let sx = d.dot(self.right) / (z * self.tan_half_fov_y * aspect);
        let sy = d.dot(self.up) / (z * self.tan_half_fov_y);
        let film = Vec2::new(
            0.5 * (sx + 1.0) * self.width as f32,
            0.5 * (1.0 - sy) * self.height as f32,
        );
        (film.x >= 0.0
            && film.y >= 0.0
            && film.x < self.width as f32
            && film.y < self.height as f32)
            .then_some(film)
    }

    /// The solid-angle density of a camera ray along unit `dir` whose film position is
    /// uniform over its pixel: d²/cos θ per unit pixel area, with d = the image-plane distance
    /// / cos θ (Georgiev et al. 2012's camera density; SmallVCM's `imageToSolidAngleFactor`).
    /// It is also the pinhole's importance W_e for a pixel of unit area.
    pub fn pixel_solid_angle_density(&self, dir: Vec3) -> f32 {
        let cos = dir.dot(self.forward);
        if cos <= 0.0 {
            return 0.0;
        }
        let d = self.image_plane_distance() / cos;
        d * d / cos
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
    fn raster_inverts_the_camera_ray() {
        let desc = CameraDesc {
            position: Vec3::new(0.3, 1.0, -4.0),
            look_at: Vec3::new(0.0, 0.8, 0.0),
            up: Vec3::Y,
            fov_y_deg: 39.3,
        };
        let cam = Camera::new(&desc, 64, 48).expect("valid camera");
        for film in [
            Vec2::new(0.5, 0.5),
            Vec2::new(63.9, 1.2),
            Vec2::new(20.25, 47.75),
        ] {
            let r = cam.ray(film);
            let back = cam.raster(r.at(3.7)).expect("in view");
            assert!((back - film).length() < 1e-3, "{film} -> {back}");
        }
        assert!(cam.raster(desc.position - cam.forward()).is_none());
        assert!(
            cam.raster(cam.ray(Vec2::new(32.0, 24.0)).at(2.0) + 50.0 * Vec3::X)
                .is_none()
        );
    }

    #[test]
    fn pixel_density_integrates_to_one_over_a_pixel() {
        // The directions through one pixel, weighted by their density, cover exactly one unit
        // of film: ∫ p(ω) dω over the pixel's solid angle = 1.
        let desc = CameraDesc {
            position: Vec3::ZERO,
            look_at: Vec3::Z,
            up: Vec3::Y,
            fov_y_deg: 60.0,
        };
        let cam = Camera::new(&desc, 40, 30).expect("valid camera");
        for (px, py) in [(20u32, 15u32), (0, 0), (39, 5)] {
            let n = 64;
            let mut integral = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let film = Vec2::new(
                        px as f32 + (i as f32 + 0.5) / n as f32,
                        py as f32 + (j as f32 + 0.5) / n as f32,
                    );
                    let d = cam.ray(film).dir;
                    // The cell's solid angle from its corners' directions, as two spherical
                    // triangles (Van Oosterom and Strackee 1983).
                    let h = 0.5 / n as f32;
                    let corner = |sx: f32, sy: f32| cam.ray(film + Vec2::new(sx, sy) * h).dir;
                    let (a, b, c, e) = (
                        corner(-1.0, -1.0),
                        corner(1.0, -1.0),
                        corner(1.0, 1.0),
                        corner(-1.0, 1.0),
                    );
                    let cell = triangle_solid_angle(a, b, c) + triangle_solid_angle(a, c, e);
                    integral += f64::from(cam.pixel_solid_angle_density(d)) * cell;
                }
            }
            assert!(
                (integral - 1.0).abs() < 1e-4,
                "pixel ({px},{py}): {integral}"
            );
        }
    }

    fn triangle_solid_angle(a: Vec3, b: Vec3, c: Vec3) -> f64 {
        let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
        let num = a.dot(b.cross(c)).abs();
        let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
        2.0 * num.atan2(den)
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
