use super::{NO_LIGHT, Scene};
use crate::accel::Bvh;
use crate::camera::{Camera, CameraDesc};
use crate::error::{Error, Result};
use crate::geometry::{Disk, Shape, Sphere, Triangle};
use crate::light::{AreaLight, Light, PointLight, SpotLight};
use crate::material::Material;
use crate::math::{Rgb, Vec3};
use crate::sampling::Distribution1D;
use glam::Affine3A;

/// Light emitted by an object's surface: constant radiance (W·m⁻²·sr⁻¹), one- or two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    pub radiance: Rgb,
    pub two_sided: bool,
}

struct Object {
    shapes: Vec<Shape>,
    /// Per-vertex shading normals of each triangle (smooth meshes), parallel to `shapes`.
    normals: Option<Vec<[Vec3; 3]>>,
    material: u32,
    emission: Option<Emission>,
}

/// Collects objects, materials and lights, then validates them into a [`Scene`].
pub struct SceneBuilder {
    name: String,
    materials: Vec<Material>,
    objects: Vec<Object>,
    lights: Vec<Light>,
    camera: Option<CameraDesc>,
    resolution: (u32, u32),
}

impl SceneBuilder {
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_owned(),
            materials: Vec::new(),
            objects: Vec::new(),
            lights: Vec::new(),
            camera: None,
            resolution: (512, 512),
        }
    }

    pub fn camera(&mut self, camera: CameraDesc, width: u32, height: u32) -> &mut Self {
        self.camera = Some(camera);
        self.resolution = (width, height);
        self
    }

    pub fn material(&mut self, m: Material) -> u32 {
        self.materials.push(m);
        (self.materials.len() - 1) as u32
    }

    fn push_object(&mut self, shapes: Vec<Shape>, material: u32, emission: Option<Emission>) {
        self.objects.push(Object {
            shapes,
            normals: None,
            material,
            emission,
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
            .map_err(|e| Error::InvalidScene(format!("object {}: {e}", self.objects.len())))?;
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
        if normals.len() != positions.len() {
            return Err(Error::InvalidScene(format!(
                "a smooth mesh has {} normals for {} vertices",
                normals.len(),
                positions.len()
            )));
        }
        let normal_matrix = transform.matrix3.inverse().transpose();
        let world_normals: Vec<Vec3> = normals
            .iter()
            .map(|&n| Vec3::from(normal_matrix * glam::Vec3A::from(n)).normalize_or_zero())
            .collect();
        let before = self.objects.len();
        self.mesh(positions, triangles, transform, material, None)?;
        // `mesh` dropped degenerate triangles: keep the normals of the ones it kept.
        let world: Vec<Vec3> = positions
            .iter()
            .map(|&p| transform.transform_point3(p))
            .collect();
        let kept: Vec<[Vec3; 3]> = triangles
            .iter()
            .filter(|t| {
                Triangle::new(
                    world[t[0] as usize],
                    world[t[1] as usize],
                    world[t[2] as usize],
                )
                .area()
                    > 0.0
            })
            .map(|t| t.map(|i| world_normals[i as usize]))
            .collect();
        if let Some(o) = self.objects.get_mut(before) {
            o.normals = Some(kept);
        }
        Ok(self)
    }

    /// A triangle mesh; `transform` maps object space to world space.
    pub fn mesh(
        &mut self,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        transform: Affine3A,
        material: u32,
        emission: Option<Emission>,
    ) -> Result<&mut Self> {
        let world: Vec<Vec3> = positions
            .iter()
            .map(|&p| transform.transform_point3(p))
            .collect();
        let mut shapes = Vec::with_capacity(triangles.len());
        for (k, t) in triangles.iter().enumerate() {
            let v = |i: u32| {
                world.get(i as usize).copied().ok_or_else(|| {
                    Error::InvalidScene(format!(
                        "triangle {k} uses vertex {i}, but the mesh has {} vertices",
                        world.len()
                    ))
                })
            };
            let tri = Triangle::new(v(t[0])?, v(t[1])?, v(t[2])?);
            // Degenerate triangles can never be hit and have no area to emit from.
            if tri.area() > 0.0 {
                shapes.push(Shape::Triangle(tri));
            }
        }
        self.push_object(shapes, material, emission);
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
        .collect();
        self.push_object(shapes, material, emission);
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

    pub fn point_light(&mut self, position: Vec3, intensity: Rgb) -> &mut Self {
        self.lights.push(Light::Point(PointLight {
            position,
            intensity,
        }));
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
        let mut lights = self.lights;
        for (i, o) in self.objects.into_iter().enumerate() {
            if o.material as usize >= self.materials.len() {
                return invalid(format!(
                    "object {i} uses material {} which does not exist",
                    o.material
                ));
            }
            let check = |s: &Shape| {
                let b = s.bounds();
                b.min.is_finite() && b.max.is_finite()
            };
            if !o.shapes.iter().all(check) {
                return invalid(format!("object {i} has non-finite coordinates"));
            }
            let light = match o.emission {
                Some(e) if e.radiance.max_element() > 0.0 => {
                    if !e.radiance.is_finite() || e.radiance.min_element() < 0.0 {
                        return invalid(format!(
                            "object {i} has an invalid emission {:?}",
                            e.radiance
                        ));
                    }
                    match AreaLight::new(o.shapes.clone(), e.radiance, e.two_sided) {
                        Some(l) => {
                            lights.push(Light::Area(l));
                            (lights.len() - 1) as u32
                        }
                        None => return invalid(format!("emissive object {i} has no area")),
                    }
                }
                _ => NO_LIGHT,
            };
            for (k, s) in o.shapes.into_iter().enumerate() {
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
            }
        }
        let bounds: Vec<_> = shapes.iter().map(Shape::bounds).collect();
        let (bvh, order) = Bvh::build(&bounds);
        let reorder = |v: &[u32]| order.iter().map(|&i| v[i as usize]).collect::<Vec<u32>>();
        let prim_material = reorder(&prim_material);
        let prim_light = reorder(&prim_light);
        let prim_normals = reorder(&prim_normals);
        let shapes = order.iter().map(|&i| shapes[i as usize]).collect();
        let powers: Vec<f64> = lights
            .iter()
            .map(|l| {
                let p = l.power();
                f64::from(p.x + p.y + p.z)
            })
            .collect();
        Ok(Scene {
            name: self.name,
            shapes,
            prim_material,
            prim_light,
            prim_normals,
            vertex_normals,
            materials: self.materials,
            light_choice: Distribution1D::new(&powers),
            lights,
            camera,
            default_resolution: self.resolution,
            bvh,
        })
    }
}
