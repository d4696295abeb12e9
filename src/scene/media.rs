//! Rays through participating media: which medium a ray is in, what it meets next (a
//! scattering point in a medium or a surface, past the invisible boundaries between media),
//! and the transmittance of a shadow ray.
//!
//! A path carries the medium it is in. It starts in the medium around the camera or its light:
//! the scene's atmosphere, or the inside of the boundary they are in (found when the scene is
//! built, as Cycles finds the volume a camera is in; pbrt-v4 and Mitsuba 3 ask the scene file
//! to say it). Crossing a [`Boundary`] puts it in the medium on the side it goes to, and any
//! other surface leaves it where it was (pbrt-v4's rule, also Mitsuba 3's `volpath`).

use super::Scene;
use crate::math::{Ray, Rgb, Vec3, offset_origin, segment_reach};
use crate::medium::{Boundary, Medium, MediumId};
use crate::sampling::Sampler;
use crate::spectrum::Lambda;

use super::Hit;

/// How many invisible boundaries one ray may cross before it is taken as lost: a bound on
/// the work of a ray that grazes along a boundary's seam.
pub const MAX_CROSSINGS: u32 = 64;

/// The directions [`Scene::medium_at`] probes along: not along an axis, so that a probe does
/// not run along the faces of axis-aligned boxes, and three of them, so that one slipping
/// through a seam of a boundary's mesh is outvoted.
const PROBES: [[f32; 3]; 3] = [[1.0, 2.0, 3.0], [-3.0, 1.0, 2.0], [2.0, -3.0, -1.0]];

/// What a ray meets next.
#[derive(Clone, Copy, Debug)]
pub enum Interaction {
    /// A surface that is there, reached through `medium` (the medium on the side the ray came
    /// from).
    Surface { hit: Hit, medium: Option<MediumId> },
    /// A scattering point at `p` in `medium`.
    Scatter { p: Vec3, medium: MediumId },
    /// Nothing: the ray left the scene.
    Escaped,
}

/// [`Interaction`] with the factor the path's throughput takes on the way: transmittance
/// over the density of the distance chosen, times σs at a scattering point (see
/// [`Medium::sample_free_flight`]), and each channel's density of the distances chosen
/// over the hero channel's, `ratio` (both exactly one in vacuum). `crossings` counts the
/// boundaries crossed, each one more ray traced. `scattering_piece` is the first stretch of
/// the ray through a medium that scatters, if it has one.
#[derive(Clone, Copy, Debug)]
pub struct Step {
    pub interaction: Interaction,
    pub weight: Rgb,
    pub ratio: Rgb,
    pub crossings: u32,
    pub scattering_piece: Option<ScatteringPiece>,
}

/// The first stretch of a ray through a medium that scatters, between two surfaces (visible
/// or not): the ray from where it starts, the distance along it to where it ends (infinite if
/// it leaves the scene), its medium, the boundaries crossed before it, and the transmittance
/// of the media before it (which only absorb, or it would not be the first).
#[derive(Clone, Copy, Debug)]
pub struct ScatteringPiece {
    pub ray: Ray,
    pub t_max: f32,
    pub medium: MediumId,
    pub crossings: u32,
    pub transmittance_before: Rgb,
}

impl Scene {
    /// Whether the scene has any medium or boundary: only then do rays need more than
    /// [`Scene::intersect`] and [`Scene::occluded`].
    #[inline]
    pub fn has_media(&self) -> bool {
        !self.media.is_empty() || !self.prim_boundary.is_empty()
    }

    /// The medium that fills the scene around its shapes, where the camera and the point,
    /// spot and distant lights are.
    pub fn atmosphere(&self) -> Option<MediumId> {
        self.atmosphere
    }

    /// The medium the camera is in (see [`Scene::medium_at`]).
    pub fn camera_medium(&self) -> Option<MediumId> {
        self.camera_medium
    }

