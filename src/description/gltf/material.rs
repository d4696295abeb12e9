//! glTF metallic-roughness materials onto ours (`pbr`, or rough glass for transmission), with
//! their base-colour, metallic-roughness, normal and emissive textures, each read through its
//! own coordinate set, `KHR_texture_transform` and sampler wrap modes, and their `alphaMode`.

use super::{Opened, Sink, read_uri};
use crate::description::mesh::ImportedMaterial;
use crate::description::{ColorSpec, EmissionSpec, ImageRef, MaterialSpec, PbrSpec, SharedTexture};
use crate::error::Result;
use crate::io::texture::Encoding;
use crate::material::{Attenuation, Dispersion};
use crate::math::Rgb;
use crate::scene::Coverage;
use crate::texture::{UvMapping, Wrap};
use glam::{Affine2, Vec2};
use std::path::Path;
use std::sync::Arc;

/// `KHR_texture_transform` on a texture reference, with the extension's defaults.
#[derive(Clone, Copy, Debug, serde::Deserialize)]
#[serde(default, rename_all = "camelCase")]
pub(super) struct TextureTransform {
    offset: [f32; 2],
    rotation: f32,
    scale: [f32; 2],
    /// Overrides the reference's own `texCoord` (the extension's rule).
    tex_coord: Option<u32>,
}

impl Default for TextureTransform {
    fn default() -> Self {
        Self {
            offset: [0.0; 2],
            rotation: 0.0,
            scale: [1.0; 2],
            tex_coord: None,
        }
    }
}

impl TextureTransform {
    fn of_info(info: &gltf::texture::Info) -> Option<Self> {
        info.texture_transform().map(|t| Self {
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
            tex_coord: t.tex_coord(),
        })
    }

    /// The transform in our coordinates (v up). The extension's matrix acts on glTF's
    /// (v down): uv' = T(offset) · R(rotation) · S(scale) · uv, where R turns the UVs
    /// counter-clockwise by `rotation` seen in the image, u' = cos·u + sin·v,
    /// v' = −sin·u + cos·v (column-major `mat3(cos, −sin, 0, sin, cos, 0, 0, 0, 1)`; the
    /// extension's example: offset (0, 1), rotation π/2 and scale ½ show the lower-left
    /// quadrant turned clockwise). Ours is F · M · F with F(u, v) = (u, 1 − v).
    fn in_our_coordinates(&self) -> Affine2 {
        let (sin, cos) = self.rotation.sin_cos();
        let gltf = Affine2::from_translation(Vec2::from(self.offset))
            * Affine2::from_cols(Vec2::new(cos, -sin), Vec2::new(sin, cos), Vec2::ZERO)
            * Affine2::from_scale(Vec2::from(self.scale));
        let flip = Affine2::from_cols(Vec2::X, -Vec2::Y, Vec2::Y);
        flip * gltf * flip
    }
}

/// How a texture reference reads its texture: its coordinate set (`texCoord`, or the
/// transform's override), its transform and its sampler's wrap modes.
pub(super) fn uv_mapping(
    g: &Opened,
    sink: &mut Sink,
    texture: &gltf::Texture,
    tex_coord: u32,
    transform: Option<TextureTransform>,
) -> Result<UvMapping> {
    let transform = transform.unwrap_or_default();
    let numbers = [
        transform.offset[0],
        transform.offset[1],
        transform.rotation,
        transform.scale[0],
        transform.scale[1],
    ];
    if numbers.iter().any(|x| !x.is_finite()) {
        return Err(g.error(format!(
            "a KHR_texture_transform of texture {} has a value that is not finite (offset, rotation, scale: {numbers:?})",
            texture.index()
        )));
    }
    let set = transform.tex_coord.unwrap_or(tex_coord);
    if set > 1 {
        sink.warn("textures on texture coordinate sets past TEXCOORD_1 read TEXCOORD_0");
    }
    // glTF 2.0 §5.26 (sampler): wrapS and wrapT, REPEAT where not given.
    let json = texture
        .sampler()
        .index()
        .and_then(|i| g.doc.as_json().samplers.get(i));
    let wrap_of =
        |mode: Option<&gltf::json::validation::Checked<gltf::texture::WrappingMode>>| match mode {
            Some(gltf::json::validation::Checked::Valid(m)) => match m {
                gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
                gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
                gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
            },
            _ => Wrap::Repeat,
        };
    Ok(UvMapping {
        set: u8::from(set == 1),
        transform: transform.in_our_coordinates(),
        wrap: [
            wrap_of(json.map(|s| &s.wrap_s)),
            wrap_of(json.map(|s| &s.wrap_t)),
        ],
    })
}

