//! Image files. The format follows the extension: `.png` (sRGB, exposure, clamped), `.exr`
//! (linear float RGB, or CIE 1931 XYZ on request), `.pfm` (linear float RGB). Every write goes to a temporary file in the
//! destination folder and is renamed over the target only once complete, so an interrupted or
//! failed write never destroys what the user had.

use crate::error::{Error, Result};
use crate::film::Image;
use crate::io::atomic::{check_writable_path, write_atomically, write_file};
use crate::io::decoded::{self, Footprint, Reservation};
use crate::math::Rgb;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Image formats Photon reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Exr,
    Pfm,
    /// NumPy arrays, one file per channel (`NAME_r.npy`, `NAME_g.npy`, `NAME_b.npy`).
    Npy,
}

const WRITABLE: &str = ".png, .exr, .pfm, .npy";
const READABLE: &str = ".exr, .pfm";

impl ImageFormat {
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(Self::Png),
            "exr" => Some(Self::Exr),
            "pfm" => Some(Self::Pfm),
            "npy" => Some(Self::Npy),
            _ => None,
        }
    }
}

fn unsupported(path: &Path, expected: &'static str) -> Error {
    Error::UnsupportedImageFormat {
        path: path.to_owned(),
        extension: path.extension().map_or_else(
            || "(none)".to_owned(),
            |e| format!(".{}", e.to_string_lossy()),
        ),
        expected,
    }
}

/// Check, before any work is done, that `path` names a format we write and a folder we can
/// write into.
pub fn check_writable(path: &Path) -> Result<ImageFormat> {
    let format = ImageFormat::from_path(path).ok_or_else(|| unsupported(path, WRITABLE))?;
    check_writable_path(path)?;
    Ok(format)
}

/// The colour space a float image is written in. Renders are linear sRGB (Rec. 709 primaries,
/// D65 white); XYZ is the same light in CIE 1931 XYZ, a linear map of it (Mitsuba 3's
/// `pixel_format = "xyz"`), which keeps colours outside the sRGB gamut without negative values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorSpace {
    #[default]
    LinearSrgb,
    Xyz,
}

/// How an image is written: the exposure a PNG takes, in stops, and the colour space of an
/// EXR.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WriteAs {
    pub exposure: f32,
    pub space: ColorSpace,
}

impl WriteAs {
    /// Linear sRGB, with `exposure` for PNG.
    pub fn exposure(exposure: f32) -> Self {
        Self {
            exposure,
            space: ColorSpace::LinearSrgb,
        }
    }

    /// Check, before any work is done, that `path` can be written so: XYZ goes only to
    /// OpenEXR, whose channels say what they hold.
    pub fn check(&self, path: &Path) -> Result<ImageFormat> {
        let format = check_writable(path)?;
        if self.space == ColorSpace::Xyz && format != ImageFormat::Exr {
            return Err(unsupported(path, "an .exr file for XYZ output"));
        }
        Ok(format)
    }
}

/// `render.npy` → `render_r.npy` (and `_g`, `_b`).
pub fn npy_channel_path(path: &Path, channel: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}_{channel}.npy"))
}

/// `render.png` + `direct` → `render.direct.png`: where an AOV goes when the format has no layers.
pub fn aov_path(path: &Path, aov: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    path.with_file_name(format!("{stem}.{aov}{ext}"))
}

/// sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn linear_to_srgb(x: f32) -> f32 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Write `image` as `how` says: the exposure applies to PNG only, since float formats keep
/// radiance; XYZ only to EXR.
pub fn write_image(image: &Image, path: &Path, how: WriteAs) -> Result<()> {
    let format = how.check(path)?;
    let exposure = how.exposure;
    let io_err = |source| Error::Write {
        path: path.to_owned(),
        source,
    };
    if format == ImageFormat::Npy {
        for (c, suffix) in ["r", "g", "b"].iter().enumerate() {
            write_npy_channel(image, c, &npy_channel_path(path, suffix))?;
        }
        return Ok(());
    }
    write_atomically(path, |tmp| match format {
        ImageFormat::Png => write_png(image, tmp, exposure).map_err(|e| Error::Write {
            path: path.to_owned(),
            source: std::io::Error::other(e),
        }),
        ImageFormat::Exr => write_exr(tmp, &[("", image)], how.space).map_err(|e| Error::Write {
            path: path.to_owned(),
            source: std::io::Error::other(e),
        }),
        ImageFormat::Pfm => write_pfm(image, tmp).map_err(io_err),
        ImageFormat::Npy => unreachable!("handled above"),
    })
}

