//! glTF metallic-roughness materials onto ours, and their base-colour textures.

use super::{Opened, Sink, read_uri};
use crate::description::mesh::ImportedMaterial;
use crate::description::{ColorSpec, EmissionSpec, MaterialSpec, SharedTexture};
use crate::error::Result;
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
    let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
    if m.alpha_mode() != gltf::material::AlphaMode::Opaque {
        sink.warn("alpha blending and masking are ignored (surfaces are opaque)");
    }
    if m.normal_texture().is_some() || m.occlusion_texture().is_some() {
        sink.warn("normal and occlusion maps are ignored");
    }
    if pbr.metallic_roughness_texture().is_some() {
        sink.warn("metallic-roughness textures are ignored (their factors are used)");
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
            sink.warn("partial transmission is rendered as fully transparent glass");
        }
        MaterialSpec::Glass {
            ior: m.ior().unwrap_or(1.5),
            transmittance: base,
        }
    } else if metallic >= 0.5 && roughness < 0.5 {
        if metallic < 1.0 || roughness > 0.0 {
            sink.warn(
                "glossy metals (metallic ≥ 0.5, roughness < 0.5) are rendered as perfect mirrors",
            );
        }
        MaterialSpec::Mirror { reflectance: base }
    } else {
        if metallic > 0.0 {
            sink.warn(
                "rough or partly metallic surfaces are rendered as diffuse with their base colour",
            );
        }
        let albedo = match pbr.base_color_texture() {
            Some(info) => {
                if info.tex_coord() != 0 {
                    sink.warn("textures on texture coordinate sets other than 0 use set 0");
                }
                ColorSpec::Decoded {
                    texture: SharedTexture(texture(g, sink, &info.texture())?),
                    tint: base,
                }
            }
            None => ColorSpec::Constant(base),
        };
        MaterialSpec::Diffuse { albedo }
    };
    let emitted = Rgb::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
    if m.emissive_texture().is_some() {
        sink.warn("emissive textures are ignored (the emissive factor is used)");
    }
    let emission = (emitted.max_element() > 0.0).then_some(EmissionSpec::Radiance {
        radiance: emitted,
        two_sided: m.double_sided(),
    });
    Ok(ImportedMaterial {
        name,
        spec,
        emission,
    })
}

fn texture(g: &Opened, sink: &mut Sink, t: &gltf::Texture) -> Result<Arc<ImageTexture>> {
    let image = t.source();
    if let Some(done) = sink.textures.get(&image.index()) {
        return Ok(done.clone());
    }
    let label = g.path.join(format!("images[{}]", image.index()));
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
    let decoded = Arc::new(crate::io::texture::decode_texture(&bytes, &label)?);
    sink.textures.insert(image.index(), decoded.clone());
    Ok(decoded)
}