/// The absorption inside a transmissive material, from `KHR_materials_volume`: its attenuation
/// colour and distance (world units) where `thicknessFactor` > 0 says the mesh encloses a
/// volume; `None` for clear glass (colour 1 or distance ∞, the extension's defaults). The
/// thickness itself is not needed: refraction is traced through the real geometry, which is
/// what the extension asks of path tracers (its thickness is a rasteriser's stand-in).
fn attenuation(
    g: &Opened,
    sink: &mut Sink,
    m: &gltf::Material,
    name: &str,
) -> Result<Option<Attenuation>> {
    let Some(volume) = m.volume() else {
        // Blender writes no volume for its glass; its objects are solid all the same.
        sink.warn("transmissive materials without KHR_materials_volume are rendered as solid glass (refracting), not thin-walled");
        return Ok(None);
    };
    let color = Rgb::from_array(volume.attenuation_color());
    let distance = volume.attenuation_distance();
    // The extension's ranges: the colour in [0, 1], the distance > 0 (default +∞).
    if !(color.is_finite() && color.min_element() >= 0.0 && color.max_element() <= 1.0)
        || distance.is_nan()
        || distance <= 0.0
    {
        return Err(g.error(format!(
            "material '{name}' has KHR_materials_volume attenuation colour {:?} and distance {distance}: the colour must be in [0, 1] and the distance positive",
            color.to_array()
        )));
    }
    let clear = color == Rgb::ONE || distance == f32::INFINITY;
    if volume.thickness_factor() <= 0.0 {
        // Thin-walled by the extension's letter: no volume to absorb in.
        sink.warn("KHR_materials_volume with thicknessFactor 0 (thin-walled) is rendered as solid glass without absorption");
        return Ok(None);
    }
    Ok((!clear).then_some(Attenuation { color, distance }))
}

/// `KHR_materials_dispersion`: `dispersion` = 20 / V_d (0, the default, is none), a Cauchy
/// glass through the material's index at the d line (the extension's definition).
fn dispersion(g: &Opened, m: &gltf::Material, name: &str, ior: f32) -> Result<Dispersion> {
    let Some(ext) = m.extension_value("KHR_materials_dispersion") else {
        return Ok(Dispersion::None);
    };
    let value = match ext.get("dispersion") {
        None => 0.0,
        Some(v) => v.as_f64().unwrap_or(f64::NAN) as f32,
    };
    if !(value.is_finite() && value >= 0.0) {
        return Err(g.error(format!(
            "material '{name}' has KHR_materials_dispersion {}: dispersion must be a number ≥ 0",
            ext.get("dispersion")
                .map_or_else(String::new, ToString::to_string)
        )));
    }
    if value == 0.0 {
        return Ok(Dispersion::None);
    }
    let d = Dispersion::from_abbe(ior, 20.0 / value);
    if !d.is_valid() {
        return Err(g.error(format!(
            "material '{name}' has KHR_materials_dispersion {value} with ior {ior}: its index leaves 1 to 5 in the visible range"
        )));
    }
    Ok(d)
}

