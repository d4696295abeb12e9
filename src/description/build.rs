//! From a [`SceneDesc`] to a renderable [`Scene`]: materials and textures, shapes and their
//! transforms, mesh files, lights given by power or radiance.

use super::mesh::{self, ImportedMaterial};
use super::source::{Diagnostic, Item};
use super::{
    ColorSpec, ConductorSpec, EmissionSpec, EnvironmentSpec, ImageRef, Intensity, LightSpec,
    LightSpectrum, MaterialSpec, MediaSides, SceneDesc, ShapeKind, ShapeSpec, Sky, compose,
};
use crate::camera::{Camera, CameraDesc};
use crate::error::{Error, Result};
use crate::geometry::{Disk, Shape, Sphere};
use crate::io::texture::Encoding;
use crate::light::{EnvironmentLight, SpotLight};
use crate::material::microfacet::Ggx;
use crate::material::{
    Conductor, ConductorFresnel, Dielectric, Dispersion, Lambertian, Material, Mirror, Pbr,
    RoughDielectric,
};
use crate::math::{Rgb, Vec3};
use crate::medium::{Boundary, GridMedium, HenyeyGreenstein, Homogeneous, MediumId, grid_file};
use crate::modeling::PolyMesh;
use crate::modeling::pot::{PotParams, pot};
use crate::scene::{Emission, Scene, SceneBuilder, TextureMaps, TriangleMesh};
use crate::spectrum::Spectrum;
use crate::texture::{Checker, MappedTexture, Texture, UvMapping};
use glam::Affine3A;
use std::collections::HashMap;
use std::f32::consts::PI;
use std::path::Path;
use std::sync::Arc;

pub use super::mesh::MeshCache;

/// Read a mesh file, choosing the reader by extension.
pub fn load_mesh_file(path: &Path) -> Result<mesh::MeshFile> {
    if !path.is_file() {
        return Err(Error::SceneFile(Box::new(Diagnostic::whole_file(
            path,
            "mesh file not found",
        ))));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("obj") => mesh::obj::read(path),
        Some("ply") => mesh::ply::read(path),
        Some("gltf" | "glb") => super::gltf::read_meshes(path),
        _ => Err(Error::SceneFile(Box::new(Diagnostic::whole_file(
            path,
            "unsupported mesh format; expected .obj, .ply, .gltf or .glb",
        )))),
    }
}

/// Build the scene a description describes, reading the files it names (relative to its
/// `base_dir`).
pub fn build(desc: &SceneDesc) -> Result<Scene> {
    build_with(desc, &mut MeshCache::new())
}

/// [`build`], taking mesh files from `cache` when they are there and adding those it reads.
pub fn build_with(desc: &SceneDesc, cache: &mut MeshCache) -> Result<Scene> {
    let mut b = SceneBuilder::new(&desc.name);
    let c = &desc.camera;
    let camera = CameraDesc {
        position: c.position,
        look_at: c.look_at,
        up: c.up,
        fov_y_deg: c.fov_y_deg,
    };
    if Camera::new(&camera, c.width, c.height).is_none() {
        let message = "the camera is degenerate (look-at equals position, up parallel to the view, or field of view outside (0°, 180°))";
        return Err(desc
            .origins
            .locate(Item::Camera, Error::InvalidScene(message.into())));
    }
    b.camera(camera, c.width, c.height);
    let mut ctx = Context {
        base_dir: &desc.base_dir,
        materials: HashMap::new(),
        black: None,
        imported: HashMap::new(),
        cache,
    };
    for (name, spec) in &desc.materials {
        let id = add_material(&mut b, spec, ctx.base_dir)?;
        ctx.materials.insert(name.clone(), id);
    }
    // The first builder object of each item, so that an object's error names its item.
    let mut first_objects: Vec<(usize, Item)> = Vec::new();
    let media = add_media(&mut b, desc)?;
    for (i, shape) in desc.shapes.iter().enumerate() {
        let first = b.object_count();
        first_objects.push((first, Item::Shape(i)));
        add_shape(&mut b, &mut ctx, shape).map_err(|e| desc.origins.locate(Item::Shape(i), e))?;
        if let Some(sides) = &shape.media {
            let boundary = media
                .boundary(sides, shape.is_invisible_boundary())
                .map_err(|e| desc.origins.locate(Item::Shape(i), e))?;
            b.bound_objects_from(first, boundary);
        }
    }
    for (i, light) in desc.lights.iter().enumerate() {
        first_objects.push((b.object_count(), Item::Light(i)));
        add_light(&mut b, &mut ctx, light).map_err(|e| desc.origins.locate(Item::Light(i), e))?;
    }
    b.build().map_err(|e| match e {
        Error::InvalidObject { index, .. } => {
            match first_objects
                .iter()
                .rev()
                .find(|(first, _)| *first <= index)
            {
                Some(&(_, item)) => desc.origins.locate(item, e),
                None => e,
            }
        }
        other => other,
    })
}

