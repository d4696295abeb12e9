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

    /// Linear RGB value at `uv`, reading an image's texels past its edges as `wrap` says
    /// (a checker repeats by nature).
    pub fn eval_wrapped(&self, uv: Vec2, wrap: [Wrap; 2]) -> Rgb {
        match self {
            Texture::Image(t) => t.eval_wrapped(uv, wrap),
            Texture::Checker(c) => c.eval(uv),
        }
    }

    /// Coverage (alpha) at `uv`: an image's alpha channel, 1 where it has none.
    pub fn alpha(&self, uv: Vec2, wrap: [Wrap; 2]) -> f32 {
        match self {
            Texture::Image(t) => t.alpha(uv, wrap),
            Texture::Checker(_) => 1.0,
        }
    }
}

/// How texel indices past an image's edge are read, per axis: glTF's sampler wrap modes
/// (glTF 2.0 §3.8.4.2: REPEAT 10497, CLAMP_TO_EDGE 33071, MIRRORED_REPEAT 33648).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    #[default]
    Repeat,
    ClampToEdge,
    MirroredRepeat,
}

impl Wrap {
    /// Texel index `i` of a row or column of `n` texels, folded into `0..n`.
    fn index(self, i: i64, n: i64) -> i64 {
        match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            // Mirrored: 0 1 … n−1 n−1 … 1 0 0 1 …, a period of 2n.
            Wrap::MirroredRepeat => {
                let k = i.rem_euclid(2 * n);
                if k < n { k } else { 2 * n - 1 - k }
            }
        }
    }
}

/// Which texture coordinates a texture reads and how: a coordinate set of the mesh
/// (glTF's `TEXCOORD_n`), an affine map applied to it (glTF's `KHR_texture_transform`,
/// already turned into our v-up coordinates) and the wrap mode of each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvMapping {
    /// 0: the mesh's first coordinate set, 1: its second.
    pub set: u8,
    pub transform: glam::Affine2,
    /// Wrap along u and along v.
    pub wrap: [Wrap; 2],
}

impl Default for UvMapping {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl UvMapping {
    /// The first coordinate set as it is, repeated.
    pub const IDENTITY: Self = Self {
        set: 0,
        transform: glam::Affine2::IDENTITY,
        wrap: [Wrap::Repeat; 2],
    };

    /// Whether the texture reads the first set as it is (then the mesh's own tangents,
    /// which follow that set, fit it).
    pub fn reads_first_set_unchanged(&self) -> bool {
        self.set == 0 && self.transform == glam::Affine2::IDENTITY
    }
}

/// A texture and how it is mapped onto a surface.
#[derive(Clone, Debug)]
pub struct MappedTexture {
    pub texture: Texture,
    pub mapping: UvMapping,
}

impl From<Texture> for MappedTexture {
    fn from(texture: Texture) -> Self {
        Self {
            texture,
            mapping: UvMapping::IDENTITY,
        }
    }
}

impl MappedTexture {
    /// Value at the coordinates `uv` of the mapping's set (the transform is applied here).
    pub fn eval(&self, uv: Vec2) -> Rgb {
        self.texture.eval_wrapped(
            self.mapping.transform.transform_point2(uv),
            self.mapping.wrap,
        )
    }

    /// Alpha at the coordinates `uv` of the mapping's set.
    pub fn alpha(&self, uv: Vec2) -> f32 {
        self.texture.alpha(
            self.mapping.transform.transform_point2(uv),
            self.mapping.wrap,
        )
    }
}

/// A raster of linear RGB texels, read with bilinear filtering; past its edges as the
/// caller's [`Wrap`] says (repeated by default).
#[derive(Clone, Debug, Default)]
pub struct ImageTexture {
    pub width: u32,
    pub height: u32,
    /// Row-major, top row first, linear RGB.
    pub texels: Vec<Rgb>,
    /// Alpha per texel (linear, as glTF defines it), parallel to `texels`; empty when the
    /// image is opaque.
    pub alpha: Vec<f32>,
}

impl ImageTexture {
    /// Bilinear lookup, repeated; `v = 0` is the bottom row.
    pub fn eval(&self, uv: Vec2) -> Rgb {
        self.eval_wrapped(uv, [Wrap::Repeat; 2])
    }

