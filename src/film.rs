//! Images in linear radiance, and the pixel filters that decide where samples land.

use crate::math::{Rgb, Vec2};
use crate::sampling::Rng;

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

impl PixelFilter {
    /// Film position of a sample for pixel (x, y).
    pub fn sample_position(&self, x: u32, y: u32, rng: &mut Rng) -> Vec2 {
        let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        match *self {
            PixelFilter::Box => Vec2::new(x as f32, y as f32) + rng.next_2d(),
            PixelFilter::Gaussian { sigma } => {
                // Box–Muller, redrawn while outside the 3σ truncation disc (rarely more than once).
                loop {
                    let u1 = 1.0 - rng.next_f32();
                    let u2 = rng.next_f32();
                    let r = (-2.0 * u1.ln()).sqrt();
                    if r <= 3.0 {
                        let phi = std::f32::consts::TAU * u2;
                        return centre + sigma * r * Vec2::new(phi.cos(), phi.sin());
                    }
                }
            }
        }
    }
}