/// The scene's media by name, and the medium around its shapes.
struct Media<'a> {
    ids: HashMap<&'a str, MediumId>,
    atmosphere: Option<MediumId>,
}

impl Media<'_> {
    fn id(&self, name: &str) -> Result<MediumId> {
        self.ids
            .get(name)
            .copied()
            .ok_or_else(|| Error::InvalidScene(format!("medium '{name}' is not defined")))
    }

    /// What a shape with these sides separates; outside is the atmosphere unless named.
    fn boundary(&self, sides: &MediaSides, invisible: bool) -> Result<Boundary> {
        Ok(Boundary {
            inside: sides.interior.as_deref().map(|n| self.id(n)).transpose()?,
            outside: match &sides.exterior {
                Some(n) => Some(self.id(n)?),
                None => self.atmosphere,
            },
            invisible,
        })
    }
}

fn add_media<'a>(b: &mut SceneBuilder, desc: &'a SceneDesc) -> Result<Media<'a>> {
    let mut media = Media {
        ids: HashMap::new(),
        atmosphere: None,
    };
    for (name, m) in &desc.media {
        let phase = HenyeyGreenstein::new(m.g);
        let id = match &m.grid {
            None => b.medium(Homogeneous {
                sigma_a: m.sigma_a,
                sigma_s: m.sigma_s,
                phase,
            }),
            Some(g) => {
                let path = desc.base_dir.join(&g.file);
                let format = grid_file::GridFormat::of(&path)?;
                let bytes = crate::io::input::read_file(&path)?;
                let file = grid_file::parse(&path, format, &bytes, &g.name)?;
                let placement = super::compose(&g.transform) * file.unit_to_world;
                let medium = GridMedium::new(m.sigma_a, m.sigma_s, phase, file.grid, placement)
                    .map_err(|e| Error::InvalidScene(format!("medium '{name}': {e}")))?;
                b.medium(medium)
            }
        };
        media.ids.insert(name, id);
    }
    media.atmosphere = desc.medium.as_deref().map(|n| media.id(n)).transpose()?;
    b.atmosphere(media.atmosphere);
    Ok(media)
}

fn add_light(b: &mut SceneBuilder, ctx: &mut Context, light: &LightSpec) -> Result<()> {
    match light {
        LightSpec::Point {
            position,
            intensity,
            spectrum,
        } => {
            let i = match *intensity {
                Intensity::Intensity(i) => i,
                Intensity::Power(p) => p / (4.0 * PI),
            };
            b.point_light(*position, emitted(i, *spectrum));
        }
        LightSpec::Spot {
            position,
            look_at,
            intensity,
            angle_deg,
            falloff_deg,
            spectrum,
        } => {
            let reach = (*look_at - *position).length_squared();
            if reach.is_nan() || reach <= 0.0 {
                return Err(Error::InvalidScene(
                    "a spot light points nowhere: its look_at equals its position".into(),
                ));
            }
            let make_white = |i: Rgb| {
                SpotLight::new(
                    *position,
                    *look_at - *position,
                    Spectrum::illuminant(i),
                    *angle_deg,
                    *falloff_deg,
                )
            };
            let make = |i: Rgb| {
                SpotLight::new(
                    *position,
                    *look_at - *position,
                    emitted(i, *spectrum),
                    *angle_deg,
                    *falloff_deg,
                )
            };
            let i = match *intensity {
                Intensity::Intensity(i) => i,
                // Power is linear in intensity: scale a unit light's power (as white: a
                // spectrum's brightness is its luminance, like white's).
                Intensity::Power(p) => p / make_white(Rgb::ONE).power().x,
            };
            b.spot_light(make(i));
        }
        LightSpec::Directional {
            direction,
            irradiance,
            spectrum,
        } => {
            b.directional_light(*direction, emitted(*irradiance, *spectrum));
        }
        LightSpec::Area(shape) => add_shape(b, ctx, shape)?,
        LightSpec::Environment(e) => {
            b.environment_light(environment_light(e, ctx.base_dir)?);
        }
    }
    Ok(())
}

