//! Images in linear radiance, and the pixel filters that decide where samples land.

use crate::math::{Rgb, Vec2};

/// A linear RGB image, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Rgb>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Rgb::ZERO; width as usize * height as usize],
        }
    }

    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[(y * self.width + x) as usize]
    }

    pub fn set(&mut self, x: u32, y: u32, c: Rgb) {
        self.pixels[(y * self.width + x) as usize] = c;
    }

    /// Mean of each channel over all pixels.
    pub fn mean(&self) -> Rgb {
        let mut s = [0.0f64; 3];
        for p in &self.pixels {
            s[0] += f64::from(p.x);
            s[1] += f64::from(p.y);
            s[2] += f64::from(p.z);
        }
        let n = self.pixels.len().max(1) as f64;
        Rgb::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
    }

    /// Box-downsample by an integer factor (each output pixel is the mean of a block), which is
    /// exactly what rendering at the lower resolution with a box pixel filter estimates.
    pub fn downsample(&self, factor: u32) -> Option<Image> {
        if factor == 0 || !self.width.is_multiple_of(factor) || !self.height.is_multiple_of(factor)
        {
            return None;
        }
        let mut out = Image::new(self.width / factor, self.height / factor);
        let norm = 1.0 / (factor * factor) as f32;
        for y in 0..out.height {
            for x in 0..out.width {
                let mut s = Rgb::ZERO;
                for dy in 0..factor {
                    for dx in 0..factor {
                        s += self.get(x * factor + dx, y * factor + dy);
                    }
                }
                out.set(x, y, s * norm);
            }
        }
        Some(out)
    }
}

/// Pixel reconstruction filter, applied by filter importance sampling: each sample's film
/// position is drawn from the filter around the pixel centre and weighted 1, so pixels stay
/// independent of each other (and of the thread that renders them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PixelFilter {
    /// Each pixel is the mean radiance over its square.
    Box,
    /// Gaussian of standard deviation `sigma` pixels, truncated at 3σ.
    Gaussian { sigma: f32 },
}

impl std::str::FromStr for PixelFilter {
    type Err = String;

    /// `box`, or `gaussian:SIGMA` with SIGMA in pixels.
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "box" {
            return Ok(PixelFilter::Box);
        }
        let sigma = s
            .strip_prefix("gaussian:")
            .ok_or_else(|| format!("'{s}' is not a filter; expected 'box' or 'gaussian:SIGMA'"))?;
        let sigma: f32 = sigma.parse().map_err(|_| {
            format!("'{sigma}' is not a number; expected 'gaussian:SIGMA' such as 'gaussian:0.5'")
        })?;
        if !(sigma > 0.0 && sigma.is_finite()) {
            return Err(format!(
                "the Gaussian filter's sigma {sigma} must be positive"
            ));
        }
        Ok(PixelFilter::Gaussian { sigma })
    }
}

impl PixelFilter {
    /// Film position of a sample for pixel (x, y) from a point `u` of the unit square (ideally
    /// stratified across the pixel's samples, see [`crate::sampling::PixelSampler`]).
    pub fn sample_position(&self, x: u32, y: u32, u: Vec2) -> Vec2 {
        let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        match *self {
            PixelFilter::Box => Vec2::new(x as f32, y as f32) + u,
            PixelFilter::Gaussian { sigma } => {
                // Box–Muller on the truncated radius: P(r ≤ 3σ) = 1 − e^{−4.5}, so the
                // remapped u.x keeps the radius inside the 3σ disc without redrawing.
                let keep = 1.0 - (-4.5f32).exp();
                let r = (-2.0 * (1.0 - u.x * keep).ln()).sqrt();
                let phi = std::f32::consts::TAU * u.y;
                centre + sigma * r * Vec2::new(phi.cos(), phi.sin())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn gaussian_filter_stays_within_three_sigma() {
        let f = PixelFilter::Gaussian { sigma: 0.5 };
        let mut rng = Rng::keyed(2, &[]);
        let mut sum = Vec2::ZERO;
        for _ in 0..10_000 {
            let p = f.sample_position(10, 20, rng.next_2d());
            let d = p - Vec2::new(10.5, 20.5);
            assert!(d.length() <= 1.5 + 1e-4);
            sum += d;
        }
        assert!((sum / 10_000.0).length() < 0.02, "centred");
    }
}

/// Light summed in fixed point: each channel a signed 128-bit count of 2^−`BITS`
/// W·m⁻²·sr⁻¹. Integers add associatively, so sums of the same values reach the same bits in
/// any order, on any number of threads or machines (floating-point sums do not); they
/// saturate, never wrap.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FixedRgb<const BITS: u32>(pub [i128; 3]);

/// A sum over samples of a pixel: 2⁻⁴⁰ resolution per sample, saturating past 1.5·10²⁶.
pub type SampleSum = FixedRgb<40>;

/// A progressive pixel's sum over passes: 2⁻²⁴ resolution per pass.
pub type PassSum = FixedRgb<24>;

impl<const BITS: u32> FixedRgb<BITS> {
    /// One unit of light in fixed point.
    pub const SCALE: f64 = (1u64 << BITS) as f64;

    /// `v` in fixed point, rounded half away from zero (saturating beyond i128).
    #[inline]
    pub fn to_fixed(v: f32) -> i128 {
        let x = f64::from(v) * Self::SCALE;
        let r = x + 0.5f64.copysign(x);
        // The common case in one hardware conversion; `as` saturates beyond i64 and i128.
        if r.abs() < 9.0e18 {
            i128::from(r as i64)
        } else {
            r as i128
        }
    }

    /// Add the finite channels of `l`: a NaN or infinity must not poison a sum for good, and
    /// dropping only the bad channel keeps the rest of the light.
    #[inline]
    pub fn add_finite(&mut self, l: Rgb) {
        for (sum, v) in self.0.iter_mut().zip(l.to_array()) {
            if v.is_finite() {
                *sum = sum.saturating_add(Self::to_fixed(v));
            }
        }
    }

    /// Add another sum of the same kind.
    #[inline]
    pub fn add(&mut self, other: &Self) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a = a.saturating_add(b);
        }
    }

    /// The mean of `count` values whose sum this is: the one formula that a render, a resumed
    /// render and a merge of partial renders all use, so that they agree bit for bit.
    #[inline]
    pub fn mean(&self, count: f64) -> Rgb {
        Rgb::from_array(self.0.map(|v| (v as f64 / Self::SCALE / count) as f32))
    }
}

#[cfg(test)]
mod fixed_tests {
    use super::*;

    #[test]
    fn fixed_point_rounds_half_away_from_zero_and_saturates() {
        type F = FixedRgb<1>;
        assert_eq!(F::to_fixed(1.25), 3);
        assert_eq!(F::to_fixed(-1.25), -3);
        assert_eq!(F::to_fixed(1.2), 2);
        assert_eq!(F::to_fixed(f32::MAX), i128::MAX);
        let mut sum = F::default();
        sum.add_finite(Rgb::new(1.0, f32::NAN, -2.0));
        sum.add(&FixedRgb([1, 1, 1]));
        assert_eq!(sum.0, [3, 1, -3]);
        assert_eq!(sum.mean(2.0), Rgb::new(0.75, 0.25, -0.75));
    }
}
