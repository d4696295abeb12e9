//! Textures: spatially varying albedo looked up by surface (u, v) coordinates.
//!
//! A texture is bound to a material by the scene (see [`crate::scene::SceneBuilder::textured_material`]);
//! the BSDFs themselves stay plain values, and [`crate::scene::Scene::material_at`] hands the
//! integrators a material whose albedo is the texture's value at the hit.
//!
//! Convention: `v` grows upward in the image (OBJ, pbrt); importers of formats whose origin is the
//! top-left corner (glTF) flip `v` when they read it.

use crate::math::{Rgb, Vec2};
use std::sync::Arc;

#[derive(Clone, Debug)]
pub enum Texture {
    Image(Arc<ImageTexture>),
    Checker(Checker),
}

impl Texture {
    /// Linear RGB value at texture coordinates `uv`.
    pub fn eval(&self, uv: Vec2) -> Rgb {
        match self {
            Texture::Image(t) => t.eval(uv),
            Texture::Checker(c) => c.eval(uv),
        }
    }
}

/// A raster of linear RGB texels, repeated over the plane and read with bilinear filtering.
#[derive(Clone, Debug)]
pub struct ImageTexture {
    pub width: u32,
    pub height: u32,
    /// Row-major, top row first, linear RGB.
    pub texels: Vec<Rgb>,
}

impl ImageTexture {
    /// Bilinear lookup with wrap-around; `v = 0` is the bottom row.
    pub fn eval(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        if w == 0 || h == 0 {
            return Rgb::ZERO;
        }
        // Texel centres sit at half-integer positions.
        let x = uv.x * w as f32 - 0.5;
        let y = (1.0 - uv.y) * h as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return Rgb::ZERO;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |i: i64, j: i64| {
            let (i, j) = (i.rem_euclid(w), j.rem_euclid(h));
            self.texels[(j * w + i) as usize]
        };
        let (i, j) = (x0 as i64, y0 as i64);
        let top = texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx;
        let bottom = texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// Alternating squares of two colours, `scale` squares per unit of `u` and `v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checker {
    pub even: Rgb,
    pub odd: Rgb,
    pub scale: Vec2,
}

impl Checker {
    pub fn eval(&self, uv: Vec2) -> Rgb {
        let s = (uv * self.scale).floor();
        if (s.x + s.y).rem_euclid(2.0) < 1.0 {
            self.even
        } else {
            self.odd
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates_and_repeats() {
        let c = Checker {
            even: Rgb::ONE,
            odd: Rgb::ZERO,
            scale: Vec2::splat(2.0),
        };
        assert_eq!(c.eval(Vec2::new(0.1, 0.1)), Rgb::ONE);
        assert_eq!(c.eval(Vec2::new(0.6, 0.1)), Rgb::ZERO);
        assert_eq!(c.eval(Vec2::new(0.6, 0.6)), Rgb::ONE);
        assert_eq!(c.eval(Vec2::new(-0.1, 0.1)), Rgb::ZERO);
    }

    #[test]
    fn image_lookup_is_bilinear_with_v_up() {
        // 2×1 image: left black, right white; 1×2: top red, bottom blue.
        let t = ImageTexture {
            width: 2,
            height: 1,
            texels: vec![Rgb::ZERO, Rgb::ONE],
        };
        assert_eq!(t.eval(Vec2::new(0.25, 0.5)), Rgb::ZERO);
        assert_eq!(t.eval(Vec2::new(0.75, 0.5)), Rgb::ONE);
        assert!((t.eval(Vec2::new(0.5, 0.5)).x - 0.5).abs() < 1e-6);
        let t = ImageTexture {
            width: 1,
            height: 2,
            texels: vec![Rgb::X, Rgb::Z],
        };
        assert_eq!(t.eval(Vec2::new(0.5, 0.75)), Rgb::X);
        assert_eq!(t.eval(Vec2::new(0.5, 0.25)), Rgb::Z);
    }
}