struct Context<'a> {
    base_dir: &'a Path,
    materials: HashMap<String, u32>,
    /// The non-reflecting material of area lights that name none.
    black: Option<u32>,
    /// Materials read from mesh files, by file and material name.
    imported: HashMap<(std::path::PathBuf, String), u32>,
    cache: &'a mut MeshCache,
}

impl Context<'_> {
    fn material(
        &mut self,
        b: &mut SceneBuilder,
        name: Option<&str>,
        emissive: bool,
    ) -> Result<u32> {
        match name {
            Some(n) => self
                .materials
                .get(n)
                .copied()
                .ok_or_else(|| Error::InvalidScene(format!("material '{n}' is not defined"))),
            None if emissive => Ok(*self.black.get_or_insert_with(|| {
                b.material(Material::Lambertian(Lambertian { albedo: Rgb::ZERO }))
            })),
            None => Err(Error::InvalidScene("a shape has no material".into())),
        }
    }
}

fn add_material(b: &mut SceneBuilder, spec: &MaterialSpec, base_dir: &Path) -> Result<u32> {
    Ok(match spec {
        MaterialSpec::Diffuse { albedo } => {
            let (constant, texture) = color(albedo, base_dir)?;
            let m = Material::Lambertian(Lambertian { albedo: constant });
            match texture {
                Some(t) => b.material_with_maps(
                    m,
                    TextureMaps {
                        base: Some(t),
                        ..TextureMaps::default()
                    },
                )?,
                None => b.material(m),
            }
        }
        MaterialSpec::Mirror { reflectance } => b.material(Material::Mirror(Mirror {
            reflectance: *reflectance,
        })),
        MaterialSpec::Glass {
            ior,
            transmittance,
            alpha,
            attenuation,
            dispersion,
        } => b.material_with_maps(
            if *alpha > 0.0 {
                Material::RoughDielectric(RoughDielectric::new(
                    *ior,
                    Ggx::isotropic(*alpha),
                    *transmittance,
                ))
            } else {
                Material::Dielectric(Dielectric::new(*ior, *transmittance))
            },
            TextureMaps {
                attenuation: *attenuation,
                dispersion: *dispersion,
                ..TextureMaps::default()
            },
        )?,
        MaterialSpec::Conductor { fresnel, alpha } => {
            let fresnel = match *fresnel {
                ConductorSpec::Metal(m) => {
                    let (eta, k) = m.ior();
                    ConductorFresnel::Complex { eta, k }
                }
                ConductorSpec::Ior { eta, k } => ConductorFresnel::Complex { eta, k },
                ConductorSpec::F0(f0) => ConductorFresnel::Schlick { f0 },
            };
            b.material(Material::Conductor(Conductor {
                ggx: Ggx {
                    alpha_x: alpha[0],
                    alpha_y: alpha[1],
                },
                fresnel,
            }))
        }
        MaterialSpec::Pbr(p) => {
            let (base, texture) = color(&p.base_color, base_dir)?;
            let data = |t: &ImageRef| -> Result<MappedTexture> {
                Ok(match t {
                    ImageRef::File(f) => Texture::Image(crate::io::texture::read_texture_as(
                        &base_dir.join(f),
                        Encoding::Linear,
                    )?)
                    .into(),
                    ImageRef::Decoded(d) => MappedTexture {
                        texture: Texture::Image(d.image.clone()),
                        mapping: d.mapping,
                    },
                })
            };
            let maps = TextureMaps {
                base: texture,
                metallic_roughness: p.metallic_roughness.as_ref().map(data).transpose()?,
                normal: match &p.normal_map {
                    Some((t, scale)) => Some((data(t)?, *scale)),
                    None => None,
                },
                coverage: p.coverage,
                attenuation: None,
                dispersion: Dispersion::None,
            };
            let pbr = Pbr::new(base, p.metallic, p.roughness).with_specular(p.specular);
            b.material_with_maps(Material::Pbr(pbr), maps)?
        }
    })
}

