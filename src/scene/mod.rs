//! The renderable scene: shapes in a BVH, materials, lights, camera.
//!
//! A [`Scene`] is built by a [`SceneBuilder`], which validates everything; once built, rendering
//! it cannot fail.

mod builder;
mod media;
mod rays;

pub use builder::{Emission, SceneBuilder, TextureMaps};
pub use media::{Interaction, MAX_CROSSINGS, ScatteringPiece, Step};

/// An indexed triangle mesh in object space, as read from a file or built in code. `normals`,
/// `uvs`, `second_uvs` and `tangents` are per vertex and may be empty (flat shading, the
/// triangle's own parametrisation, tangents from the UVs). A tangent is glTF's: xyz along +u,
/// w the sign of the bitangent (w·n × t).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    /// A second coordinate set (glTF's `TEXCOORD_1`), read by textures that name it.
    pub second_uvs: Vec<Vec2>,
    pub tangents: Vec<glam::Vec4>,
    pub triangles: Vec<[u32; 3]>,
}

use crate::accel::RayEngine;
use crate::camera::CameraDesc;
use crate::geometry::{Bounds, Shape};
use crate::hash::Fnv1a;
use crate::light::{EnvironmentLight, Light};
use crate::material::{Attenuation, Dispersion, Material, Pbr};
use crate::math::{Frame, Ray, Rgb, Vec2, Vec3};
use crate::sampling::AliasTable;
use crate::spectrum::Lambda;
use crate::texture::{MappedTexture, Texture};

/// Indices of a material's textures in the scene's texture list, its coverage and the
/// absorption inside it: what a hit resolves into the material ([`Scene::surface`]), which
/// stays a small `Copy` value.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct MaterialMaps {
    pub base: Option<u32>,
    pub metallic_roughness: Option<u32>,
    pub normal: Option<u32>,
    pub normal_scale: f32,
    pub coverage: Coverage,
    /// Absorption in the volume a dielectric encloses.
    pub attenuation: Option<Attenuation>,
    /// How a dielectric's index varies with wavelength.
    pub dispersion: Dispersion,
}

/// How much of a surface is there (glTF 2.0 §3.9.4, `alphaMode`). Its alpha is `alpha`
/// times the base-colour texture's alpha where the material has one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Coverage {
    /// Everywhere (alpha is ignored).
    #[default]
    Opaque,
    /// A cut-out: the surface is absent where its alpha is below `cutoff`.
    Mask { alpha: f32, cutoff: f32 },
    /// Partly there: each ray meets it with probability alpha, decided by a hash of the ray
    /// and the primitive (stochastic transparency, as pbrt-v4's alpha test), so a ray always
    /// gets the same answer and images stay deterministic.
    Blend { alpha: f32 },
}

/// Marks a primitive that is not part of an area light.
pub const NO_LIGHT: u32 = u32::MAX;

/// A ray–scene intersection.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Distance along the ray (whose direction has unit length).
    pub t: f32,
    pub p: Vec3,
    /// Geometric normal of the primitive as modelled (outward for spheres, winding for triangles).
    pub ng: Vec3,
    /// A bound on each coordinate of `p`'s distance from the true surface.
    pub error: Vec3,
    /// Shading normal: interpolated vertex normals on smooth meshes, else `ng`; always on the
    /// same side as `ng`.
    pub ns: Vec3,
    /// The shape's own hit parameters: barycentrics (b1, b2) on triangles, zero elsewhere.
    /// Texture coordinates are derived from them only when a texture asks
    /// ([`Scene::texture_uv`]), keeping the trigonometry of spheres off untextured hits.
    pub barycentrics: Vec2,
    pub prim: u32,
    pub material: u32,
    /// Index of the area light this primitive belongs to, or [`NO_LIGHT`].
    pub light: u32,
}

impl Hit {
    /// Origin for a ray leaving the hit in direction `w`: off the surface to `w`'s side, past
    /// the hit point's error ([`crate::math::offset_origin`]).
    #[inline]
    pub fn offset_origin(&self, w: Vec3) -> Vec3 {
        crate::math::offset_origin(self.p, self.error, self.ng, w)
    }

    /// The geometric normal on the side of `w`: which surface, and which of its faces, a
    /// point is on (photon estimates compare these; shading normals bend across a mesh).
    pub fn ng_facing(&self, w: Vec3) -> Vec3 {
        if self.ng.dot(w) < 0.0 {
            -self.ng
        } else {
            self.ng
        }
    }

