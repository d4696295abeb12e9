//! Reading image textures (PNG, JPEG) into linear RGB, within the decoded-image budget
//! ([`crate::io::decoded`]).

use crate::error::{Error, Result};
use crate::io::decoded::{self, Footprint};
use crate::math::Rgb;
use crate::texture::ImageTexture;
use image::ImageDecoder as _;
use std::path::Path;
use std::sync::Arc;

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
pub fn decode_texture(bytes: &[u8], name: &Path) -> Result<Arc<ImageTexture>> {
    decode_texture_as(bytes, name, Encoding::Srgb)
}

/// Decode a texture from memory with the given encoding. The same bytes decoded the same way
/// give the same texture, decoded once, while it is held (see [`crate::io::decoded`]).
pub fn decode_texture_as(
    bytes: &[u8],
    name: &Path,
    encoding: Encoding,
) -> Result<Arc<ImageTexture>> {
    let key = decoded::content_key(encoding as u8, bytes);
    if let Some(texture) = decoded::cached::<ImageTexture>(key) {
        return Ok(texture);
    }
    let bad = |message: String| Error::BadImage {
        path: name.to_owned(),
        message,
    };
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| bad(e.to_string()))?;
    let format = match reader.format() {
        Some(f @ (image::ImageFormat::Png | image::ImageFormat::Jpeg)) => f,
        _ => return Err(bad("not a PNG or JPEG image".into())),
    };
    let mut reader = reader;
    // The budget bounds the decoder's own buffers too; the pixels are reserved below.
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(decoded::limit()?);
    reader.limits(limits);
    let decoder = reader
        .into_decoder()
        .map_err(|e| bad(format!("cannot read the image header: {e}")))?;
    let (w, h) = decoder.dimensions();
    if u64::from(w) * u64::from(h) > MAX_TEXELS {
        return Err(bad(format!(
            "{w}×{h} texels is more than the {MAX_TEXELS} a texture may have"
        )));
    }
    let color = decoder.color_type();
    let reservation = decoded::reserve(name, footprint(format, color, w, h))?;
    let mut raw = decoded::zeroed::<u8>(name, decoder.total_bytes() as usize)?;
    decoder
        .read_image(&mut raw)
        .map_err(|e| bad(e.to_string()))?;
    let texture = Arc::new(
        texels_of(&raw, color, w, h, encoding)
            .ok_or_else(|| bad(format!("unsupported pixel type {color:?}")))?,
    );
    let kept = (texture.texels.len() * size_of::<Rgb>() + texture.alpha.len() * 4) as u64;
    reservation.hold(&texture, kept);
    decoded::remember(key, &texture);
    Ok(texture)
}

/// What decoding a texture costs: its texels (linear RGB, and alpha where the image has a
/// channel for it) kept, and the decoder's own pixels while it runs (a JPEG decoder also holds
/// 16-bit coefficients, two arrays of them, per component).
fn footprint(format: image::ImageFormat, color: image::ColorType, w: u32, h: u32) -> Footprint {
    let alpha = if color.has_alpha() { 4 } else { 0 };
    let raw = u64::from(color.bytes_per_pixel());
    let coefficients = if format == image::ImageFormat::Jpeg {
        4 * u64::from(color.channel_count())
    } else {
        0
    };
    Footprint {
        width: w,
        height: h,
        kept_per_pixel: size_of::<Rgb>() as u64 + alpha,
        transient_per_pixel: raw + coefficients,
    }
}

/// The texture of decoded pixels `raw` (8 or 16 bits a sample, grey or RGB, with or without
/// alpha; 16-bit samples rounded to 8 bits as the `image` crate does). Alpha is kept (linear,
/// glTF 2.0 §3.9.2: the sRGB transfer applies to RGB only) where the image has a channel for it
/// and uses it. `None` for other pixel types.
fn texels_of(
    raw: &[u8],
    color: image::ColorType,
    w: u32,
    h: u32,
    encoding: Encoding,
) -> Option<ImageTexture> {
    use image::ColorType as C;
    let (channels, wide) = match color {
        C::L8 | C::La8 | C::Rgb8 | C::Rgba8 => (usize::from(color.channel_count()), false),
        C::L16 | C::La16 | C::Rgb16 | C::Rgba16 => (usize::from(color.channel_count()), true),
        _ => return None,
    };
    let sample = |k: usize| -> u8 {
        if wide {
            let v = u16::from_ne_bytes([raw[2 * k], raw[2 * k + 1]]);
            ((u32::from(v) + 128) / 257) as u8
        } else {
            raw[k]
        }
    };
    let rgb = if channels >= 3 { [0, 1, 2] } else { [0, 0, 0] };
    let alpha_at = color.has_alpha().then_some(channels - 1);
    // 256-entry table: the same decode for every texel, cheap.
    let table: Vec<f32> = (0..=255u8)
        .map(|v| match encoding {
            Encoding::Srgb => srgb_to_linear(f32::from(v) / 255.0),
            Encoding::Linear => f32::from(v) / 255.0,
        })
        .collect();
    let n = w as usize * h as usize;
    let texels = (0..n)
        .map(|i| {
            let at = |c: usize| table[usize::from(sample(i * channels + rgb[c]))];
            Rgb::new(at(0), at(1), at(2))
        })
        .collect();
    let alpha: Vec<f32> = match alpha_at {
        Some(a) if (0..n).any(|i| sample(i * channels + a) != 255) => (0..n)
            .map(|i| f32::from(sample(i * channels + a)) / 255.0)
            .collect(),
        _ => Vec::new(),
    };
    Some(ImageTexture {
        width: w,
        height: h,
        texels,
        alpha,
    })
}

/// Read a colour texture from a PNG or JPEG file.
pub fn read_texture(path: &Path) -> Result<Arc<ImageTexture>> {
    read_texture_as(path, Encoding::Srgb)
}

/// Read a PNG or JPEG texture with the given encoding.
pub fn read_texture_as(path: &Path, encoding: Encoding) -> Result<Arc<ImageTexture>> {
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
