//! The volume photon map of the two-pass integrator, read along rays by the beam radiance
//! estimate (Jarosz, Zwicker and Jensen 2008, "The Beam Radiance Estimate for Volumetric
//! Photon Mapping"): each photon is a sphere whose radius is the distance to its k-th nearest
//! neighbour (smaller where photons are dense), and a ray collects every photon whose sphere
//! it passes through, weighted by a disc kernel at the photon's distance from the ray.
//!
//! The photons are kept in kd-tree order ([`super::kdtree`]); the same ranges, with bounds
//! grown by each photon's radius, make a bounding-volume hierarchy over the spheres.

use super::VolumePhoton;
use super::kdtree::{self, KdPoint, LEAF};
use crate::math::{Ray, Rgb, Vec3};
use crate::medium::MediumId;
use rayon::prelude::*;

/// A volume photon with the radius of its sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamPhoton {
    pub position: Vec3,
    pub radius: f32,
    /// Unit direction toward where the photon came from.
    pub incoming: Vec3,
    /// Power relative to the map's scale, over σs where it scattered.
    pub power: Rgb,
    pub medium: MediumId,
}

impl KdPoint for BeamPhoton {
    fn position(&self) -> Vec3 {
        self.position
    }
}

/// Volume photons for beam queries.
#[derive(Clone, Debug, Default)]
pub struct VolumePhotonMap {
    photons: Vec<BeamPhoton>,
    /// Bounds of the spheres of each kd-tree range, breadth first (node k's children are
    /// 2k + 1 and 2k + 2); empty ranges have inverted bounds.
    bounds: Vec<(Vec3, Vec3)>,
    /// Watts per unit of stored power.
    pub power_scale: f32,
}

impl VolumePhotonMap {
    /// The map of `photons`, each given the distance to its `k`-th nearest neighbour as its
    /// radius, at most `max_radius` (also the radius of a photon with fewer neighbours within
    /// it, and of every photon when `k` is 0: a fixed radius).
    pub fn build(photons: &[VolumePhoton], k: usize, max_radius: f32, power_scale: f32) -> Self {
        let mut photons: Vec<BeamPhoton> = photons
            .iter()
            .map(|p| BeamPhoton {
                position: p.position,
                radius: max_radius,
                incoming: p.incoming,
                power: p.power,
                medium: p.medium,
            })
            .collect();
        let index = kdtree::build(&mut photons);
        let radii: Vec<f32> = photons
            .par_iter()
            .map(|p| {
                if k == 0 {
                    return max_radius;
                }
                // The photon itself is the nearest: its k-th neighbour is the (k + 1)-th.
                let near = index.nearest(&photons, p.position, k + 1, max_radius * max_radius);
                match near.last() {
                    Some(&(_, d2)) if near.len() > k && d2 > 0.0 => d2.sqrt(),
                    _ => max_radius,
                }
            })
            .collect();
        for (p, r) in photons.iter_mut().zip(radii) {
            p.radius = r;
        }
        let mut bounds = Vec::new();
        fill_bounds(&photons, 0, 0, photons.len(), &mut bounds);
        Self {
            photons,
            bounds,
            power_scale,
        }
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    pub fn photons(&self) -> &[BeamPhoton] {
        &self.photons
    }

    /// Call `f(photon, t, d²)` for every photon whose sphere the segment of `ray` from `t0` to
    /// `t1` passes within its radius, at the point `t` of the ray nearest the photon (inside
    /// the segment), `d` from it. `ray.dir` must be a unit vector.
    pub fn for_each_along(
        &self,
        ray: &Ray,
        t0: f32,
        t1: f32,
        f: &mut impl FnMut(&BeamPhoton, f32, f32),
    ) {
        if self.photons.is_empty() || t1 <= t0 {
            return;
        }
        let inv = Vec3::ONE / ray.dir;
        self.visit(0, 0, self.photons.len(), ray, inv, t0, t1, f);
    }

    #[expect(
        clippy::too_many_arguments,
        reason = "the recursion's range and the ray's query, passed down unchanged"
    )]
    fn visit(
        &self,
        node: usize,
        lo: usize,
        hi: usize,
        ray: &Ray,
        inv: Vec3,
        t0: f32,
        t1: f32,
        f: &mut impl FnMut(&BeamPhoton, f32, f32),
    ) {
        let Some(&(min, max)) = self.bounds.get(node) else {
            return;
        };
        if !slab(min, max, ray.origin, inv, t0, t1) {
            return;
        }
        if hi - lo <= LEAF {
            for p in &self.photons[lo..hi] {
                let t = (p.position - ray.origin).dot(ray.dir);
                if t < t0 || t > t1 {
                    continue;
                }
                let d2 = (p.position - ray.at(t)).length_squared();
                if d2 < p.radius * p.radius {
                    f(p, t, d2);
                }
            }
            return;
        }
        let mid = lo + (hi - lo) / 2;
        self.visit(2 * node + 1, lo, mid, ray, inv, t0, t1, f);
        self.visit(2 * node + 2, mid, hi, ray, inv, t0, t1, f);
    }
}