/// A colour spec as a constant and an optional texture that multiplies it.
fn color(spec: &ColorSpec, base_dir: &Path) -> Result<(Rgb, Option<MappedTexture>)> {
    Ok(match spec {
        ColorSpec::Constant(c) => (*c, None),
        ColorSpec::Image { file, tint } => {
            let t = crate::io::texture::read_texture(&base_dir.join(file))?;
            (*tint, Some(Texture::Image(t).into()))
        }
        ColorSpec::Decoded { texture, tint } => (
            *tint,
            Some(MappedTexture {
                texture: Texture::Image(texture.image.clone()),
                mapping: texture.mapping,
            }),
        ),
        ColorSpec::Checker { even, odd, scale } => (
            Rgb::ONE,
            Some(
                Texture::Checker(Checker {
                    even: *even,
                    odd: *odd,
                    scale: *scale,
                })
                .into(),
            ),
        ),
    })
}

/// The environment light of a spec, reading its image.
fn environment_light(e: &EnvironmentSpec, base_dir: &Path) -> Result<EnvironmentLight> {
    Ok(match &e.sky {
        Sky::Uniform(r) => EnvironmentLight::uniform(*r * e.intensity),
        Sky::File(f) => EnvironmentLight::image(
            crate::io::image::read_environment(&base_dir.join(f))?,
            Rgb::splat(e.intensity),
            e.rotate_deg,
        ),
    })
}

/// Emitted light of RGB colour `rgb`, or of `spectrum` with brightness `rgb` (then grey).
fn emitted(rgb: Rgb, spectrum: Option<LightSpectrum>) -> Spectrum {
    match spectrum {
        None => Spectrum::illuminant(rgb),
        Some(s) => s.spectrum(rgb.x),
    }
}

/// Radiance of an emission spec over a surface of world-space `area`.
fn radiance(e: &EmissionSpec, area: f32, base_dir: &Path) -> Result<Emission> {
    Ok(match e {
        EmissionSpec::Radiance {
            radiance,
            two_sided,
            texture,
            spectrum,
        } => {
            let (texture, texture_mapping) = match texture {
                None => (None, UvMapping::IDENTITY),
                Some(ImageRef::File(f)) => (
                    Some(crate::io::texture::read_texture(&base_dir.join(f))?),
                    UvMapping::IDENTITY,
                ),
                Some(ImageRef::Decoded(t)) => (Some(t.image.clone()), t.mapping),
            };
            Emission {
                radiance: emitted(*radiance, *spectrum),
                two_sided: *two_sided,
                texture,
                texture_mapping,
            }
        }
        EmissionSpec::Power {
            power,
            two_sided,
            spectrum,
        } => {
            if area.is_nan() || area <= 0.0 {
                return Err(Error::InvalidScene(
                    "an emitter given by its power has no area".into(),
                ));
            }
            // Φ = L · π · A per lit side (Lambertian emitter).
            let sides = if *two_sided { 2.0 } else { 1.0 };
            Emission {
                radiance: emitted(*power / (sides * PI * area), *spectrum),
                two_sided: *two_sided,
                texture: None,
                texture_mapping: UvMapping::IDENTITY,
            }
        }
    })
}

fn mesh_area(mesh: &TriangleMesh, m: &Affine3A) -> f32 {
    let p: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|&p| m.transform_point3(p))
        .collect();
    mesh.triangles
        .iter()
        .filter(|t| t.iter().all(|&i| (i as usize) < p.len()))
        .map(|t| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

fn quad_mesh(quads: &[[Vec3; 4]]) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for q in quads {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend_from_slice(q);
        mesh.triangles.push([base, base + 1, base + 2]);
        mesh.triangles.push([base, base + 2, base + 3]);
    }
    mesh
}

