//! The light each pixel of a progressive render has accumulated, in the form of its method,
//! and the rules by which a pass adds to it.

use super::Method;
use crate::film::PassSum;
use crate::math::Rgb;

/// One SPPM pixel (pbrt-v4's SPPMPixel in spirit): radius², photon count N, flux τ, and the
/// sum of the direct light of all passes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SppmPixel {
    pub r2: f64,
    pub n: f64,
    pub tau: [f64; 3],
    pub direct: [f64; 3],
}

/// Every pixel's accumulated light (row-major), in the form its method keeps it.
#[derive(Clone, Debug, PartialEq)]
pub enum Pixels {
    /// Each pixel's radius, photon count, flux and direct light.
    Sppm(Vec<SppmPixel>),
    /// Each pixel's sum over passes of its radiance (PPM and the vertex connection and
    /// merging methods), in fixed point (128 bits: 64 wrapped to
    /// negative pixels for a light of radiance 3·10¹¹ at 2 passes; saturating, never
    /// wrapping, even for the largest f32).
    Ppm(Vec<PassSum>),
}

impl Pixels {
    /// `n` pixels of `method` that have seen no pass.
    pub fn new(method: Method, n: usize) -> Self {
        match method {
            Method::Sppm => Pixels::Sppm(vec![SppmPixel::default(); n]),
            // Every method of independent passes sums them.
            Method::Ppm | Method::Vcm | Method::Bdpt | Method::LightTrace => {
                Pixels::Ppm(vec![PassSum::default(); n])
            }
        }
    }
}

/// Adds the finite channels of `l` to `sum`: a NaN or infinity from one sample must not poison
/// a pixel for good, and dropping only the bad channel keeps the rest of the light.
pub(super) fn add_finite(sum: &mut [f64; 3], l: Rgb) {
    for (s, v) in sum.iter_mut().zip(l.to_array()) {
        if v.is_finite() {
            *s += f64::from(v);
        }
    }
}

/// SPPM's update of a pixel by the `m` photons of a pass (Hachisuka & Jensen 2009, eq. 6–7):
/// N ← N + αM, r² ← r² (N + αM)/(N + M), τ ← (τ + Φ) r²_new / r²_old.
pub(super) fn sppm_update(px: &mut SppmPixel, alpha: f64, phi: [f64; 3], m: u32) {
    if m == 0 {
        return;
    }
    let m = f64::from(m);
    let n_new = px.n + alpha * m;
    let r2_new = px.r2 * n_new / (px.n + m);
    for (tau, phi) in px.tau.iter_mut().zip(phi) {
        *tau = (*tau + phi) * (r2_new / px.r2);
    }
    px.n = n_new;
    px.r2 = r2_new;
}