/// The bounds of every range's spheres, in the kd-tree's own ranges.
fn fill_bounds(
    photons: &[BeamPhoton],
    node: usize,
    lo: usize,
    hi: usize,
    bounds: &mut Vec<(Vec3, Vec3)>,
) -> (Vec3, Vec3) {
    let b = if hi - lo <= LEAF {
        photons[lo..hi].iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(min, max), p| {
                (
                    min.min(p.position - p.radius),
                    max.max(p.position + p.radius),
                )
            },
        )
    } else {
        let mid = lo + (hi - lo) / 2;
        let left = fill_bounds(photons, 2 * node + 1, lo, mid, bounds);
        let right = fill_bounds(photons, 2 * node + 2, mid, hi, bounds);
        (left.0.min(right.0), left.1.max(right.1))
    };
    if bounds.len() <= node {
        bounds.resize(
            node + 1,
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        );
    }
    bounds[node] = b;
    b
}

/// Whether the segment o + t d, t ∈ [t0, t1], meets the box (`inv` = 1/d).
fn slab(min: Vec3, max: Vec3, o: Vec3, inv: Vec3, t0: f32, t1: f32) -> bool {
    let a = (min - o) * inv;
    let b = (max - o) * inv;
    let near = a.min(b).max_element().max(t0);
    let far = a.max(b).min_element().min(t1);
    near <= far
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn a_ray_finds_exactly_the_spheres_it_passes_through() {
        let mut rng = Rng::keyed(5, &[0]);
        let photons: Vec<VolumePhoton> = (0..3000)
            .map(|_| VolumePhoton {
                position: Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
                incoming: Vec3::Y,
                power: Rgb::ONE,
                medium: 0,
                hero_only: false,
            })
            .collect();
        let map = VolumePhotonMap::build(&photons, 8, 0.2, 1.0);
        for _ in 0..50 {
            let o = Vec3::new(-1.0, rng.next_f32(), rng.next_f32());
            let target = Vec3::new(2.0, rng.next_f32(), rng.next_f32());
            let ray = Ray::new(o, (target - o).normalize());
            let (t0, t1) = (1.2, 2.6);
            let mut found = Vec::new();
            map.for_each_along(&ray, t0, t1, &mut |p, _, _| {
                found.push(p.position.to_array())
            });
            let mut expected: Vec<[f32; 3]> = map
                .photons()
                .iter()
                .filter(|p| {
                    let t = (p.position - o).dot(ray.dir);
                    (t0..=t1).contains(&t)
                        && (p.position - ray.at(t)).length_squared() < p.radius * p.radius
                })
                .map(|p| p.position.to_array())
                .collect();
            let key = |a: &[f32; 3], b: &[f32; 3]| a.partial_cmp(b).expect("finite");
            found.sort_by(key);
            expected.sort_by(key);
            assert_eq!(found, expected);
            assert!(!found.is_empty());
        }
        // Radii follow density: with 3000 photons in a unit cube, the 8th neighbour is about
        // (8 / (3000 · 4/3 π))^(1/3) ≈ 0.086 away.
        let mean = map.photons().iter().map(|p| p.radius).sum::<f32>() / map.len() as f32;
        assert!((0.06..0.12).contains(&mean), "mean radius {mean}");
    }
}
