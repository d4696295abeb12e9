use super::{Coverage, MaterialMaps, NO_LIGHT, Scene, TriangleMesh};
use crate::accel::RayEngine;
use crate::camera::{Camera, CameraDesc};
use crate::error::{Error, Result};
use crate::geometry::{Disk, Shape, Sphere, Triangle};
use crate::light::{AreaLight, DirectionalLight, EnvironmentLight, Light, PointLight, SpotLight};
use crate::material::{Attenuation, Dispersion, Material};
use crate::math::{Rgb, Vec2, Vec3};
use crate::medium::{Boundary, Medium, MediumId};
use crate::sampling::AliasTable;
use crate::spectrum::Spectrum;
use crate::texture::{MappedTexture, Texture, UvMapping};
use glam::Affine3A;
use std::sync::Arc;

/// Largest coordinate magnitude a shape may reach: the BVH squares extents, and at 1e19 it
/// overflowed and panicked.
pub const MAX_COORDINATE: f32 = 1e15;

/// Light emitted by an object's surface: radiance (W·m⁻²·sr⁻¹), times an sRGB texture
/// looked up at the object's texture coordinates where there is one; one- or two-sided.
#[derive(Clone, Debug)]
pub struct Emission {
    pub radiance: Spectrum,
    pub two_sided: bool,
    pub texture: Option<Arc<crate::texture::ImageTexture>>,
    /// How `texture` is read (coordinate set, transform, wrap).
    pub texture_mapping: UvMapping,
}

struct Object {
    shapes: Vec<Shape>,
    /// Per-vertex shading normals of each triangle (smooth meshes), parallel to `shapes`.
    normals: Option<Vec<[Vec3; 3]>>,
    /// Per-vertex texture coordinates of each triangle, parallel to `shapes`.
    uvs: Option<Vec<[Vec2; 3]>>,
    /// The second coordinate set of each triangle, parallel to `shapes`.
    second_uvs: Option<Vec<[Vec2; 3]>>,
    /// Per-vertex tangents of each triangle (world space, w the bitangent's sign).
    tangents: Option<Vec<[glam::Vec4; 3]>>,
    material: u32,
    emission: Option<Emission>,
    /// The media this object separates, if it is a boundary.
    boundary: Option<Boundary>,
}

/// The textures a material may carry (see [`SceneBuilder::material_with_maps`]), each with
/// its own mapping, the material's coverage, and the absorption inside a dielectric.
#[derive(Clone, Debug, Default)]
pub struct TextureMaps {
    /// Multiplies the albedo or base colour (sRGB-decoded); its alpha is the coverage's.
    pub base: Option<MappedTexture>,
    /// glTF's packing, linear: blue multiplies metallic, green roughness.
    pub metallic_roughness: Option<MappedTexture>,
    /// Tangent-space normals (linear, 2·value − 1) and the scale of their x and y.
    pub normal: Option<(MappedTexture, f32)>,
    /// Where the surface is there at all (cut-outs, partly transparent surfaces).
    pub coverage: Coverage,
    /// Beer–Lambert absorption in the volume a dielectric encloses (`None`: clear).
    pub attenuation: Option<Attenuation>,
    /// How a dielectric's index varies with wavelength (spectral rendering; RGB rendering
    /// uses the material's `ior`, which should be the index at the d line).
    pub dispersion: Dispersion,
}

/// Collects objects, materials and lights, then validates them into a [`Scene`].
pub struct SceneBuilder {
    name: String,
    materials: Vec<Material>,
    material_textures: Vec<MaterialMaps>,
    textures: Vec<MappedTexture>,
    objects: Vec<Object>,
    lights: Vec<Light>,
    camera: Option<CameraDesc>,
    resolution: (u32, u32),
    ray_engine: RayEngine,
    media: Vec<Medium>,
    atmosphere: Option<MediumId>,
}