    /// Shading frame for material `m` seen from direction `wo` (pointing away from the
    /// surface): two-sided materials face `wo`; dielectrics keep the outward normal.
    pub fn frame(&self, m: &Material, wo: Vec3) -> Frame {
        let n = if m.is_two_sided() && self.ng.dot(wo) < 0.0 {
            -self.ns
        } else {
            self.ns
        };
        Frame::from_normal(n)
    }
}

pub struct Scene {
    pub name: String,
    shapes: Vec<Shape>,
    prim_material: Vec<u32>,
    prim_light: Vec<u32>,
    /// Index into `vertex_normals` per primitive, or `NO_LIGHT` for flat shading.
    prim_normals: Vec<u32>,
    vertex_normals: Vec<[Vec3; 3]>,
    /// Index into `vertex_uvs` per primitive, or `NO_LIGHT` for the shape's own parametrisation.
    prim_uvs: Vec<u32>,
    /// Index into `vertex_uvs` of each primitive's second coordinate set, or `NO_LIGHT` (then
    /// textures that name the second set read the first).
    prim_second_uvs: Vec<u32>,
    vertex_uvs: Vec<[Vec2; 3]>,
    /// Index into `vertex_tangents` per primitive, or `NO_LIGHT` for tangents from the UVs.
    prim_tangents: Vec<u32>,
    vertex_tangents: Vec<[glam::Vec4; 3]>,
    materials: Vec<Material>,
    /// The textures of each material (parallel to `materials`).
    material_textures: Vec<MaterialMaps>,
    textures: Vec<MappedTexture>,
    /// Whether any material is not [`Coverage::Opaque`]: only then do ray queries test
    /// coverage at each candidate hit.
    has_partial_coverage: bool,
    lights: Vec<Light>,
    /// Picks a light by power, in constant time for any number of lights.
    light_choice: Option<AliasTable>,
    /// The lights that shine from a point (point and spot lights), by index.
    point_lights: Vec<u32>,
    /// The participating media, indexed by [`crate::medium::MediumId`].
    media: Vec<crate::medium::Medium>,
    /// The boundary each primitive is part of (the default, none, on the others); empty when
    /// no shape bounds a medium.
    prim_boundary: Vec<crate::medium::Boundary>,
    /// The medium around every shape (`None`: vacuum).
    atmosphere: Option<crate::medium::MediumId>,
    /// The medium the camera is in, and each light's (parallel to `lights`): the atmosphere,
    /// or the inside of the boundary around them ([`Scene::medium_at`], found at build).
    camera_medium: Option<crate::medium::MediumId>,
    light_media: Vec<Option<crate::medium::MediumId>>,
    pub camera: CameraDesc,
    /// Index of the environment light among `lights`, if there is one.
    environment: Option<usize>,
    /// What the camera sees (see [`Scene::view_diagonal`]), measured at build.
    view_bounds: Option<Bounds>,
    /// Resolution used when the user gives none.
    pub default_resolution: (u32, u32),
    rays: rays::RayCaster,
    /// [`Scene::content_hash`], computed on first use: every progressive pass asks for it
    /// (photon maps carry it), and formatting every primitive took 0.22 s at 102k triangles.
    content_hash: std::sync::OnceLock<u64>,
}

