//! glTF metallic-roughness materials onto ours (`pbr`, or rough glass for transmission), with
//! their base-colour, metallic-roughness and normal textures.

use super::{Opened, Sink, read_uri};
use crate::description::mesh::ImportedMaterial;
use crate::description::{ColorSpec, EmissionSpec, ImageRef, MaterialSpec, PbrSpec, SharedTexture};
use crate::error::Result;
use crate::io::texture::Encoding;
use crate::math::Rgb;
use crate::texture::ImageTexture;
use std::path::Path;
use std::sync::Arc;

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
    let [r, gr, b, _] = pbr.base_color_factor();
    let base = Rgb::new(r, gr, b);
    let factors = [
        r,
        gr,
        b,
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
    if m.alpha_mode() != gltf::material::AlphaMode::Opaque {
        sink.warn("alpha blending and masking are ignored (surfaces are opaque)");
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
        if transmission < 1.0 {
            sink.warn("partial transmission is rendered as fully transmissive glass");
        }
        if m.volume().is_none() {
            // Blender writes no volume for its glass; its objects are solid all the same.
            sink.warn("transmissive materials without KHR_materials_volume are rendered as solid glass (refracting), not thin-walled");
        }
        MaterialSpec::Glass {
            ior: m.ior().unwrap_or(1.5),
            transmittance: base,
            alpha: roughness * roughness,
        }
    } else {
        let base_color = match pbr.base_color_texture() {
            Some(info) => ColorSpec::Decoded {
                texture: SharedTexture(texture(g, sink, &info, Encoding::Srgb)?),
                tint: base,
            },
            None => ColorSpec::Constant(base),
        };
        let metallic_roughness = match pbr.metallic_roughness_texture() {
            Some(info) => Some(ImageRef::Decoded(SharedTexture(texture(
                g,
                sink,
                &info,
                Encoding::Linear,
            )?))),
            None => None,
        };
        let normal_map = match m.normal_texture() {
            Some(n) => {
                if n.tex_coord() != 0 {
                    sink.warn("textures on texture coordinate sets other than 0 use set 0");
                }
                let t = texture_of(g, sink, &n.texture(), Encoding::Linear)?;
                Some((ImageRef::Decoded(SharedTexture(t)), n.scale()))
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
        })
    };
    let emitted = Rgb::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
    // An emissive texture multiplies the factor (sRGB, as the spec defines it): the surface
    // becomes an area light whose radiance varies with it.
    let emissive_texture = match m.emissive_texture() {
        Some(info) if emitted.max_element() > 0.0 => Some(ImageRef::Decoded(SharedTexture(
            texture(g, sink, &info, Encoding::Srgb)?,
        ))),
        _ => None,
    };
    let emission = (emitted.max_element() > 0.0).then_some(EmissionSpec::Radiance {
        radiance: emitted,
        two_sided: m.double_sided(),
        texture: emissive_texture,
    });
    Ok(ImportedMaterial {
        name,
        spec,
        emission,
    })
}

/// The texture of a texture-info (colour or metallic-roughness), warning about what is not
/// supported.
fn texture(
    g: &Opened,
    sink: &mut Sink,
    info: &gltf::texture::Info,
    encoding: Encoding,
) -> Result<Arc<ImageTexture>> {
    if info.tex_coord() != 0 {
        sink.warn("textures on texture coordinate sets other than 0 use set 0");
    }
    texture_of(g, sink, &info.texture(), encoding)
}

fn texture_of(
    g: &Opened,
    sink: &mut Sink,
    t: &gltf::Texture,
    encoding: Encoding,
) -> Result<Arc<ImageTexture>> {
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
    let decoded = Arc::new(crate::io::texture::decode_texture_as(
        &bytes, &label, encoding,
    )?);
    sink.textures.insert(key, decoded.clone());
    Ok(decoded)
}