pub(super) fn convert_material(
    g: &Opened,
    sink: &mut Sink,
    m: &gltf::Material,
) -> Result<ImportedMaterial> {
    let name = m.name().map(str::to_owned).unwrap_or_else(|| {
        m.index()
            .map_or("default".into(), |i| format!("material {i}"))
    });
    let pbr = m.pbr_metallic_roughness();
    let [r, gr, b, alpha] = pbr.base_color_factor();
    let base = Rgb::new(r, gr, b);
    let factors = [
        r,
        gr,
        b,
        alpha,
        m.alpha_cutoff().unwrap_or(0.5),
        pbr.metallic_factor(),
        pbr.roughness_factor(),
        m.emissive_factor()[0],
        m.emissive_factor()[1],
        m.emissive_factor()[2],
        m.emissive_strength().unwrap_or(1.0),
    ];
    if factors.iter().any(|x| !x.is_finite() || *x < 0.0) {
        return Err(g.error(format!(
            "material '{name}' has a factor that is negative or not finite ({factors:?}); glTF's factors are finite and ≥ 0"
        )));
    }
    let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
    // glTF 2.0 §3.9.4: OPAQUE ignores alpha; MASK keeps the surface where alpha ≥ cutoff
    // (0.5 by default); BLEND makes it that transparent (here: there with probability alpha).
    let coverage = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => Coverage::Opaque,
        gltf::material::AlphaMode::Mask => Coverage::Mask {
            alpha,
            cutoff: m.alpha_cutoff().unwrap_or(0.5),
        },
        gltf::material::AlphaMode::Blend => Coverage::Blend { alpha },
    };
    if let Some(ior) = m.ior()
        && !(ior.is_finite() && ior > 0.0)
    {
        return Err(g.error(format!(
            "material '{name}' has KHR_materials_ior {ior}: the index of refraction must be positive and finite"
        )));
    }
    if m.occlusion_texture().is_some() {
        sink.warn("occlusion maps are ignored (a path tracer finds occlusion itself)");
    }
    if m.transmission()
        .is_some_and(|t| t.transmission_texture().is_some())
    {
        sink.warn("transmission textures are ignored (the transmission factor is used)");
    }
    let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
    let spec = if m.index().is_none() {
        // No material: glTF's default is a rough white metal; a grey diffuse is what
        // importers (Blender's among them) show.
        MaterialSpec::Diffuse {
            albedo: ColorSpec::Constant(Rgb::splat(0.8)),
        }
    } else if transmission > 0.0 {
        if coverage != Coverage::Opaque {
            sink.warn(
                "alphaMode MASK and BLEND are ignored on transmissive materials (they are glass)",
            );
        }
        if transmission < 1.0 {
            sink.warn("partial transmission is rendered as fully transmissive glass");
        }
        let ior = m.ior().unwrap_or(1.5);
        MaterialSpec::Glass {
            ior,
            transmittance: base,
            alpha: roughness * roughness,
            attenuation: attenuation(g, sink, m, &name)?,
            dispersion: dispersion(g, m, &name, ior)?,
        }
    } else {
        let base_color = match pbr.base_color_texture() {
            Some(info) => ColorSpec::Decoded {
                texture: texture(g, sink, &info, Encoding::Srgb)?,
                tint: base,
            },
            None => ColorSpec::Constant(base),
        };
        let metallic_roughness = match pbr.metallic_roughness_texture() {
            Some(info) => Some(ImageRef::Decoded(texture(
                g,
                sink,
                &info,
                Encoding::Linear,
            )?)),
            None => None,
        };
        let normal_map = match m.normal_texture() {
            Some(n) => {
                // `gltf` does not hand out the normal texture's transform; it is read from
                // the JSON.
                let transform = m
                    .index()
                    .and_then(|i| {
                        g.raw
                            .pointer(&format!(
                                "/materials/{i}/normalTexture/extensions/KHR_texture_transform"
                            ))
                            .cloned()
                    })
                    .map(serde_json::from_value::<TextureTransform>)
                    .transpose()
                    .map_err(|e| {
                        g.error(format!(
                            "material '{name}': the normal texture's KHR_texture_transform cannot be read: {e}"
                        ))
                    })?;
                let mapping = uv_mapping(g, sink, &n.texture(), n.tex_coord(), transform)?;
                let image = texture_of(g, sink, &n.texture(), Encoding::Linear)?;
                Some((
                    ImageRef::Decoded(SharedTexture { image, mapping }),
                    n.scale(),
                ))
            }
            None => None,
        };
        let specular = match m.specular() {
            Some(sp) => {
                if sp.specular_color_factor() != [1.0, 1.0, 1.0]
                    || sp.specular_texture().is_some()
                    || sp.specular_color_texture().is_some()
                {
                    sink.warn("KHR_materials_specular: its colour and textures are ignored (its factor is used)");
                }
                sp.specular_factor()
            }
            None => 1.0,
        };
        MaterialSpec::Pbr(PbrSpec {
            base_color,
            metallic,
            roughness,
            specular,
            metallic_roughness,
            normal_map,
            coverage,
        })
    };
    let emitted = Rgb::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
    // An emissive texture multiplies the factor (sRGB, as the spec defines it): the surface
    // becomes an area light whose radiance varies with it.
    let emissive_texture = match m.emissive_texture() {
        Some(info) if emitted.max_element() > 0.0 => {
            Some(ImageRef::Decoded(texture(g, sink, &info, Encoding::Srgb)?))
        }
        _ => None,
    };
    let emission = (emitted.max_element() > 0.0).then_some(EmissionSpec::Radiance {
        radiance: emitted,
        two_sided: m.double_sided(),
        texture: emissive_texture,
        spectrum: None,
    });
    Ok(ImportedMaterial {
        name,
        spec,
        emission,
    })
}

