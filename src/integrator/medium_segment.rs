//! Light from point and spot lights scattered once along a path's segment through a
//! homogeneous medium, sampled by distance toward the light: equiangular sampling (Kulla and
//! Fajardo 2012, §3), combined with the path tracer's own free-flight scattering and
//! next-event estimation by multiple importance sampling (power heuristic).
//!
//! Free flight draws scattering distances by transmittance, so a segment that passes close
//! to a point light rarely scatters where its 1/r² is large: a lamp in fog made `path`'s
//! error heavy-tailed. Equiangular sampling draws the distance by that 1/r² instead.
//!
//! Both techniques make the same path (the segment's start, a scattering point at t, the
//! light) with densities
//! - free flight: mean over channels k of ratio_k · σt_k · Tr_k(t), over mean(ratio), where
//!   ratio is the path's channel densities over its hero channel's before the segment (the
//!   spectral MIS of [`crate::medium`]: a free-flight contribution is divided by the mean of
//!   the ratios after the step);
//! - equiangular: the distribution's p(t), the same for every channel.
//!
//! Both choose the light by power, so that factor cancels in the weights. Lights with an area
//! and directional lights are left to free flight alone (weight 1).

use super::RayStats;
use super::lighting::power_heuristic;
use crate::math::{Ray, Rgb, Vec2, Vec3};
use crate::medium::{Medium, MediumId};
use crate::sampling::{Equiangular, Sampler};
use crate::scene::{Scene, Step};
use crate::spectrum::Lambda;

/// A segment of a path in one homogeneous medium that scatters: from `ray.origin` to the
/// first surface at `t_max` (infinite if none), and the path's channel ratios as it began.
pub(crate) struct MediumSegment {
    ray: Ray,
    t_max: f32,
    medium: MediumId,
    sigma_t: Rgb,
    sigma_s: Rgb,
    ratio: Rgb,
}

impl MediumSegment {
    /// The segment along `ray` in `medium` up to `t_max`, if equiangular sampling applies:
    /// the medium is homogeneous and scatters, and the scene has a point or spot light.
    pub fn new(
        scene: &Scene,
        ray: &Ray,
        medium: Option<MediumId>,
        t_max: f32,
        lambda: &Lambda,
        ratio: Rgb,
    ) -> Option<Self> {
        let id = medium?;
        let m = scene.medium(id);
        if !matches!(m, Medium::Homogeneous(_)) || !m.scatters() || scene.point_lights().is_empty()
        {
            return None;
        }
        let c = m.at(lambda).coefficients();
        Some(Self {
            ray: *ray,
            t_max,
            medium: id,
            sigma_t: c.sigma_t(),
            sigma_s: c.sigma_s,
            ratio,
        })
    }

    fn toward(&self, light: Vec3) -> Option<Equiangular> {
        Equiangular::new(self.ray.origin, self.ray.dir, light, self.t_max)
    }

    /// Free flight's density of scattering at distance `t`, as the path's channels mix it.
    fn free_flight_pdf(&self, t: f32) -> f32 {
        let density = |k: usize| {
            let s = self.sigma_t.to_array()[k];
            self.ratio.to_array()[k] * s * (-s * t).exp()
        };
        (density(0) + density(1) + density(2)) / (self.ratio.x + self.ratio.y + self.ratio.z)
    }

    /// The segment and the distance along it of the scattering point `p` that free flight
    /// found in `step`, if it lies on this segment: the step crossed no boundary before it.
    pub fn reached_by_free_flight(&self, step: &Step, p: Vec3) -> Option<(&Self, f32)> {
        (step.crossings == 0).then(|| (self, (p - self.ray.origin).dot(self.ray.dir)))
    }

    /// The weight of free flight's scattering at distance `t` followed by a light sample of
    /// the point light at `light`.
    pub fn free_flight_weight(&self, light: Vec3, t: f32) -> f32 {
        let p_equiangular = self.toward(light).map_or(0.0, |d| d.pdf(t));
        power_heuristic(self.free_flight_pdf(t), p_equiangular)
    }

    /// One equiangular sample of a light chosen by power (if it shines from a point): see
    /// [`MediumSegment::single_scattering_from`]. Free flight's light samples choose the same
    /// way, so the choice's probability leaves the weights alike.
    pub fn single_scattering_by_power(
        &self,
        scene: &Scene,
        lambda: &Lambda,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Rgb {
        let u_choose = rng.next_f32();
        let Some((i, pmf, _)) = scene.choose_light(u_choose) else {
            return Rgb::ZERO;
        };
        if scene.lights()[i].point_position().is_none() {
            return Rgb::ZERO;
        }
        self.single_scattering_from(scene, i, lambda, rng, stats) / pmf
    }

    /// One equiangular sample of every point and spot light, for integrators whose light
    /// samples at a scattering point take every light ([`super::lighting::direct_light_in_medium`]).
    pub fn single_scattering_from_each(
        &self,
        scene: &Scene,
        lambda: &Lambda,
        rng: &mut impl Sampler,
        stats: &mut RayStats,
    ) -> Rgb {
        scene
            .point_lights()
            .iter()
            .map(|&i| self.single_scattering_from(scene, i as usize, lambda, rng, stats))
            .sum()
    }

    /// One equiangular sample of light `i` (a point or spot light): a distance drawn toward it,
    /// its light scattered there toward the segment's start (transmittance both ways, σs,
    /// the phase function), MIS-weighted against free flight. The path's throughput and
    /// spectral MIS factor before the segment are the caller's to apply.
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
        let p = self.ray.at(t);
        let Some(ls) = light.sample_li(p, 0.0, Vec2::ZERO, lambda) else {
            return Rgb::ZERO;
        };
        let phase = scene.medium(self.medium).phase().eval(-self.ray.dir, ls.wi);
        if phase == 0.0 || ls.radiance == Rgb::ZERO {
            return Rgb::ZERO;
        }
        stats.shadow += 1;
        let to_light = scene.transmittance(p, ls.point, Some(self.medium), lambda, rng);
        if to_light == Rgb::ZERO {
            return Rgb::ZERO;
        }
        let along = Rgb::new(
            (-self.sigma_t.x * t).exp(),
            (-self.sigma_t.y * t).exp(),
            (-self.sigma_t.z * t).exp(),
        );
        let weight = power_heuristic(pdf, self.free_flight_pdf(t));
        along * self.sigma_s * to_light * ls.radiance * (phase * weight / pdf)
    }
}
