//! Light from point and spot lights scattered once along a ray's stretch through a
//! homogeneous medium, sampled by distance toward the light: equiangular sampling (Kulla and
//! Fajardo 2012, §3), combined with free-flight scattering and its light samples by multiple
//! importance sampling (power heuristic).
//!
//! Free flight draws scattering distances by transmittance alone, so its light samples of a
//! point light at distance r score ∝ 1/r² at points spread evenly along the ray: their
//! variance diverges near the light (∫ r⁻⁴ r² dr). Equiangular sampling draws the distance
//! by that 1/r² instead; a ray passing at distance h from the light then scores ∝ 1/h, whose
//! variance diverges only logarithmically as h → 0.
//!
//! Both techniques make the same path (the stretch's start, a scattering point at t, the
//! light) with densities
//! - free flight: mean over channels k of ratio_k · σt_k · Tr_k(t), over mean(ratio), where
//!   ratio is the path's channel densities over its hero channel's before the ray (the
//!   spectral MIS of [`crate::medium`]: a free-flight contribution is divided by the mean of
//!   the ratios after the step);
//! - equiangular: the distribution's p(t), the same for every channel.
//!
//! Both choose lights alike ([`LightsSampled`]), so the choice cancels in the weights. Lights
//! with an area and directional lights are left to free flight alone (weight 1). Only the
//! ray's first stretch in a medium that scatters is sampled so: free flight's scattering
//! points beyond it keep weight 1.

use super::RayStats;
use super::lighting::power_heuristic;
use crate::light::Light;
use crate::math::{Rgb, Vec2, Vec3};
use crate::medium::Medium;
use crate::sampling::{Equiangular, Sampler};
use crate::scene::{ScatteringPiece, Scene, Step};
use crate::spectrum::Lambda;

/// How an integrator's light samples at a scattering point choose lights.
#[derive(Clone, Copy, Debug)]
pub(crate) enum LightsSampled {
    /// One light, chosen by power ([`super::lighting::one_light_in_medium`]).
    OneByPower,
    /// Every light ([`super::lighting::direct_light_in_medium`]).
    Each,
}

/// A ray's first stretch through a medium that scatters ([`ScatteringPiece`]), where that
/// medium is homogeneous, and the path's channel ratios before the ray.
pub(crate) struct MediumSegment {
    piece: ScatteringPiece,
    sigma_t: Rgb,
    sigma_s: Rgb,
    ratio: Rgb,
}

impl MediumSegment {
    /// The stretch of `step` to sample distances on toward point lights, if there is one:
    /// its medium is homogeneous, and the scene has a point or spot light. `ratio`: the
    /// path's channel ratios before the step.
    pub fn new(scene: &Scene, step: &Step, lambda: &Lambda, ratio: Rgb) -> Option<Self> {
        let piece = step.scattering_piece?;
        let m = scene.medium(piece.medium);
        if !matches!(m, Medium::Homogeneous(_)) || scene.point_lights().is_empty() {
            return None;
        }
        let c = m.at(lambda).coefficients();
        Some(Self {
            piece,
            sigma_t: c.sigma_t(),
            sigma_s: c.sigma_s,
            ratio,
        })
    }

    fn toward(&self, light: Vec3) -> Option<Equiangular> {
        let ray = &self.piece.ray;
        Equiangular::new(ray.origin, ray.dir, light, self.piece.t_max)
    }

    /// Free flight's density of scattering at distance `t`, as the path's channels mix it.
    fn free_flight_pdf(&self, t: f32) -> f32 {
        let density = |k: usize| {
            let s = self.sigma_t.to_array()[k];
            self.ratio.to_array()[k] * s * (-s * t).exp()
        };
        (density(0) + density(1) + density(2)) / (self.ratio.x + self.ratio.y + self.ratio.z)
    }