fn box_quads(min: Vec3, max: Vec3) -> Vec<[Vec3; 4]> {
    let c = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { max.x } else { min.x },
            if y { max.y } else { min.y },
            if z { max.z } else { min.z },
        )
    };
    let (f, t) = (false, true);
    // Counter-clockwise seen from outside.
    vec![
        [c(f, f, f), c(f, t, f), c(t, t, f), c(t, f, f)], // −z
        [c(f, f, t), c(t, f, t), c(t, t, t), c(f, t, t)], // +z
        [c(f, f, f), c(t, f, f), c(t, f, t), c(f, f, t)], // −y
        [c(f, t, f), c(f, t, t), c(t, t, t), c(t, t, f)], // +y
        [c(f, f, f), c(f, f, t), c(f, t, t), c(f, t, f)], // −x
        [c(t, f, f), c(t, t, f), c(t, t, t), c(t, f, t)], // +x
    ]
}

fn add_shape(b: &mut SceneBuilder, ctx: &mut Context, s: &ShapeSpec) -> Result<()> {
    let m = compose(&s.transform);
    let emissive = s.emission.is_some() || s.is_invisible_boundary();
    match &s.kind {
        ShapeKind::Sphere { center, radius } => {
            let shape = Shape::Sphere(Sphere {
                center: *center,
                radius: *radius,
            });
            analytic(b, ctx, s, shape, &m)
        }
        ShapeKind::Disk {
            center,
            normal,
            radius,
        } => {
            let shape = Shape::Disk(Disk {
                center: *center,
                normal: normal.normalize_or(Vec3::Z),
                radius: *radius,
            });
            analytic(b, ctx, s, shape, &m)
        }
        ShapeKind::Quad { vertices } => {
            let material = ctx.material(b, s.material.as_deref(), emissive)?;
            let world = vertices.map(|v| m.transform_point3(v));
            let emission = match &s.emission {
                Some(e) => Some(radiance(
                    e,
                    mesh_area(&quad_mesh(&[world]), &Affine3A::IDENTITY),
                    ctx.base_dir,
                )?),
                None => None,
            };
            b.quad(world, material, emission);
            Ok(())
        }
        ShapeKind::Box { min, max } => {
            let mesh = quad_mesh(&box_quads(*min, *max));
            add_mesh(b, ctx, s, &mesh, &m)
        }
        ShapeKind::Triangles(mesh) => add_mesh(b, ctx, s, mesh, &m),
        ShapeKind::MeshFile { file, smooth } => add_mesh_file(b, ctx, s, file, *smooth, &m),
        ShapeKind::Pot {
            subdivisions,
            seed,
            soil_material,
            leaf_material,
        } => {
            let params = PotParams {
                subdivisions: *subdivisions,
                seed: *seed,
            };
            let soil = soil_material.as_deref().or(s.material.as_deref());
            let leaf = leaf_material.as_deref().or(s.material.as_deref());
            add_pot(b, ctx, &params, [s.material.as_deref(), soil, leaf], &m)
        }
    }
}

/// Every part of a mesh file, with the shape's material (and emission) or the file's own.
fn add_mesh_file(
    b: &mut SceneBuilder,
    ctx: &mut Context,
    s: &ShapeSpec,
    file: &Path,
    smooth: bool,
    m: &Affine3A,
) -> Result<()> {
    let path = ctx.base_dir.join(file);
    let file = match ctx.cache.get(&path) {
        Some(f) => f.clone(),
        None => {
            let f = Arc::new(load_mesh_file(&path)?);
            ctx.cache.insert(path.clone(), f.clone());
            f
        }
    };
    for part in &file.parts {
        let flat;
        let mesh = if smooth || part.mesh.normals.is_empty() {
            &part.mesh
        } else {
            flat = TriangleMesh {
                normals: Vec::new(),
                ..part.mesh.clone()
            };
            &flat
        };
        let (material, emission) = match (&s.material, &part.material) {
            _ if s.is_invisible_boundary() => (ctx.material(b, None, true)?, None),
            (None, None) if s.emission.is_none() => {
                return Err(Error::SceneFile(Box::new(Diagnostic::whole_file(
                    &path,
                    format!(
                        "part '{}' has no material of its own; give the shape a `material`",
                        part.name
                    ),
                ))));
            }
            (Some(_), _) | (None, None) => (
                ctx.material(
                    b,
                    s.material.as_deref(),
                    s.emission.is_some() || s.is_invisible_boundary(),
                )?,
                s.emission.clone(),
            ),
            (None, Some(im)) => (
                imported(b, ctx, &path, im)?,
                s.emission.clone().or_else(|| im.emission.clone()),
            ),
        };
        let emission = match &emission {
            Some(e) => Some(radiance(e, mesh_area(mesh, m), ctx.base_dir)?),
            None => None,
        };
        b.triangle_mesh(mesh, *m, material, emission)?;
    }
    Ok(())
}

