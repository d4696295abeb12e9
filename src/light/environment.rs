//! Light arriving from infinitely far away in every direction: a uniform sky, or an
//! equirectangular (latitude–longitude) image.
//!
//! Directions map to the image as Mitsuba 3's `envmap` does, so that scenes and references
//! agree: +y is up; a direction d (pointing toward the sky) reads u = atan2(d.x, −d.z) / 2π
//! (wrapped into [0, 1)) and v = acos(d.y) / π, with v = 0 the top row. `rotation` turns the
//! sky about +y (right-handed, as Mitsuba's `<rotate y="1" angle=…/>` on `to_world`).
//!
//! Directions are importance-sampled from a piecewise-constant density over the pixels,
//! proportional to luminance × sin θ (pbrt-v4 §12.5; the sin θ is the area of the pixel's
//! patch of sphere). Photons leave a disc that covers the scene's bounding sphere, as for
//! the directional light: power Φ = π r² ∫ L(ω) dω.

use super::{Aperture, LightSample, PhotonEmission};
use crate::math::{Rgb, Vec2, Vec3, luminance};
use crate::sampling::{Distribution2D, uniform_sphere};
use crate::spectrum::Lambda;
use std::f32::consts::PI;
use std::sync::Arc;

/// An equirectangular image of radiance: rows from the top (+y), linear RGB.
#[derive(Clone, Debug)]
pub struct EnvironmentMap {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Rgb>,
}

#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    /// Multiplies the image (or is the radiance of a uniform sky), W·m⁻²·sr⁻¹.
    pub scale: Rgb,
    map: Option<Arc<EnvironmentMap>>,
    distribution: Option<Arc<Distribution2D>>,
    /// cos and sin of the rotation about +y.
    rotation: (f32, f32),
    rotation_deg: f32,
    /// Where its photons enter the scene (set at build).
    pub aperture: Aperture,
}

impl EnvironmentLight {
    /// A uniform sky of radiance `radiance`.
    pub fn uniform(radiance: Rgb) -> Self {
        Self {
            scale: radiance,
            map: None,
            distribution: None,
            rotation: (1.0, 0.0),
            rotation_deg: 0.0,
            aperture: Aperture::default(),
        }
    }

    /// An image sky, times `scale`, turned by `rotation_deg` about +y.
    pub fn image(map: Arc<EnvironmentMap>, scale: Rgb, rotation_deg: f32) -> Self {
        let (w, h) = (map.width as usize, map.height as usize);
        let distribution = Distribution2D::from_rows(w, h, |y, weights| {
            let sin_theta = (PI * (y as f32 + 0.5) / h as f32).sin();
            for (x, weight) in weights.iter_mut().enumerate() {
                let l = luminance(map.texels[y * w + x] * scale).max(0.0);
                *weight = f64::from(l * sin_theta);
            }
        })
        .map(Arc::new);
        let r = rotation_deg.to_radians();
        Self {
            scale,
            map: Some(map),
            distribution,
            rotation: (r.cos(), r.sin()),
            rotation_deg,
            aperture: Aperture::default(),
        }
    }

    pub fn rotation_deg(&self) -> f32 {
        self.rotation_deg
    }

    pub fn map(&self) -> Option<&Arc<EnvironmentMap>> {
        self.map.as_ref()
    }