    /// The medium light `i` emits into (see [`Scene::medium_at`]): distant lights are in the
    /// atmosphere; a point or spot light in the medium at its position; a shape light in the
    /// medium just in front of its first shape (a light across a boundary takes that side's).
    pub fn light_medium(&self, i: usize) -> Option<MediumId> {
        self.light_media.get(i).copied().unwrap_or(self.atmosphere)
    }

    /// The medium at the point `p`: that on `p`'s side of the first boundary a ray from `p`
    /// meets (media do not nest, so the nearest boundary decides), or the atmosphere where no
    /// ray meets one; the answer of most of three rays.
    pub fn medium_at(&self, p: Vec3) -> Option<MediumId> {
        if self.prim_boundary.is_empty() {
            return self.atmosphere;
        }
        let [a, b, c] = PROBES.map(|d| self.medium_along(p, Vec3::from_array(d).normalize()));
        if a != b && b == c { b } else { a }
    }

    /// The medium at `p` as seen along `dir`: that on `p`'s side of the first boundary hit.
    fn medium_along(&self, p: Vec3, dir: Vec3) -> Option<MediumId> {
        let mut origin = p;
        for _ in 0..=MAX_CROSSINGS {
            let Some(hit) = self.intersect(&Ray::new(origin, dir), f32::INFINITY) else {
                return self.atmosphere;
            };
            if let Some(b) = self.boundary(hit.prim) {
                return if dir.dot(hit.ng) > 0.0 {
                    b.inside
                } else {
                    b.outside
                };
            }
            origin = hit.offset_origin(dir);
        }
        self.atmosphere
    }

    /// Finds the media of the camera and of every light ([`Scene::camera_medium`],
    /// [`Scene::light_medium`]); part of building a scene.
    pub(super) fn locate_camera_and_lights_in_media(&mut self) {
        self.camera_medium = self.medium_at(self.camera.position);
        let light_media = self
            .lights
            .iter()
            .map(|light| match light {
                crate::light::Light::Point(l) => self.medium_at(l.position),
                crate::light::Light::Spot(l) => self.medium_at(l.position),
                crate::light::Light::Area(l) => {
                    let s = l.shapes[0].sample_area(crate::math::Vec2::splat(0.5));
                    self.medium_at(offset_origin(s.p, s.error, s.n, s.n))
                }
                crate::light::Light::Directional(_) | crate::light::Light::Environment(_) => {
                    self.atmosphere
                }
            })
            .collect();
        self.light_media = light_media;
    }

    pub fn medium(&self, id: MediumId) -> &Medium {
        &self.media[id as usize]
    }

    pub fn media(&self) -> &[Medium] {
        &self.media
    }

    /// The hero channel a path draws its distances with (see [`crate::medium`]): drawn from
    /// `sampler` in a scene with media; channel 0, drawing nothing, in one without, so that
    /// its paths use the random numbers they always did.
    pub fn draw_hero_channel(&self, sampler: &mut impl Sampler) -> usize {
        if self.has_media() {
            crate::medium::hero_channel(sampler.next_f32())
        } else {
            0
        }
    }

    /// The boundary a primitive is part of, if any.
    #[inline]
    pub fn boundary(&self, prim: u32) -> Option<&Boundary> {
        self.prim_boundary
            .get(prim as usize)
            .filter(|b| b.inside.is_some() || b.outside.is_some() || b.invisible)
    }

    /// Whether a hit is on an invisible boundary, which rays cross unchanged.
    #[inline]
    pub fn is_invisible(&self, hit: &Hit) -> bool {
        self.boundary(hit.prim).is_some_and(|b| b.invisible)
    }

    /// The medium a ray leaving `hit` in direction `w` is in, for a path that reached the hit
    /// through `current`.
    #[inline]
    pub fn medium_after(&self, hit: &Hit, current: Option<MediumId>, w: Vec3) -> Option<MediumId> {
        match self.boundary(hit.prim) {
            Some(b) if w.dot(hit.ng) > 0.0 => b.outside,
            Some(b) => b.inside,
            None => current,
        }
    }