/// The texture of a texture-info (colour, metallic-roughness, emissive) with its mapping.
fn texture(
    g: &Opened,
    sink: &mut Sink,
    info: &gltf::texture::Info,
    encoding: Encoding,
) -> Result<SharedTexture> {
    let mapping = uv_mapping(
        g,
        sink,
        &info.texture(),
        info.tex_coord(),
        TextureTransform::of_info(info),
    )?;
    let image = texture_of(g, sink, &info.texture(), encoding)?;
    Ok(SharedTexture { image, mapping })
}

fn texture_of(
    g: &Opened,
    sink: &mut Sink,
    t: &gltf::Texture,
    encoding: Encoding,
) -> Result<Arc<crate::texture::ImageTexture>> {
    let image = t.source();
    let key = (image.index(), encoding == Encoding::Linear);
    if let Some(done) = sink.textures.get(&key) {
        return Ok(done.clone());
    }
    let label = g.path.join(format!("images[{}]", image.index()));
    // `gltf` unwraps these two when asked for the source (fuzzing found the panics).
    if let Some(json) = g.doc.as_json().images.get(image.index()) {
        match (&json.buffer_view, &json.mime_type, &json.uri) {
            (Some(_), None, _) => {
                return Err(g.error(format!(
                    "image {} lies in a bufferView but gives no mimeType",
                    image.index()
                )));
            }
            (None, _, None) => {
                return Err(g.error(format!(
                    "image {} has neither a uri nor a bufferView",
                    image.index()
                )));
            }
            _ => {}
        }
    }
    let bytes = match image.source() {
        gltf::image::Source::View { view, .. } => {
            let buffer = g
                .buffers
                .get(view.buffer().index())
                .map_or(&[][..], Vec::as_slice);
            buffer
                .get(view.offset()..view.offset() + view.length())
                .ok_or_else(|| g.error(format!("image {} lies outside its buffer", image.index())))?
                .to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => {
            let dir = g.path.parent().unwrap_or(Path::new("")).to_owned();
            read_uri(&g.path, &dir, uri)?
        }
    };
    let decoded = crate::io::texture::decode_texture_as(&bytes, &label, encoding)?;
    sink.textures.insert(key, decoded.clone());
    Ok(decoded)
}