/// Write a multi-layer OpenEXR the way Blender and compositors read it: one part whose plain
/// `R`, `G`, `B` channels hold the first image (the beauty), and `NAME.R`, `NAME.G`, `NAME.B`
/// for each further image (`direct.R`, …); `X`, `Y`, `Z` for each in XYZ.
pub fn write_exr_layers(path: &Path, layers: &[(&str, &Image)], space: ColorSpace) -> Result<()> {
    if layers.is_empty() {
        return Ok(());
    }
    write_atomically(path, |tmp| {
        write_exr(tmp, layers, space).map_err(|e| crate::error::Error::Write {
            path: path.to_owned(),
            source: std::io::Error::other(e),
        })
    })
}

/// The OpenEXR writer behind both: lossless (FAST_LOSSLESS) float channels, blocks in
/// increasing line order, compressed on one thread. On several threads the crate wrote the
/// blocks as they finished, whatever line order was asked for: two identical renders of 256²
/// and more gave different files with the same pixels. (A 512² EXR compresses in ~40 ms.)
/// In XYZ the channels are `X`, `Y`, `Z`, and the header's chromaticities are the XYZ space's
/// (OpenEXR's convention for XYZ data: red (1, 0), green (0, 1), blue (0, 0), white ⅓, ⅓).
fn write_exr(path: &Path, layers: &[(&str, &Image)], space: ColorSpace) -> exr::error::UnitResult {
    use exr::prelude::*;
    let first = layers[0].1;
    let size = (first.width as usize, first.height as usize);
    let letters = match space {
        ColorSpace::LinearSrgb => ["R", "G", "B"],
        ColorSpace::Xyz => ["X", "Y", "Z"],
    };
    let mut channels = Vec::new();
    for (k, (name, img)) in layers.iter().enumerate() {
        let pixels: Vec<Rgb> = match space {
            ColorSpace::LinearSrgb => img.pixels.clone(),
            ColorSpace::Xyz => img
                .pixels
                .iter()
                .map(|&p| crate::spectrum::linear_srgb_to_xyz(p))
                .collect(),
        };
        for (c, letter) in letters.iter().enumerate() {
            let full = if k == 0 {
                (*letter).to_owned()
            } else {
                format!("{name}.{letter}")
            };
            let samples = FlatSamples::F32(pixels.iter().map(|p| p[c]).collect());
            channels.push(AnyChannel::new(full.as_str(), samples));
        }
    }
    let encoding = Encoding {
        line_order: LineOrder::Increasing,
        ..Encoding::FAST_LOSSLESS
    };
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        encoding,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let mut image = exr::image::Image::from_layer(layer);
    if space == ColorSpace::Xyz {
        image.attributes.chromaticities = Some(attribute::Chromaticities {
            red: Vec2(1.0, 0.0),
            green: Vec2(0.0, 1.0),
            blue: Vec2(0.0, 0.0),
            white: Vec2(1.0 / 3.0, 1.0 / 3.0),
        });
    }
    image.write().non_parallel().to_file(path)
}

/// NumPy `.npy` (format 1.0) of one channel: a height × width little-endian float32 array, as
/// the original project saved its per-channel images.
pub fn write_npy_channel(image: &Image, channel: usize, path: &Path) -> Result<()> {
    let mut header = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({}, {}), }}",
        image.height, image.width
    );
    // The header, with magic and length, pads to a multiple of 64 bytes and ends in '\n'.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut bytes = Vec::with_capacity(10 + header.len() + image.pixels.len() * 4);
    bytes.extend_from_slice(b"\x93NUMPY\x01\x00");
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for p in &image.pixels {
        bytes.extend_from_slice(&p[channel].to_le_bytes());
    }
    write_file(path, &bytes)
}