    /// The next interaction along `ray`, which starts in `medium`: a distance is sampled in
    /// each medium crossed, at the path's channels `lambda`, with its `hero` channel (media
    /// that only absorb take their transmittance instead), and invisible boundaries are
    /// crossed.
    pub fn next_interaction(
        &self,
        ray: &Ray,
        mut medium: Option<MediumId>,
        (hero, lambda): (usize, &Lambda),
        sampler: &mut impl Sampler,
    ) -> Step {
        let mut weight = Rgb::ONE;
        let mut ratio = Rgb::ONE;
        let mut ray = *ray;
        let mut scattering_piece = None;
        for crossings in 0..=MAX_CROSSINGS {
            let hit = self.intersect(&ray, f32::INFINITY);
            if let Some(id) = medium {
                let m = self.medium(id).at(lambda);
                let t_max = hit.map_or(f32::INFINITY, |h| h.t);
                if self.medium(id).scatters() {
                    scattering_piece.get_or_insert(ScatteringPiece {
                        ray,
                        t_max,
                        medium: id,
                        crossings,
                        transmittance_before: weight,
                    });
                    let flight = m.sample_free_flight(&ray, t_max, hero, sampler);
                    weight *= flight.weight;
                    ratio *= flight.ratio;
                    if flight.scattered {
                        return Step {
                            interaction: Interaction::Scatter {
                                p: ray.at(flight.t),
                                medium: id,
                            },
                            weight,
                            ratio,
                            crossings,
                            scattering_piece,
                        };
                    }
                } else {
                    weight *= m.transmittance(&ray, t_max, sampler);
                }
            }
            let Some(hit) = hit else {
                return Step {
                    interaction: Interaction::Escaped,
                    weight,
                    ratio,
                    crossings,
                    scattering_piece,
                };
            };
            if !self.is_invisible(&hit) {
                return Step {
                    interaction: Interaction::Surface { hit, medium },
                    weight,
                    ratio,
                    crossings,
                    scattering_piece,
                };
            }
            medium = self.medium_after(&hit, medium, ray.dir);
            ray = Ray::new(hit.offset_origin(ray.dir), ray.dir);
        }
        Step {
            interaction: Interaction::Escaped,
            weight: Rgb::ZERO,
            ratio: Rgb::ONE,
            crossings: MAX_CROSSINGS,
            scattering_piece,
        }
    }

    /// The fraction of light that travels from `origin`, in `medium`, to `target`: zero if a
    /// surface is in the way, else the product of the media's transmittances over the
    /// segments between the invisible boundaries crossed (estimated with `sampler` in grids),
    /// at the path's channels `lambda`.
    pub fn transmittance(
        &self,
        origin: Vec3,
        target: Vec3,
        mut medium: Option<MediumId>,
        lambda: &Lambda,
        sampler: &mut impl Sampler,
    ) -> Rgb {
        let mut tr = Rgb::ONE;
        let mut from = origin;
        for _ in 0..=MAX_CROSSINGS {
            let d = target - from;
            let dist = d.length();
            if dist.is_nan() || dist <= 0.0 {
                return tr;
            }
            let ray = Ray::new(from, d / dist);
            let hit = self.intersect(&ray, segment_reach(from, target, dist));
            let travelled = hit.map_or(dist, |h| h.t);
            if let Some(id) = medium {
                tr *= self
                    .medium(id)
                    .at(lambda)
                    .transmittance(&ray, travelled, sampler);
            }
            match hit {
                None => return tr,
                Some(h) if self.is_invisible(&h) => {
                    medium = self.medium_after(&h, medium, ray.dir);
                    from = h.offset_origin(ray.dir);
                }
                Some(_) => return Rgb::ZERO,
            }
            if tr == Rgb::ZERO {
                return tr;
            }
        }
        Rgb::ZERO
    }
}
