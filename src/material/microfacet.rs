//! The GGX (Trowbridge–Reitz) microfacet distribution, anisotropic, with the height-correlated
//! Smith masking-shadowing term (Heitz 2014, "Understanding the Masking-Shadowing Function in
//! Microfacet-Based BRDFs") and sampling of the visible normals (Heitz 2018, "Sampling the GGX
//! Distribution of Visible Normals", JCGT 7(4)).
//!
//! Everything is in the local shading frame (`z` = macro-surface normal); `alpha_x`/`alpha_y`
//! are the roughness along the frame's `x` and `y` tangents.

use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

/// Below this α a lobe is treated as a perfect (delta) reflector or refractor: D would
/// overflow f32, and no renderer can tell the difference.
pub const DELTA_ALPHA: f32 = 1e-3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    pub alpha_x: f32,
    pub alpha_y: f32,
}

impl Ggx {
    pub fn isotropic(alpha: f32) -> Self {
        Self {
            alpha_x: alpha,
            alpha_y: alpha,
        }
    }

    /// Whether the distribution is so narrow that it is a delta lobe: narrow every way, in
    /// both tangent directions.
    pub fn is_delta(&self) -> bool {
        self.alpha_x.max(self.alpha_y) < DELTA_ALPHA
    }

    /// How broad the lobe is, for every decision that depends on it (rough or near-specular
    /// part, see [`super::NEAR_SPECULAR_ALPHA`]; read from the irradiance cache as if
    /// diffuse): the roughness of its narrowest direction. A lobe counts as broad only if it
    /// is broad every way, since the share of a disc's photons it catches, which those
    /// thresholds bound, shrinks with either α (about as αx·αy).
    pub fn narrowest_alpha(&self) -> f32 {
        self.alpha_x.min(self.alpha_y)
    }

    /// Normal distribution D(m), normalised so that ∫ D(m) cos θm dω = 1.
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let e = (m.x / ax) * (m.x / ax) + (m.y / ay) * (m.y / ay) + m.z * m.z;
        1.0 / (PI * ax * ay * e * e)
    }

    /// Smith's Λ(w) for GGX: (−1 + √(1 + α²(w) tan²θ)) / 2.
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 == 0.0 {
            return f32::INFINITY;
        }
        let a2_tan2 = (w.x * w.x * self.alpha_x * self.alpha_x
            + w.y * w.y * self.alpha_y * self.alpha_y)
            / z2;
        0.5 * (-1.0 + (1.0 + a2_tan2).sqrt())
    }

    /// Masking G1(w) = 1 / (1 + Λ(w)).
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing G2(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi)).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of the visible normals seen from `w` (either hemisphere):
    /// D_w(m) = G1(w) · max(0, w·m) · D(m) / |cos θw|, with `w` flipped to the upper side.
    pub fn visible_pdf(&self, w: Vec3, m: Vec3) -> f32 {
        let w = if w.z < 0.0 { -w } else { w };
        if w.z == 0.0 {
            return 0.0;
        }
        self.g1(w) * w.dot(m).max(0.0) * self.d(m) / w.z
    }

    /// Sample a microfacet normal visible from `w` (flipped to the upper side if below); the
    /// result is in the upper hemisphere. Heitz 2018, listing 1.
    pub fn sample_visible(&self, w: Vec3, u: Vec2) -> Vec3 {
        let w = if w.z < 0.0 { -w } else { w };
        // Stretch to the hemisphere configuration of unit roughness.
        let vh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        // A point on the disc, projected onto the visible half of the hemisphere.
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        // Unstretch.
        Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(1e-7)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Rng, uniform_sphere};

    /// ∫ D(m) cos θm dω = 1 and ∫ D_w(m) dω = 1, by uniform sampling of the sphere.
    #[test]
    fn distribution_and_visible_normals_are_normalised() {
        for (ax, ay) in [(0.3, 0.3), (0.1, 0.5), (0.8, 0.8)] {
            let ggx = Ggx {
                alpha_x: ax,
                alpha_y: ay,
            };
            let w = Vec3::new(0.5, 0.3, 0.6).normalize();
            let mut rng = Rng::keyed(7, &[]);
            let n = 2_000_000;
            let (mut proj, mut vis) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let m = uniform_sphere(rng.next_2d());
                proj += f64::from(ggx.d(m) * m.z.max(0.0));
                vis += f64::from(ggx.visible_pdf(w, m));
            }
            let scale = 4.0 * std::f64::consts::PI / f64::from(n);
            assert!(
                (proj * scale - 1.0).abs() < 0.02,
                "∫D cos = {}",
                proj * scale
            );
            assert!((vis * scale - 1.0).abs() < 0.02, "∫D_w = {}", vis * scale);
        }
    }

    /// Sampled visible normals have the density `visible_pdf`: the mean of g(m)/pdf(m) over
    /// samples equals ∫ g for a test function g.
    #[test]
    fn visible_normal_samples_follow_their_density() {
        let ggx = Ggx {
            alpha_x: 0.4,
            alpha_y: 0.2,
        };
        let w = Vec3::new(-0.6, 0.2, 0.5).normalize();
        let mut rng = Rng::keyed(8, &[]);
        let n = 400_000;
        // g(m) = m.z² over the upper hemisphere: ∫ = 2π/3.
        let mut sum = 0.0f64;
        for _ in 0..n {
            let m = ggx.sample_visible(w, rng.next_2d());
            assert!(m.z > 0.0 && m.dot(w) >= -1e-4);
            sum += f64::from(m.z * m.z * ggx.d(m) * m.z / ggx.visible_pdf(w, m));
        }
        // E[g · D cos / D_w] = ∫ g D cos dω; with g = m.z², check against a direct estimate.
        let mut direct = 0.0f64;
        for _ in 0..n {
            let m = uniform_sphere(rng.next_2d());
            direct += f64::from(m.z.max(0.0).powi(3) * ggx.d(m));
        }
        let direct = direct * 4.0 * std::f64::consts::PI / f64::from(n);
        let sampled = sum / f64::from(n);
        assert!(
            (sampled / direct - 1.0).abs() < 0.02,
            "{sampled} vs {direct}"
        );
    }
}