impl Scene {
    /// Closest intersection along `ray` nearer than `t_max`, skipping the parts of surfaces
    /// their coverage leaves out (so every integrator, camera ray, shadow ray and photon
    /// sees the same cut-outs).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (prim, shape_hit) = if self.has_partial_coverage {
            self.rays
                .closest_hit(&self.shapes, ray, t_max, |prim, hit| {
                    self.covers(prim, hit, ray)
                })?
        } else {
            self.rays
                .closest_hit(&self.shapes, ray, t_max, |_, _| true)?
        };
        let surface = self.shapes[prim as usize].surface(ray, &shape_hit);
        let ns = match self.prim_normals[prim as usize] {
            NO_LIGHT => surface.n,
            k => {
                let [n0, n1, n2] = self.vertex_normals[k as usize];
                let (b1, b2) = (shape_hit.uv.x, shape_hit.uv.y);
                let n = ((1.0 - b1 - b2) * n0 + b1 * n1 + b2 * n2).normalize_or(surface.n);
                if n.dot(surface.n) < 0.0 { -n } else { n }
            }
        };
        Some(Hit {
            t: shape_hit.t,
            p: surface.p,
            ng: surface.n,
            error: surface.error,
            ns,
            barycentrics: shape_hit.uv,
            prim,
            material: self.prim_material[prim as usize],
            light: self.prim_light[prim as usize],
        })
    }

    /// Whether nothing blocks the segment from `from` to `to` (up to
    /// [`crate::math::segment_reach`]: its end may lie on a surface).
    #[inline]
    pub fn segment_is_clear(&self, from: Vec3, to: Vec3) -> bool {
        let d = to - from;
        let dist = d.length();
        dist > 0.0 && !self.occluded(from, d / dist, crate::math::segment_reach(from, to, dist))
    }

    /// Whether anything blocks the segment from `origin` along unit `dir` up to `dist`
    /// (surfaces' coverage as in [`Scene::intersect`]).
    #[inline]
    pub fn occluded(&self, origin: Vec3, dir: Vec3, dist: f32) -> bool {
        let ray = Ray::new(origin, dir);
        if self.has_partial_coverage {
            self.rays.any_hit(&self.shapes, &ray, dist, |prim, hit| {
                self.covers(prim, hit, &ray)
            })
        } else {
            self.rays.any_hit(&self.shapes, &ray, dist, |_, _| true)
        }
    }

    /// Whether a candidate hit on `prim` along `ray` is on the surface its coverage keeps.
    fn covers(&self, prim: u32, hit: &crate::geometry::ShapeHit, ray: &Ray) -> bool {
        let maps = &self.material_textures[self.prim_material[prim as usize] as usize];
        let (factor, cutoff) = match maps.coverage {
            Coverage::Opaque => return true,
            Coverage::Mask { alpha, cutoff } => (alpha, Some(cutoff)),
            Coverage::Blend { alpha } => (alpha, None),
        };
        let alpha = factor
            * maps.base.map_or(1.0, |t| {
                let texture = &self.textures[t as usize];
                let uv = self.uv_at(prim, hit, ray.at(hit.t), texture.mapping.set);
                texture.alpha(uv)
            });
        match cutoff {
            Some(cutoff) => alpha >= cutoff,
            None => alpha >= 1.0 || (alpha > 0.0 && blend_hash(ray, prim) < alpha),
        }
    }

    /// The ray caster this scene was built with (never [`RayEngine::Best`]).
    pub fn ray_engine(&self) -> RayEngine {
        self.rays.engine()
    }

    /// Closest hit by testing every primitive: the reference the BVH is tested against.
    pub fn intersect_brute_force(&self, ray: &Ray, t_max: f32) -> Option<(u32, f32)> {
        let mut best: Option<(u32, f32)> = None;
        for (i, s) in self.shapes.iter().enumerate() {
            let limit = best.map_or(t_max, |b| b.1);
            if let Some(h) = s.intersect(ray, 0.0, limit) {
                best = Some((i as u32, h.t));
            }
        }
        best
    }

    pub fn material(&self, id: u32) -> &Material {
        &self.materials[id as usize]
    }

    /// The material at a hit, with its textures looked up at the hit's (u, v).
    #[inline]
    pub fn material_at(&self, hit: &Hit) -> Material {
        let m = self.materials[hit.material as usize];
        let maps = &self.material_textures[hit.material as usize];
        if maps.base.is_none() && maps.metallic_roughness.is_none() {
            return m;
        }
        let base = maps.base.map_or(Rgb::ONE, |t| self.lookup(t, hit));
        match m {
            Material::Lambertian(mut l) => {
                l.albedo *= base;
                Material::Lambertian(l)
            }
            Material::Pbr(p) => {
                let (mut metallic, mut roughness) = (p.metallic, p.roughness);
                if let Some(t) = maps.metallic_roughness {
                    let mr = self.lookup(t, hit);
                    metallic *= mr.z;
                    roughness *= mr.y;
                }
                Material::Pbr(
                    Pbr::new(p.base_color * base, metallic, roughness).with_specular(p.specular),
                )
            }
            _ => m,
        }
    }

    /// The material at a hit and its shading frame seen from `wo` (normal-mapped where the
    /// material has a normal map).
    ///
    /// Met from inside an absorbing dielectric (`wo` on the inner side of the outward
    /// geometric normal), the path has just travelled `hit.t` through its volume, and the
    /// material comes with that segment's Beer–Lambert transmittance on every lobe
    /// ([`Material::attenuated`]). Each segment inside a closed volume ends at such a hit,
    /// and paths from the camera and from the lights alike meet it in the order travelled,
    /// so every integrator, and photons, attenuate each segment once, where the path goes on
    /// (through the surface or reflected back inside). Shadow rays never cross a dielectric
    /// (it occludes), so they need no attenuation. Surfaces enclosed in the glass are not in
    /// its volume: media do not nest.
    #[inline]
    pub fn surface(&self, hit: &Hit, wo: Vec3, lambda: &mut Lambda) -> (Material, Frame) {
        let maps = &self.material_textures[hit.material as usize];
        let m = self.material_at(hit).at(lambda, maps.dispersion);
        let m = match maps.attenuation {
            Some(a) if hit.ng.dot(wo) < 0.0 => m.attenuated(a.transmittance(hit.t, lambda)),
            _ => m,
        };
        if let Some(t) = maps.normal
            && let Some(ns) = self.normal_mapped(hit, t, maps.normal_scale)
        {
            let mapped = Hit { ns, ..*hit };
            return (m, mapped.frame(&m, wo));
        }
        (m, hit.frame(&m, wo))
    }

    /// The shading normal bent by a tangent-space normal map, on triangles with texture
    /// coordinates. The tangent frame is the file's tangents where it has them (glTF
    /// `TANGENT`), else the triangle's own: the tangent along ∂p/∂u (made orthogonal to the
    /// interpolated normal), the bitangent along ∂p/∂v (glTF's convention, green up, with our
    /// v growing up the image). `None` where there is no frame, or where
    /// the map would turn the normal past the surface.
    fn normal_mapped(&self, hit: &Hit, texture: u32, scale: f32) -> Option<Vec3> {
        let Shape::Triangle(tri) = &self.shapes[hit.prim as usize] else {
            return None;
        };
        let map = &self.textures[texture as usize];
        let k = self.set_index(hit.prim, map.mapping.set);
        if k == NO_LIGHT {
            return None;
        }
        // The tangent frame follows the coordinates the map is read with (its set and
        // transform: a rotated normal map turns its frame with it).
        let [a, b, c] =
            self.vertex_uvs[k as usize].map(|uv| map.mapping.transform.transform_point2(uv));
        let (d1, d2) = (b - a, c - a);
        let det = d1.x * d2.y - d1.y * d2.x;
        if det.abs() < 1e-12 {
            return None;
        }
        let (e1, e2) = (tri.e1(), tri.e2());
        let dpdu = (e1 * d2.y - e2 * d1.y) / det;
        let dpdv = (e2 * d1.x - e1 * d2.x) / det;
        let n = hit.ns;
        let (tangent, bitangent) = match self.prim_tangents[hit.prim as usize] {
            // The file's tangents (glTF: interpolated, bitangent w·n × t), which follow the
            // first coordinate set as it is.
            k if k != NO_LIGHT && map.mapping.reads_first_set_unchanged() => {
                let [t0, t1, t2] = self.vertex_tangents[k as usize];
                let (b1, b2) = (hit.barycentrics.x, hit.barycentrics.y);
                let t = ((1.0 - b1 - b2) * t0 + b1 * t1 + b2 * t2).truncate();
                let tangent = (t - n * n.dot(t)).try_normalize()?;
                (tangent, n.cross(tangent) * t0.w.signum())
            }
            _ => {
                let tangent = (dpdu - n * n.dot(dpdu)).try_normalize()?;
                let bitangent = n.cross(tangent);
                (
                    tangent,
                    if bitangent.dot(dpdv) < 0.0 {
                        -bitangent
                    } else {
                        bitangent
                    },
                )
            }
        };
        let t = self.lookup(texture, hit) * 2.0 - Rgb::ONE;
        let mapped =
            (tangent * (t.x * scale) + bitangent * (t.y * scale) + n * t.z).try_normalize()?;
        (mapped.dot(hit.ng) > 0.0).then_some(mapped)
    }

    /// Texture coordinates at a hit: interpolated vertex UVs on meshes that have them, else
    /// the shape's own parametrisation (barycentrics, spherical angles, polar disk coordinates).
    pub fn texture_uv(&self, hit: &Hit) -> Vec2 {
        self.uv_in_set(hit, 0)
    }

    /// Texture coordinates of set `set` (0 or 1) at a hit; where a mesh has no second set,
    /// the first.
    pub fn uv_in_set(&self, hit: &Hit, set: u8) -> Vec2 {
        let shape_hit = crate::geometry::ShapeHit {
            t: hit.t,
            uv: hit.barycentrics,
        };
        self.uv_at(hit.prim, &shape_hit, hit.p, set)
    }

    fn uv_at(&self, prim: u32, hit: &crate::geometry::ShapeHit, p: Vec3, set: u8) -> Vec2 {
        match self.set_index(prim, set) {
            NO_LIGHT => self.shapes[prim as usize].uv(hit, p),
            k => {
                let (b1, b2) = (hit.uv.x, hit.uv.y);
                let [a, b, c] = self.vertex_uvs[k as usize];
                (1.0 - b1 - b2) * a + b1 * b + b2 * c
            }
        }
    }

    /// Index into `vertex_uvs` of a primitive's coordinate set `set`, or `NO_LIGHT`.
    fn set_index(&self, prim: u32, set: u8) -> u32 {
        match self.prim_second_uvs[prim as usize] {
            k if set == 1 && k != NO_LIGHT => k,
            _ => self.prim_uvs[prim as usize],
        }
    }

    /// Texture `t` of the scene's list at a hit, read through its own mapping.
    fn lookup(&self, t: u32, hit: &Hit) -> Rgb {
        let texture = &self.textures[t as usize];
        texture.eval(self.uv_in_set(hit, texture.mapping.set))
    }

    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Radiance emitted from a hit toward direction `w` (zero unless the hit is on an area light).
    pub fn emitted(&self, hit: &Hit, w: Vec3, lambda: &Lambda) -> Rgb {
        if hit.light == NO_LIGHT {
            return Rgb::ZERO;
        }
        match &self.lights[hit.light as usize] {
            Light::Area(l) if l.is_textured() => {
                l.emitted_at(hit.ng, w, self.uv_in_set(hit, l.texture_uv_set()), lambda)
            }
            Light::Area(l) => l.emitted(hit.ng, w, lambda),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Environment(_) => {
                Rgb::ZERO
            }
        }
    }

    /// The environment light, if the scene has one, with its index among the lights.
    #[inline]
    pub fn environment(&self) -> Option<(usize, &EnvironmentLight)> {
        let i = self.environment?;
        match &self.lights[i] {
            Light::Environment(e) => Some((i, e)),
            _ => None,
        }
    }

    /// Radiance arriving along a ray that leaves the scene in direction `dir`: the environment's,
    /// or zero.
    #[inline]
    pub fn escaped(&self, dir: Vec3, lambda: &Lambda) -> Rgb {
        self.environment()
            .map_or(Rgb::ZERO, |(_, e)| e.radiance(dir, lambda))
    }

    /// Pick a light in proportion to its power; returns its index and probability.
    pub fn choose_light(&self, u: f32) -> Option<(usize, f32, f32)> {
        let d = self.light_choice.as_ref()?;
        let (i, rest) = d.sample(u);
        Some((i, d.pmf(i), rest))
    }

    /// The lights that shine from a point (point and spot lights), by index.
    pub fn point_lights(&self) -> &[u32] {
        &self.point_lights
    }

    /// Probability that [`Scene::choose_light`] picks light `i`.
    pub fn light_choice_pmf(&self, i: usize) -> f32 {
        self.light_choice.as_ref().map_or(0.0, |d| d.pmf(i))
    }

    pub fn primitive_count(&self) -> usize {
        self.shapes.len()
    }

    pub fn shape(&self, prim: u32) -> &Shape {
        &self.shapes[prim as usize]
    }

    pub fn bounds(&self) -> Bounds {
        self.rays.bounds()
    }

    /// A stable 64-bit fingerprint of everything that affects light transport (shapes,
    /// materials, lights), used to refuse photon maps traced for another scene. FNV-1a over
    /// the exact (round-trip) text of every value, so it is the same on every machine and run.
    pub fn content_hash(&self) -> u64 {
        *self
            .content_hash
            .get_or_init(|| self.compute_content_hash())
    }

    fn compute_content_hash(&self) -> u64 {
        let mut h = Fnv1a::default();
        for (i, s) in self.shapes.iter().enumerate() {
            h.write(format!("{s:?}{}{}", self.prim_material[i], self.prim_light[i]).as_bytes());
        }
        for m in &self.materials {
            h.write(format!("{m:?}").as_bytes());
        }
        for t in &self.material_textures {
            h.write(format!("{t:?}").as_bytes());
        }
        for t in &self.textures {
            h.write(format!("{:?}", t.mapping).as_bytes());
            match &t.texture {
                Texture::Checker(c) => h.write(format!("{c:?}").as_bytes()),
                Texture::Image(i) => {
                    h.write(format!("{}x{}", i.width, i.height).as_bytes());
                    for v in &i.texels {
                        h.write(bytemuck::bytes_of(&v.to_array()));
                    }
                    for a in &i.alpha {
                        h.write(&a.to_le_bytes());
                    }
                }
            }
        }
        for uv in &self.vertex_uvs {
            h.write(format!("{uv:?}").as_bytes());
        }
        if self.has_media() {
            let media = (&self.media, &self.prim_boundary, self.atmosphere);
            h.write(format!("{media:?}").as_bytes());
        }
        for l in &self.lights {
            h.write(format!("{:?}", l.power()).as_bytes());
            h.write(format!("{l:?}").as_bytes());
        }
        h.finish()
    }

    /// Give distant lights (sun, sky) a sphere around what the camera sees, through which half
    /// their photons enter (see [`crate::light::Aperture`]): the bounding box of the first hits
    /// of a 48 × 48 grid of camera rays, 10% larger. None when it would not be much smaller
    /// than the whole scene (then it would gain nothing) or the camera sees nothing.
    /// The diagonal of what the camera sees (the bounding box of the first hits of a grid of
    /// camera rays), or of the whole scene when the camera sees nothing: the length that
    /// default gather radii are fractions of. A scene's ground may reach far beyond the
    /// objects looked at; radii scaled by the whole scene then reach across to other objects
    /// whose surfaces face the same way (a row of small spheres on a 20 m plane lost most of
    /// their indirect light so).
    pub fn view_diagonal(&self) -> f32 {
        let whole = self.bounds().extent().length();
        self.view_bounds
            .map_or(whole, |b| b.extent().length().min(whole))
    }

    pub(crate) fn aim_distant_lights_at_view(&mut self) {
        const GRID: u32 = 48;
        let (w, h) = self.default_resolution;
        let Some(camera) = crate::camera::Camera::new(&self.camera, w.max(1), h.max(1)) else {
            return;
        };
        let mut bounds: Option<Bounds> = None;
        for j in 0..GRID {
            for i in 0..GRID {
                let film = Vec2::new(
                    (i as f32 + 0.5) / GRID as f32 * w as f32,
                    (j as f32 + 0.5) / GRID as f32 * h as f32,
                );
                if let Some(hit) = self.intersect(&camera.ray(film), f32::INFINITY) {
                    let b = Bounds {
                        min: hit.p,
                        max: hit.p,
                    };
                    bounds = Some(bounds.map_or(b, |a| a.union(b)));
                }
            }
        }
        let Some(b) = bounds else {
            return;
        };
        self.view_bounds = Some(b);
        let center = 0.5 * (b.min + b.max);
        for l in &mut self.lights {
            let aperture = match l {
                Light::Directional(d) => &mut d.aperture,
                Light::Environment(e) => &mut e.aperture,
                _ => continue,
            };
            let radius = (0.5 * b.extent().length() * 1.1).max(1e-3 * aperture.radius);
            let inside = (center - aperture.center).length() + radius <= aperture.radius;
            aperture.view = (inside && radius < 0.5 * aperture.radius).then_some((center, radius));
        }
    }

    /// Sum of all lights' power, watts per channel.
    pub fn total_power(&self) -> Rgb {
        self.lights.iter().map(Light::power).sum()
    }
}

/// A number in [0, 1) that is a hash of a ray (origin and direction) and a primitive: the
/// draw that decides whether a [`Coverage::Blend`] surface is met. pbrt-v4 hashes the ray the
/// same way (`HashFloat(ray.o, ray.d)`); the primitive makes layers along one ray independent.
fn blend_hash(ray: &Ray, prim: u32) -> f32 {
    let mut h = u64::from(prim);
    for x in ray.origin.to_array().into_iter().chain(ray.dir.to_array()) {
        h = crate::sampling::mix64(h ^ u64::from(x.to_bits()));
    }
    (h >> 40) as f32 / (1u64 << 24) as f32
}