/// The pot's body, soil disc and leaves with materials `[body, soil, leaves]`.
fn add_pot(
    b: &mut SceneBuilder,
    ctx: &mut Context,
    params: &PotParams,
    materials: [Option<&str>; 3],
    m: &Affine3A,
) -> Result<()> {
    let model = pot(params);
    let [clay, soil, leaf] = materials.map(|name| ctx.material(b, name, false));
    let (clay, soil, leaf) = (clay?, soil?, leaf?);
    b.triangle_mesh(&smooth_mesh(&model.body), *m, clay, None)?;
    let soil_disk = Shape::Disk(Disk {
        center: model.soil_center.as_vec3(),
        normal: Vec3::Z,
        radius: model.soil_radius as f32,
    });
    b.object_transformed(&[soil_disk], *m, soil, None)?;
    for leaf_mesh in &model.leaves {
        b.triangle_mesh(&smooth_mesh(leaf_mesh), *m, leaf, None)?;
    }
    Ok(())
}

fn smooth_mesh(mesh: &PolyMesh) -> TriangleMesh {
    TriangleMesh {
        positions: mesh.positions.iter().map(|p| p.as_vec3()).collect(),
        normals: mesh.vertex_normals().iter().map(|n| n.as_vec3()).collect(),
        uvs: Vec::new(),
        second_uvs: Vec::new(),
        tangents: Vec::new(),
        triangles: mesh.triangles(),
    }
}

fn analytic(
    b: &mut SceneBuilder,
    ctx: &mut Context,
    s: &ShapeSpec,
    shape: Shape,
    m: &Affine3A,
) -> Result<()> {
    let material = ctx.material(
        b,
        s.material.as_deref(),
        s.emission.is_some() || s.is_invisible_boundary(),
    )?;
    let world = shape
        .transformed(m)
        .map_err(|e| Error::InvalidScene(e.to_owned()))?;
    let emission = match &s.emission {
        Some(e) => Some(radiance(e, world.area(), ctx.base_dir)?),
        None => None,
    };
    // Already in world space: the identity keeps the analytic shape bit-exact.
    b.object_transformed(&[world], Affine3A::IDENTITY, material, emission)?;
    Ok(())
}

fn add_mesh(
    b: &mut SceneBuilder,
    ctx: &mut Context,
    s: &ShapeSpec,
    mesh: &TriangleMesh,
    m: &Affine3A,
) -> Result<()> {
    let material = ctx.material(
        b,
        s.material.as_deref(),
        s.emission.is_some() || s.is_invisible_boundary(),
    )?;
    let emission = match &s.emission {
        Some(e) => Some(radiance(e, mesh_area(mesh, m), ctx.base_dir)?),
        None => None,
    };
    b.triangle_mesh(mesh, *m, material, emission)?;
    Ok(())
}

/// The scene material for a material read from a mesh file (added once per file and name).
fn imported(
    b: &mut SceneBuilder,
    ctx: &mut Context,
    file: &Path,
    im: &ImportedMaterial,
) -> Result<u32> {
    let key = (file.to_owned(), im.name.clone());
    if let Some(&id) = ctx.imported.get(&key) {
        return Ok(id);
    }
    let dir = file.parent().unwrap_or(Path::new(""));
    let id = add_material(b, &im.spec, dir).map_err(|e| match e {
        Error::Read { path, source } => Error::SceneFile(Box::new(Diagnostic::whole_file(
            file,
            format!(
                "material '{}' uses texture '{}', which cannot be read: {source}",
                im.name,
                path.display()
            ),
        ))),
        other => other,
    })?;
    ctx.imported.insert(key, id);
    Ok(id)
}