impl SceneBuilder {
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_owned(),
            materials: Vec::new(),
            material_textures: Vec::new(),
            textures: Vec::new(),
            objects: Vec::new(),
            lights: Vec::new(),
            camera: None,
            resolution: (512, 512),
            ray_engine: RayEngine::Best,
            media: Vec::new(),
            atmosphere: None,
        }
    }

    /// Add a participating medium; returns its id for boundaries and the atmosphere.
    pub fn medium(&mut self, m: impl Into<Medium>) -> MediumId {
        self.media.push(m.into());
        (self.media.len() - 1) as MediumId
    }

    /// The medium around every shape, where the camera and the lights are (vacuum unless set).
    pub fn atmosphere(&mut self, m: Option<MediumId>) -> &mut Self {
        self.atmosphere = m;
        self
    }

    /// Make the objects added since `first` (see [`SceneBuilder::object_count`]) a boundary
    /// between media.
    pub fn bound_objects_from(&mut self, first: usize, boundary: Boundary) -> &mut Self {
        for o in self.objects.iter_mut().skip(first) {
            o.boundary = Some(boundary);
        }
        self
    }

    /// The ray caster to build (the best compiled in unless set). Building with
    /// [`RayEngine::Embree`] fails when the `embree` feature is not compiled in.
    pub fn ray_engine(&mut self, engine: RayEngine) -> &mut Self {
        self.ray_engine = engine;
        self
    }

    /// How many objects have been added: the index the next one will have in errors.
    pub fn object_count(&self) -> usize {
        self.objects.len()
    }

    pub fn camera(&mut self, camera: CameraDesc, width: u32, height: u32) -> &mut Self {
        self.camera = Some(camera);
        self.resolution = (width, height);
        self
    }

    pub fn material(&mut self, m: Material) -> u32 {
        self.materials.push(m);
        self.material_textures.push(MaterialMaps::default());
        (self.materials.len() - 1) as u32
    }

    /// A material whose albedo (diffuse) or base colour (pbr) is multiplied by `texture` at
    /// each hit's (u, v).
    pub fn textured_material(&mut self, m: Material, texture: Texture) -> Result<u32> {
        self.material_with_maps(
            m,
            TextureMaps {
                base: Some(texture.into()),
                ..TextureMaps::default()
            },
        )
    }

    /// A material with textures: a base colour (diffuse and pbr), a metallic-roughness map and
    /// a tangent-space normal map (pbr).
    pub fn material_with_maps(&mut self, m: Material, maps: TextureMaps) -> Result<u32> {
        let is_pbr = matches!(m, Material::Pbr(_));
        if maps.base.is_some() && !(is_pbr || matches!(m, Material::Lambertian(_))) {
            return Err(Error::InvalidScene(
                "only diffuse and pbr materials take a colour texture".into(),
            ));
        }
        if (maps.metallic_roughness.is_some() || maps.normal.is_some()) && !is_pbr {
            return Err(Error::InvalidScene(
                "only pbr materials take metallic-roughness and normal maps".into(),
            ));
        }
        if let Coverage::Mask { alpha, cutoff } = maps.coverage
            && !(alpha.is_finite() && cutoff.is_finite())
        {
            return Err(Error::InvalidScene(format!(
                "a material's alpha {alpha} and cutoff {cutoff} must be finite"
            )));
        }
        if let Coverage::Blend { alpha } = maps.coverage
            && !alpha.is_finite()
        {
            return Err(Error::InvalidScene(format!(
                "a material's alpha {alpha} must be finite"
            )));
        }
        if let Some(a) = maps.attenuation {
            if !m.encloses_volume() {
                return Err(Error::InvalidScene(
                    "only glass (dielectric) materials absorb inside".into(),
                ));
            }
            // Absorption only removes light: a colour above 1 would add it.
            let c = a.color;
            if !(c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0)
                || a.distance.is_nan()
                || a.distance <= 0.0
            {
                return Err(Error::InvalidScene(format!(
                    "a glass's attenuation colour {:?} must be in [0, 1] and its distance {} positive",
                    c.to_array(),
                    a.distance
                )));
            }
        }
        if maps.dispersion.is_dispersive() {
            if !m.encloses_volume() {
                return Err(Error::InvalidScene(
                    "only glass (dielectric) materials disperse".into(),
                ));
            }
            if !maps.dispersion.is_valid() {
                return Err(Error::InvalidScene(format!(
                    "a glass's dispersion {:?} must give an index between 1 and 5 from 360 to 830 nm",
                    maps.dispersion
                )));
            }
        }
        let mut push = |t: Option<MappedTexture>| {
            t.map(|t| {
                self.textures.push(t);
                (self.textures.len() - 1) as u32
            })
        };
        let normal_scale = maps.normal.as_ref().map_or(1.0, |n| n.1);
        let ids = MaterialMaps {
            base: push(maps.base),
            metallic_roughness: push(maps.metallic_roughness),
            normal: push(maps.normal.map(|n| n.0)),
            normal_scale,
            coverage: maps.coverage,
            attenuation: maps.attenuation,
            dispersion: maps.dispersion,
        };
        self.materials.push(m);
        self.material_textures.push(ids);
        Ok((self.materials.len() - 1) as u32)
    }

    fn push_object(&mut self, shapes: Vec<Shape>, material: u32, emission: Option<Emission>) {
        self.objects.push(Object {
            shapes,
            normals: None,
            uvs: None,
            second_uvs: None,
            tangents: None,
            material,
            emission,
            boundary: None,
        });
    }

    /// Any shapes given in object space, placed by `transform` (object to world).
    pub fn object_transformed(
        &mut self,
        shapes: &[Shape],
        transform: Affine3A,
        material: u32,
        emission: Option<Emission>,
    ) -> Result<&mut Self> {
        let world = shapes
            .iter()
            .map(|s| s.transformed(&transform))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| Error::InvalidObject {
                index: self.objects.len(),
                message: format!("cannot take its transform: {e}"),
            })?;
        self.push_object(world, material, emission);
        Ok(self)
    }

    /// A smooth triangle mesh: like [`SceneBuilder::mesh`], with one shading normal per vertex,
    /// interpolated across each triangle.
    pub fn smooth_mesh(
        &mut self,
        positions: &[Vec3],
        normals: &[Vec3],
        triangles: &[[u32; 3]],
        transform: Affine3A,
        material: u32,
    ) -> Result<&mut Self> {
        let mesh = TriangleMesh {
            positions: positions.to_vec(),
            normals: normals.to_vec(),
            uvs: Vec::new(),
            second_uvs: Vec::new(),
            tangents: Vec::new(),
            triangles: triangles.to_vec(),
        };
        self.triangle_mesh(&mesh, transform, material, None)
    }

    /// A flat-shaded triangle mesh; `transform` maps object space to world space.
    pub fn mesh(
        &mut self,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        transform: Affine3A,
        material: u32,
        emission: Option<Emission>,
    ) -> Result<&mut Self> {
        let mesh = TriangleMesh {
            positions: positions.to_vec(),
            normals: Vec::new(),
            uvs: Vec::new(),
            second_uvs: Vec::new(),
            tangents: Vec::new(),
            triangles: triangles.to_vec(),
        };
        self.triangle_mesh(&mesh, transform, material, emission)
    }

    /// A triangle mesh with optional per-vertex shading normals and texture coordinates;
    /// `transform` maps object space to world space. Degenerate triangles are dropped: they can
    /// never be hit and have no area to emit from.
    pub fn triangle_mesh(
        &mut self,
        mesh: &TriangleMesh,
        transform: Affine3A,
        material: u32,
        emission: Option<Emission>,
    ) -> Result<&mut Self> {
        let n = mesh.positions.len();
        for (what, len) in [
            ("normals", mesh.normals.len()),
            ("uvs", mesh.uvs.len()),
            ("second uvs", mesh.second_uvs.len()),
            ("tangents", mesh.tangents.len()),
        ] {
            if len != 0 && len != n {
                return Err(Error::InvalidScene(format!(
                    "a mesh has {len} {what} for {n} vertices"
                )));
            }
        }
        let world: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|&p| transform.transform_point3(p))
            .collect();
        let normal_matrix = transform.matrix3.inverse().transpose();
        let world_normals: Vec<Vec3> = mesh
            .normals
            .iter()
            .map(|&v| Vec3::from(normal_matrix * glam::Vec3A::from(v)).normalize_or_zero())
            .collect();
        // Tangents turn with the surface; a mirroring transform flips the bitangent's sign.
        let flip = if transform.matrix3.determinant() < 0.0 {
            -1.0
        } else {
            1.0
        };
        let world_tangents: Vec<glam::Vec4> = mesh
            .tangents
            .iter()
            .map(|t| {
                let v = Vec3::from(transform.matrix3 * glam::Vec3A::from(t.truncate()));
                v.normalize_or_zero()
                    .extend(if t.w < 0.0 { -flip } else { flip })
            })
            .collect();
        let mut shapes = Vec::with_capacity(mesh.triangles.len());
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        let mut second_uvs = Vec::new();
        let mut tangents = Vec::new();
        for (k, t) in mesh.triangles.iter().enumerate() {
            if let Some(&i) = t.iter().find(|&&i| i as usize >= n) {
                return Err(Error::InvalidScene(format!(
                    "triangle {k} uses vertex {i}, but the mesh has {n} vertices"
                )));
            }
            let [a, b, c] = t.map(|i| world[i as usize]);
            if !(a.is_finite() && b.is_finite() && c.is_finite()) {
                // Its area is NaN, and it was dropped as degenerate without a word.
                return Err(Error::InvalidScene(format!(
                    "triangle {k} of a mesh has a non-finite vertex ({a}, {b}, {c})"
                )));
            }
            let tri = Triangle::new(a, b, c);
            if tri.area() > 0.0 {
                shapes.push(Shape::Triangle(tri));
                if !world_normals.is_empty() {
                    normals.push(t.map(|i| world_normals[i as usize]));
                }
                if !mesh.uvs.is_empty() {
                    uvs.push(t.map(|i| mesh.uvs[i as usize]));
                }
                if !mesh.second_uvs.is_empty() {
                    second_uvs.push(t.map(|i| mesh.second_uvs[i as usize]));
                }
                if !world_tangents.is_empty() {
                    tangents.push(t.map(|i| world_tangents[i as usize]));
                }
            }
        }
        self.objects.push(Object {
            shapes,
            normals: (!normals.is_empty()).then_some(normals),
            uvs: (!uvs.is_empty()).then_some(uvs),
            second_uvs: (!second_uvs.is_empty()).then_some(second_uvs),
            tangents: (!tangents.is_empty()).then_some(tangents),
            material,
            emission,
            boundary: None,
        });
        Ok(self)
    }

    /// A planar quad `v0 v1 v2 v3`, split as (v0, v1, v2) and (v0, v2, v3). Its front side is the
    /// one from which the vertices run counter-clockwise.
    pub fn quad(&mut self, v: [Vec3; 4], material: u32, emission: Option<Emission>) -> &mut Self {
        let shapes = [
            Triangle::new(v[0], v[1], v[2]),
            Triangle::new(v[0], v[2], v[3]),
        ]
        .into_iter()
        .filter(|t| t.area() > 0.0)
        .map(Shape::Triangle)
        .collect::<Vec<_>>();
        let uv = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        let uvs = [[uv[0], uv[1], uv[2]], [uv[0], uv[2], uv[3]]];
        // Keep the texture coordinates of the triangles the degenerate filter kept.
        let uvs = if shapes.len() == 2 {
            uvs.to_vec()
        } else {
            Vec::new()
        };
        self.objects.push(Object {
            shapes,
            normals: None,
            uvs: (!uvs.is_empty()).then_some(uvs),
            second_uvs: None,
            tangents: None,
            material,
            emission,
            boundary: None,
        });
        self
    }

    pub fn sphere(
        &mut self,
        center: Vec3,
        radius: f32,
        material: u32,
        emission: Option<Emission>,
    ) -> &mut Self {
        self.push_object(
            vec![Shape::Sphere(Sphere { center, radius })],
            material,
            emission,
        );
        self
    }

    pub fn disk(
        &mut self,
        center: Vec3,
        normal: Vec3,
        radius: f32,
        material: u32,
        emission: Option<Emission>,
    ) -> &mut Self {
        let normal = normal.normalize();
        self.push_object(
            vec![Shape::Disk(Disk {
                center,
                normal,
                radius,
            })],
            material,
            emission,
        );
        self
    }

    pub fn point_light(&mut self, position: Vec3, intensity: Spectrum) -> &mut Self {
        self.lights.push(Light::Point(PointLight {
            position,
            intensity,
        }));
        self
    }

    /// Light from one direction; its power is set from the scene's bounding sphere at build.
    pub fn directional_light(&mut self, direction: Vec3, irradiance: Spectrum) -> &mut Self {
        self.lights.push(Light::Directional(DirectionalLight::new(
            direction, irradiance,
        )));
        self
    }

    /// Light from every direction; its power is set from the scene's bounding sphere at build.
    /// A scene has at most one (a second replaces the first).
    pub fn environment_light(&mut self, light: EnvironmentLight) -> &mut Self {
        self.lights.retain(|l| !matches!(l, Light::Environment(_)));
        self.lights.push(Light::Environment(light));
        self
    }

    pub fn spot_light(&mut self, light: SpotLight) -> &mut Self {
        self.lights.push(Light::Spot(light));
        self
    }

    /// Validate and build the scene, including its BVH.
    pub fn build(self) -> Result<Scene> {
        let invalid = |m: String| Err(Error::InvalidScene(m));
        let Some(camera) = self.camera else {
            return invalid("the scene has no camera".into());
        };
        if Camera::new(&camera, self.resolution.0, self.resolution.1).is_none() {
            return invalid("the camera is degenerate (look-at equals position, up parallel to the view, or field of view outside (0°, 180°))".into());
        }
        let mut shapes = Vec::new();
        let mut prim_material = Vec::new();
        let mut prim_light = Vec::new();
        let mut prim_normals = Vec::new();
        let mut vertex_normals = Vec::new();
        let mut prim_uvs = Vec::new();
        let mut prim_second_uvs = Vec::new();
        let mut vertex_uvs = Vec::new();
        let mut prim_tangents = Vec::new();
        let mut vertex_tangents = Vec::new();
        let mut prim_boundary = Vec::new();
        let any_boundary = self.objects.iter().any(|o| o.boundary.is_some());
        let media_count = self.media.len();
        let known = |m: Option<MediumId>| m.is_none_or(|m| (m as usize) < media_count);
        if !known(self.atmosphere) {
            return invalid("the scene's medium does not exist".into());
        }
        for (i, m) in self.media.iter().enumerate() {
            let (sigma_a, sigma_s) = m.coefficients();
            if ![sigma_a, sigma_s]
                .iter()
                .all(|c| c.is_finite() && c.min_element() >= 0.0)
            {
                return invalid(format!(
                    "medium {i} has σa {sigma_a} and σs {sigma_s}: both must be finite and not negative"
                ));
            }
        }
        let mut lights = self.lights;
        for (i, o) in self.objects.into_iter().enumerate() {
            let object_error = |message: String| Err(Error::InvalidObject { index: i, message });
            if o.material as usize >= self.materials.len() {
                return object_error(format!("uses material {} which does not exist", o.material));
            }
            let check = |s: &Shape| {
                let b = s.bounds();
                b.min.is_finite() && b.max.is_finite()
            };
            if !o.shapes.iter().all(check) {
                return object_error("has non-finite coordinates".into());
            }
            // Bounds the BVH and the ray arithmetic can take (extents are squared).
            let reach = o
                .shapes
                .iter()
                .map(|s| {
                    let b = s.bounds();
                    b.min.abs().max(b.max.abs()).max_element()
                })
                .fold(0.0f32, f32::max);
            if reach > MAX_COORDINATE {
                return object_error(format!(
                    "reaches {reach:e} from the origin, beyond the ±{MAX_COORDINATE:e} that coordinates may have"
                ));
            }
            let light = match o.emission {
                Some(e) if e.radiance.rgb().max_element() > 0.0 => {
                    // Spectra hold their colour clamped to UNBOUNDED_MAX: an emission that
                    // reaches it overflowed.
                    let rgb = e.radiance.rgb();
                    if !rgb.is_finite()
                        || rgb.min_element() < 0.0
                        || rgb.max_element() >= crate::spectrum::UNBOUNDED_MAX
                    {
                        return object_error(format!("has an invalid emission {rgb}"));
                    }
                    let light = AreaLight::new(o.shapes.clone(), e.radiance, e.two_sided);
                    let light = match (light, e.texture) {
                        (Some(l), Some(t)) => {
                            let uvs = match (e.texture_mapping.set, &o.second_uvs) {
                                (1, Some(second)) => Some(second.clone()),
                                _ => o.uvs.clone(),
                            };
                            Some(l.with_texture(t, e.texture_mapping, uvs))
                        }
                        (l, _) => l,
                    };
                    match light {
                        Some(l) => {
                            lights.push(Light::Area(l));
                            (lights.len() - 1) as u32
                        }
                        None => return object_error("is emissive but has no area".into()),
                    }
                }
                _ => NO_LIGHT,
            };
            if let Some(b) = o.boundary
                && !(known(b.inside) && known(b.outside))
            {
                return object_error("bounds a medium that does not exist".into());
            }
            for (k, s) in o.shapes.into_iter().enumerate() {
                if any_boundary {
                    prim_boundary.push(o.boundary.unwrap_or_default());
                }
                shapes.push(s);
                prim_material.push(o.material);
                prim_light.push(light);
                match o.normals.as_ref().and_then(|n| n.get(k)) {
                    Some(n) if n.iter().all(|v| v.is_finite() && *v != Vec3::ZERO) => {
                        vertex_normals.push(*n);
                        prim_normals.push((vertex_normals.len() - 1) as u32);
                    }
                    _ => prim_normals.push(NO_LIGHT),
                }
                match o.uvs.as_ref().and_then(|uv| uv.get(k)) {
                    Some(uv) if uv.iter().all(|v| v.is_finite()) => {
                        vertex_uvs.push(*uv);
                        prim_uvs.push((vertex_uvs.len() - 1) as u32);
                    }
                    _ => prim_uvs.push(NO_LIGHT),
                }
                match o.second_uvs.as_ref().and_then(|uv| uv.get(k)) {
                    Some(uv) if uv.iter().all(|v| v.is_finite()) => {
                        vertex_uvs.push(*uv);
                        prim_second_uvs.push((vertex_uvs.len() - 1) as u32);
                    }
                    _ => prim_second_uvs.push(NO_LIGHT),
                }
                match o.tangents.as_ref().and_then(|t| t.get(k)) {
                    Some(t)
                        if t.iter()
                            .all(|v| v.is_finite() && v.truncate() != Vec3::ZERO) =>
                    {
                        vertex_tangents.push(*t);
                        prim_tangents.push((vertex_tangents.len() - 1) as u32);
                    }
                    _ => prim_tangents.push(NO_LIGHT),
                }
            }
        }
        let covered_partly =
            |m: &u32| self.material_textures[*m as usize].coverage != Coverage::Opaque;
        let refusable: Vec<bool> = prim_material.iter().map(covered_partly).collect();
        let has_partial_coverage = refusable.contains(&true);
        let (rays, order) = super::rays::RayCaster::build(&shapes, &refusable, self.ray_engine)?;
        fit_directional_lights(&mut lights, &rays.bounds());
        let reorder = |v: &[u32]| order.iter().map(|&i| v[i as usize]).collect::<Vec<u32>>();
        let prim_material = reorder(&prim_material);
        let prim_light = reorder(&prim_light);
        let prim_normals = reorder(&prim_normals);
        let prim_uvs = reorder(&prim_uvs);
        let prim_second_uvs = reorder(&prim_second_uvs);
        let prim_tangents = reorder(&prim_tangents);
        let prim_boundary: Vec<Boundary> = order
            .iter()
            .filter_map(|&i| prim_boundary.get(i as usize).copied())
            .collect();
        let shapes = order.iter().map(|&i| shapes[i as usize]).collect();
        check_light_powers(&lights)?;
        let powers: Vec<f64> = lights
            .iter()
            .map(|l| {
                let p = l.power();
                f64::from(p.x) + f64::from(p.y) + f64::from(p.z)
            })
            .collect();
        let environment = lights
            .iter()
            .position(|l| matches!(l, Light::Environment(_)));
        let mut scene = Scene {
            view_bounds: None,
            environment,
            name: self.name,
            shapes,
            prim_material,
            prim_light,
            prim_normals,
            vertex_normals,
            prim_uvs,
            prim_second_uvs,
            vertex_uvs,
            prim_tangents,
            vertex_tangents,
            materials: self.materials,
            material_textures: self.material_textures,
            textures: self.textures,
            has_partial_coverage,
            light_choice: AliasTable::new(&powers),
            point_lights: (0..lights.len() as u32)
                .filter(|&i| lights[i as usize].point_position().is_some())
                .collect(),
            lights,
            camera,
            default_resolution: self.resolution,
            rays,
            content_hash: std::sync::OnceLock::new(),
            media: self.media,
            prim_boundary,
            atmosphere: self.atmosphere,
            camera_medium: self.atmosphere,
            light_media: Vec::new(),
        };
        scene.aim_distant_lights_at_view();
        scene.locate_camera_and_lights_in_media();
        Ok(scene)
    }
}