    /// Bilinear lookup with the given wrap modes along u and v.
    pub fn eval_wrapped(&self, uv: Vec2, wrap: [Wrap; 2]) -> Rgb {
        self.bilinear(uv, wrap, Rgb::ZERO, |k| self.texels[k])
    }

    /// Bilinear alpha, 1 for an opaque image.
    pub fn alpha(&self, uv: Vec2, wrap: [Wrap; 2]) -> f32 {
        if self.alpha.len() != self.texels.len() {
            return 1.0;
        }
        self.bilinear(uv, wrap, 0.0, |k| self.alpha[k])
    }

    fn bilinear<T>(&self, uv: Vec2, wrap: [Wrap; 2], outside: T, texel: impl Fn(usize) -> T) -> T
    where
        T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
    {
        let (w, h) = (self.width as i64, self.height as i64);
        if w == 0 || h == 0 {
            return outside;
        }
        // Texel centres sit at half-integer positions.
        let x = uv.x * w as f32 - 0.5;
        let y = (1.0 - uv.y) * h as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return outside;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: i64, j: i64| {
            let (i, j) = (wrap[0].index(i, w), wrap[1].index(j, h));
            texel((j * w + i) as usize)
        };
        let (i, j) = (x0 as i64, y0 as i64);
        let top = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
        let bottom = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
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
            alpha: Vec::new(),
        };
        assert_eq!(t.eval(Vec2::new(0.25, 0.5)), Rgb::ZERO);
        assert_eq!(t.eval(Vec2::new(0.75, 0.5)), Rgb::ONE);
        assert!((t.eval(Vec2::new(0.5, 0.5)).x - 0.5).abs() < 1e-6);
        let t = ImageTexture {
            width: 1,
            height: 2,
            texels: vec![Rgb::X, Rgb::Z],
            alpha: Vec::new(),
        };
        assert_eq!(t.eval(Vec2::new(0.5, 0.75)), Rgb::X);
        assert_eq!(t.eval(Vec2::new(0.5, 0.25)), Rgb::Z);
    }

    #[test]
    fn wrap_modes_fold_texel_indices_as_gltf_samplers_do() {
        let n = 4;
        let folded = |w: Wrap| (-5..9).map(|i| w.index(i, n)).collect::<Vec<_>>();
        assert_eq!(
            folded(Wrap::Repeat),
            [3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0]
        );
        assert_eq!(
            folded(Wrap::ClampToEdge),
            [0, 0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3]
        );
        assert_eq!(
            folded(Wrap::MirroredRepeat),
            [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0]
        );
    }

    #[test]
    fn clamped_and_mirrored_images_read_their_edge_not_the_opposite_one() {
        // 2×1: left black, right white. Just past u = 1 a repeated image blends back to
        // black; clamped it stays white; mirrored it reads white, then black by u = 1.75.
        let t = ImageTexture {
            width: 2,
            height: 1,
            texels: vec![Rgb::ZERO, Rgb::ONE],
            alpha: vec![0.0, 1.0],
        };
        let at = |u: f32, w: Wrap| t.eval_wrapped(Vec2::new(u, 0.5), [w, Wrap::Repeat]).x;
        assert_eq!(at(1.0, Wrap::Repeat), 0.5);
        assert_eq!(at(1.0, Wrap::ClampToEdge), 1.0);
        assert_eq!(at(1.0, Wrap::MirroredRepeat), 1.0);
        assert_eq!(at(1.75, Wrap::MirroredRepeat), 0.0);
        assert_eq!(at(-3.0, Wrap::ClampToEdge), 0.0);
        assert_eq!(t.alpha(Vec2::new(0.75, 0.5), [Wrap::Repeat; 2]), 1.0);
        assert_eq!(t.alpha(Vec2::new(0.25, 0.5), [Wrap::Repeat; 2]), 0.0);
    }
}
