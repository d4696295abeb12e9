//! The Henyey–Greenstein phase function (Henyey and Greenstein 1941): one parameter `g`, the
//! mean cosine of the scattering angle, from −1 (back) through 0 (isotropic) to 1 (forward).
//! Directions follow the crate's rule: `wo` and `wi` both point away from the scattering
//! point, so light going straight on has `wi = −wo`.

use crate::math::{Frame, Vec2, Vec3};
use std::f32::consts::PI;

/// `g` is kept inside (−1, 1) by this margin: at ±1 the function is a delta.
const G_LIMIT: f32 = 0.999;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    g: f32,
}

/// A sampled direction with its density in solid angle, which is also the phase function's
/// value (it is sampled exactly), so the path weight is 1.
#[derive(Clone, Copy, Debug)]
pub struct PhaseSample {
    pub wi: Vec3,
    pub pdf: f32,
}

impl HenyeyGreenstein {
    pub fn new(g: f32) -> Self {
        Self {
            g: g.clamp(-G_LIMIT, G_LIMIT),
        }
    }

    pub fn g(&self) -> f32 {
        self.g
    }

    /// p(cos θ) per steradian, θ between `wo` and `wi` as the crate orients them: the
    /// forward peak (g > 0) is at `wi = −wo`, cos θ = −1.
    fn value(&self, cos_wo_wi: f32) -> f32 {
        let g = self.g;
        let denom = 1.0 + g * g + 2.0 * g * cos_wo_wi;
        (1.0 - g * g) / (4.0 * PI * denom * denom.max(1e-12).sqrt())
    }

    /// p(wo, wi); it integrates to 1 over the sphere.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.value(wo.dot(wi))
    }

    /// Sample `wi` in proportion to p(wo, ·) by inverting the cosine's distribution.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> PhaseSample {
        let g = self.g;
        let cos_theta = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
            -(1.0 + g * g - s * s) / (2.0 * g)
        }
        .clamp(-1.0, 1.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
        let wi = Frame::from_normal(wo).to_world(local).normalize();
        PhaseSample {
            wi,
            pdf: self.value(cos_theta),
        }
    }
}