/// Every light's power, and the lights' total, finite in each channel: photons carry it, and
/// light choice, photon maps and progressive passes all divide by it. A light whose radiance or
/// intensity times its size (its area, or the scene's bounding disc for distant lights)
/// overflows single precision is refused.
fn check_light_powers(lights: &[Light]) -> Result<()> {
    let mut total = Rgb::ZERO;
    for (i, l) in lights.iter().enumerate() {
        let p = l.power();
        total += p;
        if !p.is_finite() || !total.is_finite() {
            let kind = match l {
                Light::Point(_) => "point light",
                Light::Spot(_) => "spot light",
                Light::Directional(_) => "directional light",
                Light::Area(_) => "emitter",
                Light::Environment(_) => "environment light",
            };
            return Err(Error::InvalidScene(format!(
                "light {i} (the {kind}) has a power of {p} W, beyond the {:e} W per channel the lights may emit together: lower its radiance or intensity",
                f32::MAX
            )));
        }
    }
    Ok(())
}

/// Give distant lights (directional, environment) the scene's bounding sphere (a hair larger,
/// so shadow rays end outside it), which sets their power and where their photons start. In an
/// empty scene they have no power.
fn fit_directional_lights(lights: &mut [Light], bounds: &crate::geometry::Bounds) {
    for l in lights {
        let aperture = match l {
            Light::Directional(d) => &mut d.aperture,
            Light::Environment(e) => &mut e.aperture,
            _ => continue,
        };
        aperture.center = 0.5 * (bounds.min + bounds.max);
        aperture.radius = 0.5 * bounds.extent().length() * 1.001;
        if !aperture.radius.is_finite() || !aperture.center.is_finite() {
            *aperture = crate::light::Aperture::default();
        }
    }
}
