use super::{LightSample, PhotonEmission};
use crate::geometry::{Bounds, Shape, ShapeHit};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::{AliasTable, cosine_hemisphere};
use crate::spectrum::{Lambda, Spectrum};
use crate::texture::{ImageTexture, UvMapping};
use std::f32::consts::PI;
use std::sync::Arc;

/// A diffuse (Lambertian) emitter made of one or more shapes with constant radiance, or
/// radiance times a texture (glTF's emissive textures). One-sided lights emit on the side
/// their normals face.
#[derive(Clone, Debug)]
pub struct AreaLight {
    pub shapes: Vec<Shape>,
    pub radiance: Spectrum,
    pub two_sided: bool,
    area: f32,
    /// Picks a shape by area, in constant time for meshes of any size.
    by_area: AliasTable,
    texture: Option<EmissionTexture>,
    bounds: Bounds,
}

/// A point is near a light when its distance to the light's bounds is below this fraction of
/// the bounds' diagonal. Farther away, r ≥ 0.5 · diagonal, so a light sample's weight
/// L f cos θ cos θ′ A / r² is bounded by 2 L f (A ≤ diagonal² / 2): sampling the light alone
/// is safe. Nearer, r can approach 0 and the estimate needs BSDF samples too.
const NEAR_FRACTION: f32 = 0.5;

/// An emitter's texture and the texture coordinates of its shapes.
#[derive(Clone, Debug)]
struct EmissionTexture {
    image: Arc<ImageTexture>,
    /// The coordinate set, transform and wrap the image is read with.
    mapping: UvMapping,
    /// Per shape, its vertices' coordinates (triangles of meshes with UVs); otherwise the
    /// shape's own parametrisation, as for any texture ([`Shape::uv`]).
    uvs: Option<Vec<[Vec2; 3]>>,
    /// Mean of the texture over each shape, for the light's power.
    power: Rgb,
}

impl AreaLight {
    /// `None` if the shapes have no area.
    pub fn new(shapes: Vec<Shape>, radiance: Spectrum, two_sided: bool) -> Option<Self> {
        let areas: Vec<f64> = shapes.iter().map(|s| f64::from(s.area())).collect();
        let by_area = AliasTable::new(&areas)?;
        let bounds = shapes
            .iter()
            .fold(Bounds::EMPTY, |b, s| b.union(s.bounds()));
        Some(Self {
            bounds,
            area: by_area.total() as f32,
            shapes,
            radiance,
            two_sided,
            by_area,
            texture: None,
        })
    }

    /// The same light with its radiance multiplied by `image` at each point's texture
    /// coordinates (`uvs`: per shape, as the scene keeps them, of the set `mapping` names).
    pub fn with_texture(
        mut self,
        image: Arc<ImageTexture>,
        mapping: UvMapping,
        uvs: Option<Vec<[Vec2; 3]>>,
    ) -> Self {
        let uvs = uvs.filter(|u| u.len() == self.shapes.len());
        let mut texture = EmissionTexture {
            image,
            mapping,
            uvs,
            power: Rgb::ZERO,
        };
        // ∫ texture dA by a fixed stratified grid over each shape (deterministic): 16 × 16 for
        // a few shapes, down to 2 × 2 for meshes of 50k triangles and more (the power only
        // chooses between lights and scales stored photons; photon fluxes use the texture at
        // their own point, so they stay exact).
        let grid = ((200_000.0 / self.shapes.len() as f64).sqrt() as usize).clamp(2, 16);
        let mut sum = Rgb::ZERO;
        for (i, shape) in self.shapes.iter().enumerate() {
            let mut mean = Rgb::ZERO;
            for a in 0..grid {
                for b in 0..grid {
                    let u = Vec2::new(
                        (a as f32 + 0.5) / grid as f32,
                        (b as f32 + 0.5) / grid as f32,
                    );
                    let p = shape.sample_area(u).p;
                    mean += texture.at(shape, i, p);
                }
            }
            sum += mean / (grid * grid) as f32 * shape.area();
        }
        texture.power = sum;
        self.texture = Some(texture);
        self
    }

    /// The radiance factor of a point `p` on shape `i` of the light: the texture there, or 1.
    fn factor(&self, i: usize, p: Vec3) -> Rgb {
        self.texture
            .as_ref()
            .map_or(Rgb::ONE, |t| t.at(&self.shapes[i], i, p))
    }

    /// Whether the radiance varies over the surface (then [`AreaLight::emitted_at`] needs the
    /// hit's texture coordinates).
    pub fn is_textured(&self) -> bool {
        self.texture.is_some()
    }

    /// The texture coordinate set the emission texture reads (0 when there is none).
    pub fn texture_uv_set(&self) -> u8 {
        self.texture.as_ref().map_or(0, |t| t.mapping.set)
    }

    /// Radiance leaving a point with normal `n` and texture coordinates `uv` (of the set
    /// [`AreaLight::texture_uv_set`] names) in direction `w`.
    pub fn emitted_at(&self, n: Vec3, w: Vec3, uv: Vec2, lambda: &Lambda) -> Rgb {
        match &self.texture {
            Some(t) if self.faces(n, w) => self.radiance_times(t.read(uv), lambda),
            _ => self.emitted(n, w, lambda),
        }
    }

