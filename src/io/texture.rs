//! Reading image textures (PNG, JPEG) into linear RGB.

use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::texture::ImageTexture;
use std::path::Path;

/// Largest texture accepted, in texels (a 16k × 16k image); bigger files are refused before
/// their pixels are decoded.
pub const MAX_TEXELS: u64 = 1 << 28;

/// sRGB transfer function inverted (IEC 61966-2-1): an 8-bit colour value to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// How a texture's 8-bit values map to the numbers it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Colours, as painted: sRGB-encoded.
    Srgb,
    /// Data (normal maps, metallic-roughness): values / 255 as they are.
    Linear,
}

/// Decode an sRGB-encoded colour texture from memory; `name` is used in error messages.
pub fn decode_texture(bytes: &[u8], name: &Path) -> Result<ImageTexture> {
    decode_texture_as(bytes, name, Encoding::Srgb)
}

/// Decode a texture from memory with the given encoding.
pub fn decode_texture_as(bytes: &[u8], name: &Path, encoding: Encoding) -> Result<ImageTexture> {
    let bad = |message: String| Error::BadImage {
        path: name.to_owned(),
        message,
    };
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| bad(e.to_string()))?;
    if reader.format().is_none() {
        return Err(bad("not a PNG or JPEG image".into()));
    }
    let mut reader = reader;
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_TEXELS * 16);
    reader.limits(limits);
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| bad(format!("cannot read the image size: {e}")))?;
    if u64::from(w) * u64::from(h) > MAX_TEXELS {
        return Err(bad(format!(
            "{w}×{h} texels is more than the {MAX_TEXELS} a texture may have"
        )));
    }
    let decoded = image::load_from_memory(bytes).map_err(|e| bad(e.to_string()))?;
    // Alpha is kept (linear, glTF 2.0 §3.9.2: the sRGB transfer applies to RGB only) where
    // the image has a channel for it and uses it.
    let alpha: Vec<f32> = if decoded.color().has_alpha() {
        decoded
            .to_rgba8()
            .pixels()
            .map(|p| f32::from(p[3]) / 255.0)
            .collect()
    } else {
        Vec::new()
    };
    let alpha = if alpha.iter().all(|&a| a == 1.0) {
        Vec::new()
    } else {
        alpha
    };
    let rgb = decoded.to_rgb8();
    // 256-entry table: the same decode for every texel, cheap.
    let table: Vec<f32> = (0..=255u8)
        .map(|v| match encoding {
            Encoding::Srgb => srgb_to_linear(f32::from(v) / 255.0),
            Encoding::Linear => f32::from(v) / 255.0,
        })
        .collect();
    let texels = rgb
        .pixels()
        .map(|p| {
            Rgb::new(
                table[p[0] as usize],
                table[p[1] as usize],
                table[p[2] as usize],
            )
        })
        .collect();
    Ok(ImageTexture {
        width: rgb.width(),
        height: rgb.height(),
        texels,
        alpha,
    })
}

/// Read a colour texture from a PNG or JPEG file.
pub fn read_texture(path: &Path) -> Result<ImageTexture> {
    read_texture_as(path, Encoding::Srgb)
}

/// Read a PNG or JPEG texture with the given encoding.
pub fn read_texture_as(path: &Path, encoding: Encoding) -> Result<ImageTexture> {
    let bytes = crate::io::input::read_file(path)?;
    decode_texture_as(&bytes, path, encoding)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_decoding_matches_the_standard() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214).abs() < 1e-3);
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        assert!(decode_texture(b"not an image", Path::new("x.png")).is_err());
    }
}