fn write_png(image: &Image, path: &Path, exposure: f32) -> Result<(), image::ImageError> {
    let scale = exposure.exp2();
    let mut bytes = Vec::with_capacity(image.pixels.len() * 3);
    for p in &image.pixels {
        for c in p.to_array() {
            let v = linear_to_srgb((c * scale).clamp(0.0, 1.0));
            bytes.push((v * 255.0 + 0.5) as u8);
        }
    }
    image::save_buffer_with_format(
        path,
        &bytes,
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
}

/// Portable float map: a text header, then rows bottom to top, little-endian (negative scale).
fn write_pfm(image: &Image, path: &Path) -> std::io::Result<()> {
    let mut f = BufWriter::new(fs::File::create(path)?);
    write!(f, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    for y in (0..image.height).rev() {
        for x in 0..image.width {
            for c in image.get(x, y).to_array() {
                f.write_all(&c.to_le_bytes())?;
            }
        }
    }
    f.flush()
}

/// Read a linear image (OpenEXR or PFM).
pub fn read_image(path: &Path) -> Result<Image> {
    read_linear(path, MAX_IMAGE_PIXELS).map(|(image, _room)| image)
}

/// Read two linear images needed together (an image and its reference): the second must fit
/// the decoded-image budget beside the first.
pub fn read_image_pair(first: &Path, second: &Path) -> Result<(Image, Image)> {
    let (a, _room) = read_linear(first, MAX_IMAGE_PIXELS)?;
    let (b, _) = read_linear(second, MAX_IMAGE_PIXELS)?;
    Ok((a, b))
}

/// An OpenEXR or PFM image of at most `max_pixels`, and its room in the decoded-image budget.
fn read_linear(path: &Path, max_pixels: u64) -> Result<(Image, Reservation)> {
    let format = ImageFormat::from_path(path).ok_or_else(|| unsupported(path, READABLE))?;
    if !path.exists() {
        return Err(Error::Read {
            path: path.to_owned(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
        });
    }
    match format {
        ImageFormat::Exr => read_exr(path, max_pixels),
        ImageFormat::Pfm => {
            let data = crate::io::input::read_file(path)?;
            parse_pfm(&data, path, max_pixels)
        }
        ImageFormat::Png | ImageFormat::Npy => Err(unsupported(path, READABLE)),
    }
}

fn bad_image(path: &Path, message: String) -> Error {
    Error::BadImage {
        path: path.to_owned(),
        message,
    }
}

/// Room for a linear RGB image of `w` × `h` pixels (12 bytes each), refused past `max_pixels`
/// or the budget.
fn reserve_linear(path: &Path, w: u64, h: u64, max_pixels: u64) -> Result<Reservation> {
    let room = decoded::reserve(
        path,
        Footprint {
            width: w.try_into().unwrap_or(u32::MAX),
            height: h.try_into().unwrap_or(u32::MAX),
            kept_per_pixel: size_of::<Rgb>() as u64,
            transient_per_pixel: 0,
        },
    )?;
    if w.saturating_mul(h) > max_pixels {
        return Err(bad_image(
            path,
            format!("{w}×{h} pixels is more than the {max_pixels} accepted"),
        ));
    }
    Ok(room)
}

/// The first RGB layer of an OpenEXR file, at its largest resolution. Its size is the
/// header's word: room for it is taken before its pixels are allocated (an empty image
/// stands in for a refused one, and the refusal is returned).
fn read_exr(path: &Path, max_pixels: u64) -> Result<(Image, Reservation)> {
    use exr::prelude::{ReadChannels as _, ReadLayers as _};
    type Outcome = Option<Result<Reservation>>;
    fn lock(m: &Mutex<Outcome>) -> std::sync::MutexGuard<'_, Outcome> {
        m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }
    let bytes = crate::io::input::read_file(path)?;
    // Every layer's size, from the headers alone: a refused file is not decompressed.
    let meta = exr::meta::MetaData::read_from_buffered(bytes.as_slice(), false)
        .map_err(|e| bad_image(path, format!("not a readable OpenEXR image: {e}")))?;
    for header in &meta.headers {
        let size = header.layer_size;
        drop(reserve_linear(
            path,
            size.width() as u64,
            size.height() as u64,
            max_pixels,
        )?);
    }
    let outcome: Arc<Mutex<Outcome>> = Arc::default();
    let seen = outcome.clone();
    let owned = path.to_owned();
    let img = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            move |res: exr::math::Vec2<usize>, _: &exr::image::RgbaChannels| {
                let (w, h) = (res.width() as u64, res.height() as u64);
                let made = reserve_linear(&owned, w, h, max_pixels)
                    .and_then(|room| Ok((decoded::zeroed::<Rgb>(&owned, (w * h) as usize)?, room)));
                let (image, room) = match made {
                    Ok((pixels, room)) => {
                        let (width, height) = (w as u32, h as u32);
                        (
                            Image {
                                width,
                                height,
                                pixels,
                            },
                            Ok(room),
                        )
                    }
                    Err(e) => (Image::new(0, 0), Err(e)),
                };
                *lock(&seen) = Some(room);
                image
            },
            |img: &mut Image, pos: exr::math::Vec2<usize>, (r, g, b, _a): (f32, f32, f32, f32)| {
                if img.width > 0 {
                    img.set(pos.x() as u32, pos.y() as u32, Rgb::new(r, g, b));
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes));
    let room = lock(&outcome).take().transpose()?;
    let img = img.map_err(|e| bad_image(path, format!("not a readable OpenEXR image: {e}")))?;
    let room = room.ok_or_else(|| bad_image(path, "it has no RGB layer".into()))?;
    Ok((img.layer_data.channel_data.pixels, room))
}

/// Formats an environment map may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvironmentFormat {
    Exr,
    Hdr,
    Pfm,
}

impl EnvironmentFormat {
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "exr" => Some(Self::Exr),
            "hdr" => Some(Self::Hdr),
            "pfm" => Some(Self::Pfm),
            _ => None,
        }
    }
}

