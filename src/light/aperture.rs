//! Where the photons of a distant light (the sun, the sky) enter the scene.
//!
//! A distant light's photons travel along parallel lines for each direction; every line that
//! can meet the scene crosses the disc of the scene's bounding sphere seen from that
//! direction, so photons start on that disc (pbrt-v4's convention). In a scene whose ground
//! reaches far beyond what the camera sees, nearly all of them land where no one looks, and the
//! estimates in view starve: a sphere on a 20 m plane under a sky got 5% of its indirect light
//! at 250k photons, because the few photons on it made every estimate reach its maximum radius.
//!
//! So half the photons start on the disc of a second, smaller sphere around what the camera
//! sees (found once, from a grid of camera rays). Each photon's flux divides by the density of
//! its line under the *mixture* of the two discs, so every line the whole disc reaches keeps
//! a non-zero density and the photon map stays unbiased; only its noise moves to where it is
//! seen (the one-sample MIS estimator of Veach 1997, §9.2.4, over two strategies).

use crate::math::{Frame, Vec2, Vec3};
use crate::sampling::uniform_disk_polar;
use std::f32::consts::PI;

/// Share of the photons aimed at the camera's view when there is one.
pub const VIEW_SHARE: f32 = 0.5;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aperture {
    /// The scene's bounding sphere (a hair larger), set at build.
    pub center: Vec3,
    pub radius: f32,
    /// A sphere around the surfaces the camera sees, inside the scene's.
    pub view: Option<(Vec3, f32)>,
}

/// Whether the line through `p` along `d` (unit) passes within `r` of `c`.
fn line_within(p: Vec3, d: Vec3, c: Vec3, r: f32) -> bool {
    let to_c = c - p;
    (to_c - d * to_c.dot(d)).length_squared() <= r * r
}

impl Aperture {
    /// Area of the whole disc, πr²: the power of a distant light is its irradiance over it.
    pub fn area(&self) -> f32 {
        PI * self.radius * self.radius
    }

    /// A photon's start for a light whose photons travel along `dir` (unit): a point on the
    /// plane facing `dir` one radius outside the scene's centre, and the density (per m² of
    /// that plane) of the line it starts, under the mixture of the two discs.
    pub fn sample(&self, dir: Vec3, u_pick: f32, u: Vec2) -> Option<(Vec3, f32)> {
        if self.radius <= 0.0 {
            return None;
        }
        let frame = Frame::from_normal(dir);
        let (center, radius) = match self.view {
            Some(view) if u_pick < VIEW_SHARE => view,
            _ => (self.center, self.radius),
        };
        let d = uniform_disk_polar(u, radius);
        let on_line = center + frame.s * d.x + frame.t * d.y;
        // Slide along the line to the plane one radius before the scene's centre.
        let origin = on_line - dir * ((on_line - self.center).dot(dir) + self.radius);
        let density = self.density(origin, dir);
        (density > 0.0).then_some((origin, density))
    }

    /// Density per m² with which [`Aperture::sample`] starts the line through `p` along `dir`.
    pub fn density(&self, p: Vec3, dir: Vec3) -> f32 {
        let whole = if line_within(p, dir, self.center, self.radius) {
            1.0 / self.area()
        } else {
            0.0
        };
        match self.view {
            Some((c, r)) => {
                let view = if line_within(p, dir, c, r) {
                    1.0 / (PI * r * r)
                } else {
                    0.0
                };
                (1.0 - VIEW_SHARE) * whole + VIEW_SHARE * view
            }
            None => whole,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The mixture is a density over the lines of the whole disc: the mean of 1/density over
    /// samples is the whole disc's area, and a region of the plane receives lines in
    /// proportion to its mixture density.
    #[test]
    fn mixture_density_integrates_to_the_disc() {
        let a = Aperture {
            center: Vec3::new(1.0, 2.0, 3.0),
            radius: 10.0,
            view: Some((Vec3::new(2.0, 2.0, 1.0), 1.5)),
        };
        let dir = Vec3::new(0.3, -0.8, 0.2).normalize();
        let mut rng = Rng::keyed(3, &[]);
        let n = 400_000;
        let mut inv = 0.0f64;
        let mut in_view = 0usize;
        for _ in 0..n {
            let (p, density) = a
                .sample(dir, rng.next_f32(), rng.next_2d())
                .expect("sample");
            inv += 1.0 / f64::from(density);
            if line_within(p, dir, Vec3::new(2.0, 2.0, 1.0), 1.5) {
                in_view += 1;
            }
            // Every start lies on the plane one radius before the centre.
            assert!(((p - a.center).dot(dir) + a.radius).abs() < 1e-3);
        }
        let area = f64::from(a.area());
        assert!(
            (inv / f64::from(n) / area - 1.0).abs() < 0.01,
            "{}",
            inv / f64::from(n)
        );
        // Half go to the view disc, plus the whole disc's share of it.
        let expected = 0.5 + 0.5 * (1.5f64 * 1.5) / (10.0 * 10.0);
        assert!((in_view as f64 / f64::from(n) - expected).abs() < 0.005);
    }
}