    /// Free flight's scattering point `p` of `step`, if it lies on the stretch (no boundary
    /// lies between them).
    pub fn free_flight_point(&self, step: &Step, p: Vec3) -> Option<FreeFlightPoint<'_>> {
        let ray = &self.piece.ray;
        (step.crossings == self.piece.crossings).then(|| FreeFlightPoint {
            segment: self,
            t: (p - ray.origin).dot(ray.dir),
        })
    }

    /// Equiangular samples of the point and spot lights, chosen as the caller's light samples
    /// at a scattering point choose theirs (so that a light's choice leaves the weights
    /// alike); see [`MediumSegment::single_scattering_from`].
    pub fn single_scattering(
        &self,
        scene: &Scene,
        lights: LightsSampled,
        lambda: &Lambda,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Rgb {
        match lights {
            LightsSampled::OneByPower => {
                let u_choose = rng.next_f32();
                let Some((i, pmf, _)) = scene.choose_light(u_choose) else {
                    return Rgb::ZERO;
                };
                if scene.lights()[i].point_position().is_none() {
                    return Rgb::ZERO;
                }
                self.single_scattering_from(scene, i, lambda, rng, stats) / pmf
            }
            LightsSampled::Each => scene
                .point_lights()
                .iter()
                .map(|&i| self.single_scattering_from(scene, i as usize, lambda, rng, stats))
                .sum(),
        }
    }

    /// One equiangular sample of light `i` (a point or spot light): a distance drawn toward it,
    /// its light scattered there toward the ray's start (transmittance both ways and before the
    /// stretch, σs, the phase function), MIS-weighted against free flight. The path's
    /// throughput and spectral MIS factor before the ray are the caller's to apply.
    fn single_scattering_from(
        &self,
        scene: &Scene,
        i: usize,
        lambda: &Lambda,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Rgb {
        let u_distance = rng.next_f32();
        let light = &scene.lights()[i];
        let Some(distances) = light.point_position().and_then(|q| self.toward(q)) else {
            return Rgb::ZERO;
        };
        let t = distances.sample(u_distance);
        let pdf = distances.pdf(t);
        if pdf <= 0.0 || !t.is_finite() {
            return Rgb::ZERO;
        }
        let ray = &self.piece.ray;
        let p = ray.at(t);
        let Some(ls) = light.sample_li(p, 0.0, Vec2::ZERO, lambda) else {
            return Rgb::ZERO;
        };
        let medium = self.piece.medium;
        let phase = scene.medium(medium).phase().eval(-ray.dir, ls.wi);
        if phase == 0.0 || ls.radiance == Rgb::ZERO {
            return Rgb::ZERO;
        }
        stats.shadow += 1;
        let to_light = scene.transmittance(p, ls.point, Some(medium), lambda, rng);
        if to_light == Rgb::ZERO {
            return Rgb::ZERO;
        }
        let to_start = self.piece.transmittance_before
            * Rgb::new(
                (-self.sigma_t.x * t).exp(),
                (-self.sigma_t.y * t).exp(),
                (-self.sigma_t.z * t).exp(),
            );
        let weight = power_heuristic(pdf, self.free_flight_pdf(t));
        to_start * self.sigma_s * to_light * ls.radiance * (phase * weight / pdf)
    }
}

/// A scattering point free flight found on a [`MediumSegment`], at distance `t` along it.
#[derive(Clone, Copy)]
pub(crate) struct FreeFlightPoint<'a> {
    segment: &'a MediumSegment,
    t: f32,
}

impl FreeFlightPoint<'_> {
    /// The weight of a light sample of `light` taken here: against the stretch's distances
    /// drawn toward it if it is a point or spot light, 1 otherwise.
    pub fn weight(&self, light: &Light) -> f32 {
        let Some(position) = light.point_position() else {
            return 1.0;
        };
        let p_equiangular = self.segment.toward(position).map_or(0.0, |d| d.pdf(self.t));
        power_heuristic(self.segment.free_flight_pdf(self.t), p_equiangular)
    }
}