/// Largest image read (compare inputs, EXR environment maps), in pixels: 32k × 32k.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 30;

/// Largest environment map accepted, in pixels (16k × 8k).
pub const MAX_ENVIRONMENT_PIXELS: u64 = 1 << 27;

/// Read an equirectangular environment map: OpenEXR, Radiance HDR (RGBE) or PFM, linear RGB,
/// top row first. Negative and non-finite values are errors, not light. The map counts against
/// the decoded-image budget while it is held.
pub fn read_environment(path: &Path) -> Result<Arc<crate::light::EnvironmentMap>> {
    let format =
        EnvironmentFormat::from_path(path).ok_or_else(|| unsupported(path, ".exr, .hdr, .pfm"))?;
    let bad = |message: String| bad_image(path, message);
    let (image, room) = match format {
        EnvironmentFormat::Exr | EnvironmentFormat::Pfm => {
            read_linear(path, MAX_ENVIRONMENT_PIXELS)?
        }
        EnvironmentFormat::Hdr => read_hdr(path)?,
    };
    if image.width == 0 || image.height == 0 {
        return Err(bad("the image is empty".into()));
    }
    if let Some(i) = image
        .pixels
        .iter()
        .position(|p| !p.is_finite() || p.min_element() < 0.0)
    {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        return Err(bad(format!(
            "pixel ({x}, {y}) is {}: radiance must be finite and not negative",
            image.pixels[i]
        )));
    }
    let bytes = (image.pixels.len() * size_of::<Rgb>()) as u64;
    let map = Arc::new(crate::light::EnvironmentMap {
        width: image.width,
        height: image.height,
        texels: image.pixels,
    });
    room.hold(&map, bytes);
    Ok(map)
}