    /// World direction → the sky's own frame (undo the rotation about +y).
    fn to_local(&self, d: Vec3) -> Vec3 {
        let (c, s) = self.rotation;
        Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z)
    }

    fn to_world(&self, d: Vec3) -> Vec3 {
        let (c, s) = self.rotation;
        Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
    }

    /// Image coordinates of a local direction.
    fn uv(d: Vec3) -> Vec2 {
        let u = (d.x.atan2(-d.z) / (2.0 * PI)).rem_euclid(1.0);
        let v = d.y.clamp(-1.0, 1.0).acos() / PI;
        Vec2::new(u, v)
    }

    /// The local direction at image coordinates (u, v).
    fn direction(uv: Vec2) -> Vec3 {
        let phi = uv.x * 2.0 * PI;
        let theta = uv.y * PI;
        let sin_theta = theta.sin();
        Vec3::new(sin_theta * phi.sin(), theta.cos(), -sin_theta * phi.cos())
    }

    /// Radiance arriving from direction `d` (unit, pointing toward the sky) at the channels of
    /// `lambda` (an RGB sky's colour upsampled as an illuminant in spectral rendering).
    pub fn radiance(&self, d: Vec3, lambda: &Lambda) -> Rgb {
        lambda.illuminant(self.radiance_rgb(d))
    }

    fn radiance_rgb(&self, d: Vec3) -> Rgb {
        let Some(map) = &self.map else {
            return self.scale;
        };
        self.scale * bilinear(map, Self::uv(self.to_local(d)))
    }

    /// Total power: π r² ∫ L dω over the sphere, of the radiance as it is looked up. The
    /// bilinear lookup is a sum of texels times hat functions, so the integral is a sum of
    /// texels times the integrals of their hats: 1/w across (columns wrap), and ∫ hat(v)
    /// sin(πv) dv down (rows sit at v = j/(h − 1); integrated numerically, once per row).
    pub fn power(&self) -> Rgb {
        let disc = self.aperture.area();
        let Some(map) = &self.map else {
            return self.scale * (4.0 * PI * disc);
        };
        let (w, h) = (map.width as usize, map.height as usize);
        let row_weights = row_hat_integrals(h);
        let mut sum = [0f64; 3];
        for (y, weight) in row_weights.iter().enumerate() {
            for x in 0..w {
                let t = map.texels[y * w + x];
                for (c, s) in sum.iter_mut().enumerate() {
                    *s += f64::from(t[c]) * weight / w as f64;
                }
            }
        }
        // dω = sin θ dθ dφ = 2π² sin(πv) du dv.
        let k = 2.0 * std::f64::consts::PI * std::f64::consts::PI;
        let integral = Rgb::new(sum[0] as f32, sum[1] as f32, sum[2] as f32) * k as f32;
        self.scale * integral * disc
    }

    /// Sample a direction toward the sky with its solid-angle density.
    fn sample_direction(&self, u: Vec2) -> Option<(Vec3, f32)> {
        let Some(dist) = &self.distribution else {
            if self.map.is_some() {
                return None; // a black image
            }
            return Some((uniform_sphere(u), 1.0 / (4.0 * PI)));
        };
        let (uv, pdf_uv) = dist.sample(u);
        if pdf_uv <= 0.0 {
            return None;
        }
        let d = self.to_world(Self::direction(uv));
        // The density of the direction as `pdf` computes it, so that the two agree to the bit
        // (the direction's cell, recomputed, may be the neighbour at a cell's edge).
        let pdf = self.pdf(d);
        (pdf > 0.0).then_some((d, pdf))
    }

    /// Solid-angle density with which [`EnvironmentLight::sample_li`] picks direction `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let Some(dist) = &self.distribution else {
            return if self.map.is_some() {
                0.0
            } else {
                1.0 / (4.0 * PI)
            };
        };
        let uv = Self::uv(self.to_local(d));
        let sin_theta = (uv.y * PI).sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        dist.pdf(uv) / (2.0 * PI * PI * sin_theta)
    }

    /// A direction toward the sky from `p`; the shadow ray ends outside the scene's sphere.
    pub fn sample_li(&self, p: Vec3, u: Vec2, lambda: &Lambda) -> Option<LightSample> {
        let (wi, pdf) = self.sample_direction(u)?;
        let far = 2.0 * self.aperture.radius + (p - self.aperture.center).length();
        Some(LightSample {
            wi,
            radiance: self.radiance(wi, lambda),
            pdf,
            point: p + wi * far.max(1.0),
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            is_delta: false,
        })
    }

    /// A photon arriving from a sampled direction through the aperture (see [`Aperture`]):
    /// flux L / (pdf(ω) · density of its line), which is L · π r² / pdf(ω) for the scene's disc.
    pub fn emit(
        &self,
        u_pick: f32,
        u_pos: Vec2,
        u_dir: Vec2,
        lambda: &Lambda,
    ) -> Option<PhotonEmission> {
        let (toward_sky, pdf) = self.sample_direction(u_dir)?;
        let (origin, density) = self.aperture.sample(-toward_sky, u_pick, u_pos)?;
        Some(PhotonEmission {
            origin,
            dir: -toward_sky,
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            flux: self.radiance(toward_sky, lambda) / (pdf * density),
        })
    }
}