    /// The radiance times the texture's `factor` (1 untextured) at the path's channels: the
    /// light's own spectrum untextured, a texel's colour upsampled as an illuminant.
    fn radiance_times(&self, factor: Rgb, lambda: &Lambda) -> Rgb {
        match self.texture {
            None => lambda.spectrum(&self.radiance),
            Some(_) => lambda.illuminant(self.radiance.rgb() * factor),
        }
    }

    /// Whether the light emits from a point with normal `n` toward `w`.
    fn faces(&self, n: Vec3, w: Vec3) -> bool {
        self.two_sided || n.dot(w) > 0.0
    }

    /// Whether `p` is close enough for sampling the light alone to have unbounded variance
    /// (see [`NEAR_FRACTION`]).
    pub fn is_near(&self, p: Vec3) -> bool {
        let outside = (self.bounds.min - p)
            .max(p - self.bounds.max)
            .max(Vec3::ZERO);
        outside.length() < NEAR_FRACTION * self.bounds.extent().length()
    }

    pub fn area(&self) -> f32 {
        self.area
    }

    /// Φ = π ∫ L dA for one side (π A L untextured).
    pub fn power(&self) -> Rgb {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        match &self.texture {
            Some(t) => self.radiance.rgb() * t.power * (PI * sides),
            None => self.radiance.rgb() * (PI * self.area * sides),
        }
    }

    /// Radiance leaving a point with normal `n` in direction `w`.
    pub fn emitted(&self, n: Vec3, w: Vec3, lambda: &Lambda) -> Rgb {
        if self.faces(n, w) {
            lambda.spectrum(&self.radiance)
        } else {
            Rgb::ZERO
        }
    }

    /// Uniform point on the area (density 1/A), cosine-weighted direction (density cos θ/π) on
    /// the emitting side, or on a side chosen at random for two-sided lights: every photon
    /// carries flux L·cos θ / (cos θ/π · 1/A) = π A L (L at its point), times two for
    /// two-sided lights.
    pub fn emit(
        &self,
        u_pick: f32,
        u_pos: Vec2,
        u_dir: Vec2,
        lambda: &Lambda,
    ) -> Option<PhotonEmission> {
        let (i, rest) = self.by_area.sample(u_pick);
        let s = self.shapes[i].sample_area(u_pos);
        let (normal, sides) = if self.two_sided {
            (if rest < 0.5 { s.n } else { -s.n }, 2.0)
        } else {
            (s.n, 1.0)
        };
        let local = cosine_hemisphere(u_dir);
        if local.z <= 0.0 {
            return None;
        }
        Some(PhotonEmission {
            origin: s.p,
            dir: Frame::from_normal(normal).to_world(local),
            normal: s.n,
            error: s.error,
            flux: self.radiance_times(self.factor(i, s.p), lambda)
                * (std::f32::consts::PI * self.area * sides),
        })
    }

    /// Uniform point on the light's area, then converted to a solid-angle density at `p`.
    /// Density with which [`AreaLight::emit`] sends a photon from a point of normal `n` in
    /// direction `w`: uniform by area, cosine-weighted about the side it leaves (a
    /// two-sided light picks a side with probability ½).
    pub fn pdf_emit(&self, n: Vec3, w: Vec3) -> f32 {
        let cos = n.dot(w);
        let sides = if self.two_sided {
            0.5
        } else if cos <= 0.0 {
            return 0.0;
        } else {
            1.0
        };
        sides * cos.abs() / (PI * self.area)
    }

    pub fn sample_li(&self, p: Vec3, u_pick: f32, u: Vec2, lambda: &Lambda) -> Option<LightSample> {
        let (i, _) = self.by_area.sample(u_pick);
        let s = self.shapes[i].sample_area(u);
        let d = s.p - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let wi = d / dist2.sqrt();
        if !self.faces(s.n, -wi) {
            return None;
        }
        let radiance = self.radiance_times(self.factor(i, s.p), lambda);
        if radiance == Rgb::ZERO {
            return None;
        }
        let pdf = self.pdf_li(p, s.p, s.n);
        (pdf > 0.0 && pdf.is_finite()).then_some(LightSample {
            wi,
            radiance,
            pdf,
            point: s.p,
            normal: s.n,
            error: s.error,
            is_delta: false,
        })
    }

    /// Solid-angle density with which [`AreaLight::sample_li`] picks the point `q` (normal `n`)
    /// as seen from `p`: the area density 1/A converted by distance² / |cos θ_light|.
    pub fn pdf_li(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        let d = q - p;
        let dist2 = d.length_squared();
        let cos = (n.dot(d) / dist2.sqrt()).abs();
        if cos == 0.0 {
            return 0.0;
        }
        dist2 / (cos * self.area)
    }
}

impl EmissionTexture {
    /// The image at coordinates `uv` of the mapping's set, transformed and wrapped.
    fn read(&self, uv: Vec2) -> Rgb {
        self.image.eval_wrapped(
            self.mapping.transform.transform_point2(uv),
            self.mapping.wrap,
        )
    }

    /// The texture at point `p` of shape `i`.
    fn at(&self, shape: &Shape, i: usize, p: Vec3) -> Rgb {
        let bary = match shape {
            Shape::Triangle(t) => t.barycentrics(p),
            _ => Vec2::ZERO,
        };
        let uv = match &self.uvs {
            Some(uvs) => {
                let [a, b, c] = uvs[i];
                (1.0 - bary.x - bary.y) * a + bary.x * b + bary.y * c
            }
            None => shape.uv(&ShapeHit { t: 0.0, uv: bary }, p),
        };
        self.read(uv)
    }
}