/// A Radiance HDR (RGBE) image, decoded straight into its texels (the decoder's own buffer is
/// one scan line), after room for them is taken from the header's size.
fn read_hdr(path: &Path) -> Result<(Image, Reservation)> {
    use image::ImageDecoder as _;
    let bad =
        |e: image::ImageError| bad_image(path, format!("not a readable Radiance HDR image: {e}"));
    let bytes = crate::io::input::read_file(path)?;
    let decoder = image::codecs::hdr::HdrDecoder::new(std::io::Cursor::new(&bytes)).map_err(bad)?;
    let (w, h) = decoder.dimensions();
    let room = reserve_linear(path, w.into(), h.into(), MAX_ENVIRONMENT_PIXELS)?;
    let mut pixels = decoded::zeroed::<Rgb>(path, w as usize * h as usize)?;
    decoder
        .read_image(bytemuck::cast_slice_mut(&mut pixels))
        .map_err(bad)?;
    let image = Image {
        width: w,
        height: h,
        pixels,
    };
    Ok((image, room))
}

/// A PFM image of at most `max_pixels`, and its room in the decoded-image budget.
fn parse_pfm(data: &[u8], path: &Path, max_pixels: u64) -> Result<(Image, Reservation)> {
    let (w, h, channels, scale, body) = pfm_header(data).map_err(|m| bad_image(path, m))?;
    let room = reserve_linear(path, w.into(), h.into(), max_pixels)?;
    let pixels = decoded::zeroed::<Rgb>(path, w as usize * h as usize)?;
    let mut img = Image {
        width: w,
        height: h,
        pixels,
    };
    let mut k = 0;
    for y in (0..h).rev() {
        for x in 0..w {
            let mut c = [0.0f32; 3];
            for v in c.iter_mut().take(channels) {
                let b = [body[k], body[k + 1], body[k + 2], body[k + 3]];
                *v = if scale < 0.0 {
                    f32::from_le_bytes(b)
                } else {
                    f32::from_be_bytes(b)
                };
                k += 4;
            }
            if channels == 1 {
                c = [c[0]; 3];
            }
            img.set(x, y, Rgb::from_array(c));
        }
    }
    Ok((img, room))
}

/// A PFM file's width, height, channels (1 or 3), scale (its sign gives the byte order) and
/// pixel data, checked to be long enough.
type PfmHeader<'a> = (u32, u32, usize, f32, &'a [u8]);

fn pfm_header(data: &[u8]) -> Result<PfmHeader<'_>, String> {
    // Header: three whitespace-separated tokens after the magic, then one whitespace byte.
    let mut tokens = Vec::new();
    let mut i = 0;
    while tokens.len() < 4 {
        while i < data.len() && data[i].is_ascii_whitespace() {
            i += 1;
        }
        let start = i;
        while i < data.len() && !data[i].is_ascii_whitespace() {
            i += 1;
        }
        if start == i {
            return Err("truncated PFM header".into());
        }
        tokens.push(String::from_utf8_lossy(&data[start..i]).into_owned());
    }
    i += 1;
    let channels = match tokens[0].as_str() {
        "PF" => 3,
        "Pf" => 1,
        m => {
            return Err(format!(
                "not a PFM file (magic '{m}', expected 'PF' or 'Pf')"
            ));
        }
    };
    let parse = |s: &str, what: &str| {
        s.parse::<u32>()
            .map_err(|_| format!("bad {what} '{s}' in PFM header"))
    };
    let (w, h) = (parse(&tokens[1], "width")?, parse(&tokens[2], "height")?);
    let scale: f32 = tokens[3]
        .parse()
        .map_err(|_| format!("bad scale '{}' in PFM header", tokens[3]))?;
    let needed = (w as usize)
        .checked_mul(h as usize)
        .and_then(|n| n.checked_mul(channels * 4))
        .ok_or("PFM dimensions overflow")?;
    let body = data.get(i..).unwrap_or_default();
    if body.len() < needed {
        return Err(format!(
            "truncated PFM data: {} bytes, expected {needed}",
            body.len()
        ));
    }
    Ok((w, h, channels, scale, body))
}