/// ∫ hat_j(v) sin(πv) dv for each of `h` rows at v = j/(h − 1), hat_j falling linearly to zero
/// at the neighbouring rows (the first and last rows have half a hat).
fn row_hat_integrals(h: usize) -> Vec<f64> {
    if h == 1 {
        return vec![2.0 / std::f64::consts::PI];
    }
    const STEPS: usize = 64;
    let dv = 1.0 / (h - 1) as f64;
    (0..h)
        .map(|j| {
            let vj = j as f64 * dv;
            let mut sum = 0.0;
            for side in [-1.0, 1.0] {
                for s in 0..STEPS {
                    let t = (s as f64 + 0.5) / STEPS as f64;
                    let v = vj + side * t * dv;
                    if (0.0..=1.0).contains(&v) {
                        sum += (1.0 - t) * (std::f64::consts::PI * v).sin() * dv / STEPS as f64;
                    }
                }
            }
            sum
        })
        .collect()
}

/// Bilinear lookup as Mitsuba 3's `envmap` does it: columns centred at (i + ½)/w and wrapping,
/// rows at v = j/(h − 1), so the first row is the zenith and the last the nadir.
fn bilinear(map: &EnvironmentMap, uv: Vec2) -> Rgb {
    let (w, h) = (map.width as i64, map.height as i64);
    let x = uv.x * w as f32 - 0.5;
    let y = uv.y * (h - 1).max(1) as f32;
    if !(x.is_finite() && y.is_finite()) {
        return Rgb::ZERO;
    }
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |i: i64, j: i64| {
        let (i, j) = (i.rem_euclid(w), j.clamp(0, h - 1));
        map.texels[(j * w + i) as usize]
    };
    let (i, j) = (x0 as i64, y0 as i64);
    let top = texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx;
    let bottom = texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_coordinates_follow_mitsubas_envmap() {
        // +y is the top row; −z is u = 0, +x is u = 0.25, +z the centre column.
        let uv = |d: Vec3| EnvironmentLight::uv(d);
        assert!(uv(Vec3::Y).y.abs() < 1e-6);
        assert!((uv(-Vec3::Y).y - 1.0).abs() < 1e-6);
        assert!((uv(Vec3::X) - Vec2::new(0.25, 0.5)).length() < 1e-6);
        assert!((uv(Vec3::Z) - Vec2::new(0.5, 0.5)).length() < 1e-6);
        for d in [Vec3::new(0.3, 0.5, -0.8), Vec3::new(-0.9, -0.1, 0.2)] {
            let d = d.normalize();
            let back = EnvironmentLight::direction(uv(d));
            assert!((back - d).length() < 1e-5, "{d} → {back}");
        }
        // Turning the sky by 90° brings what was at +x to −z... rotate +x about +y by 90°.
        let sky = EnvironmentLight {
            rotation: (0.0, 1.0),
            ..EnvironmentLight::uniform(Rgb::ONE)
        };
        assert!((sky.to_world(Vec3::X) - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!(
            (sky.to_local(sky.to_world(Vec3::new(0.2, 0.3, 0.9))) - Vec3::new(0.2, 0.3, 0.9))
                .length()
                < 1e-6
        );
    }
}
