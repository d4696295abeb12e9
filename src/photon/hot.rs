//! Bright, small secondary sources for final gathering: the regions whose precomputed
//! irradiance is far above the scene's, grouped into clusters that gather rays can aim at.
//!
//! A light strip mounted a few millimetres below a ceiling lights the ceiling beside it
//! hundreds of times more than anything else. Cosine-distributed gather rays find that thin
//! band rarely, and each one that does brings back a huge value: speckles over the whole
//! indirect image. Aiming some gather rays at the band (uniformly in the cone around each
//! cluster's bounding sphere), and weighting every ray by the balance heuristic over both
//! strategies (Veach 1997, §9.2), removes the speckles without bias: where there is no hot
//! region, nothing changes.

use crate::math::{Frame, Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// A cache site counts as hot above this multiple of the mean irradiance of all sites.
pub const HOT_FACTOR: f32 = 16.0;
/// At most this many clusters (so a shading point's choice fits in a fixed array).
pub const MAX_CLUSTERS: usize = 32;
/// Clusters are split until their bounding sphere's radius is below this fraction of the
/// scene's diagonal (or the cluster budget is spent).
const CLUSTER_RADIUS: f32 = 0.01;
/// No cluster is smaller than this fraction of the scene's diagonal (one site, or sites at one
/// point, would make a cone narrower than f32 directions resolve).
const MIN_RADIUS: f32 = 1e-3;
/// Cones are at least this wide (1 − cos of the half-angle; about 1.4 mrad).
const MIN_ONE_MINUS_COS: f32 = 1e-6;

/// A group of hot sites: where to aim, and roughly how much light falls on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HotCluster {
    pub center: Vec3,
    pub radius: f32,
    /// Flux arriving on the cluster's surface (luminance, W): each site stands for the same
    /// number of photons, so this is its site count times the flux per site.
    pub flux: f32,
}

/// Rays aim at hot regions only where they are estimated to bring at least this share of the
/// scene's mean irradiance; elsewhere (most of a scene whose only hot region is a small
/// caustic) halving the cosine rays would only add noise.
pub const MIN_SHARE: f32 = 0.25;

/// Group hot sites (position) of `flux_per_site` each by splitting at the median of the longest
/// axis, largest cluster first, until every cluster is small or there are `MAX_CLUSTERS`.
pub fn clusters(mut sites: Vec<Vec3>, flux_per_site: f32, scene_diagonal: f32) -> Vec<HotCluster> {
    if sites.is_empty() {
        return Vec::new();
    }
    let small = CLUSTER_RADIUS * scene_diagonal;
    let mut ranges = vec![(0usize, sites.len())];
    while ranges.len() < MAX_CLUSTERS {
        // The widest range that can still be split.
        let Some((i, _)) = ranges
            .iter()
            .enumerate()
            .filter(|(_, r)| r.1 - r.0 > 1)
            .map(|(i, r)| (i, bounds(&sites[r.0..r.1])))
            .filter(|(_, b)| (b.1 - b.0).length() * 0.5 > small)
            .max_by(|a, b| {
                let ea = (a.1.1 - a.1.0).length();
                let eb = (b.1.1 - b.1.0).length();
                ea.total_cmp(&eb)
            })
        else {
            break;
        };
        let (lo, hi) = ranges[i];
        let (min, max) = bounds(&sites[lo..hi]);
        let axis = (max - min).max_position();
        let mid = lo + (hi - lo) / 2;
        sites[lo..hi].select_nth_unstable_by(mid - lo, |a, b| a[axis].total_cmp(&b[axis]));
        ranges[i] = (lo, mid);
        ranges.push((mid, hi));
    }
    ranges
        .into_iter()
        .map(|(lo, hi)| {
            let part = &sites[lo..hi];
            let (min, max) = bounds(part);
            let center = (min + max) * 0.5;
            let radius = part
                .iter()
                .map(|s| (*s - center).length())
                .fold(0.0f32, f32::max)
                .max(MIN_RADIUS * scene_diagonal);
            HotCluster {
                center,
                radius,
                flux: part.len() as f32 * flux_per_site,
            }
        })
        .collect()
}

fn bounds(sites: &[Vec3]) -> (Vec3, Vec3) {
    sites.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &s| (lo.min(s), hi.max(s)),
    )
}

/// The cone from a shading point around one cluster's bounding sphere.
#[derive(Clone, Copy, Debug, Default)]
struct Cone {
    frame_axis: Vec3,
    /// 1 − cos of the half-angle, kept apart from cos for precision with tiny cones.
    one_minus_cos: f32,
    probability: f32,
}

/// Directions toward the hot clusters as seen from one shading point.
#[derive(Clone, Debug)]
pub struct HotSampler {
    cones: [Cone; MAX_CLUSTERS],
    count: usize,
}

impl HotSampler {
    /// Cones toward the clusters above the surface at `p` (normal `n`), chosen in proportion
    /// to the irradiance each would give if it reflected all its light toward `p` (Φ/π ·
    /// cos / d²). `None` if those add up to less than `MIN_SHARE` of `irradiance` (the
    /// scene's mean), or no cluster is above the surface.
    pub fn new(clusters: &[HotCluster], p: Vec3, n: Vec3, irradiance: f32) -> Option<Self> {
        // A cheap bound first (every cluster facing `p`): most points of a scene whose hot
        // regions are small and far need nothing more.
        let bound: f32 = clusters
            .iter()
            .map(|c| c.flux * FRAC_1_PI / (c.center - p).length_squared().max(c.radius * c.radius))
            .sum();
        if bound.is_nan() || bound < MIN_SHARE * irradiance {
            return None;
        }
        let mut cones = [Cone::default(); MAX_CLUSTERS];
        let mut count = 0;
        let mut total = 0.0;
        for c in clusters.iter().take(MAX_CLUSTERS) {
            let d = c.center - p;
            let dist2 = d.length_squared();
            let dist = dist2.sqrt();
            if d.dot(n) <= -c.radius || dist == 0.0 {
                continue;
            }
            let axis = d / dist;
            let sin2 = c.radius * c.radius / dist2;
            // Inside the bounding sphere the cone is the whole sphere.
            let one_minus_cos = if sin2 >= 1.0 {
                2.0
            } else {
                (sin2 / (1.0 + (1.0 - sin2).sqrt())).max(MIN_ONE_MINUS_COS)
            };
            // The largest cosine at `p` toward any point of the cluster's sphere: clusters in
            // the surface's own plane bring (almost) nothing.
            let cos_p = ((d.dot(n) + c.radius) / dist).min(1.0);
            let w = c.flux * FRAC_1_PI * cos_p / dist2.max(c.radius * c.radius);
            if !(w > 0.0 && w.is_finite()) {
                continue;
            }
            cones[count] = Cone {
                frame_axis: axis,
                one_minus_cos,
                probability: w,
            };
            total += w;
            count += 1;
        }
        if count == 0 || total < MIN_SHARE * irradiance {
            return None;
        }
        for c in &mut cones[..count] {
            c.probability /= total;
        }
        Some(Self { cones, count })
    }

    /// A direction: a cone chosen by `u_pick`, then uniform inside it.
    pub fn sample(&self, u_pick: f32, u: Vec2) -> Vec3 {
        let mut acc = 0.0;
        let mut chosen = &self.cones[self.count - 1];
        for c in &self.cones[..self.count] {
            acc += c.probability;
            if u_pick < acc {
                chosen = c;
                break;
            }
        }
        let one_minus_cos = u.x * chosen.one_minus_cos;
        let cos_theta = 1.0 - one_minus_cos;
        let sin_theta = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
        let (s, c) = (2.0 * PI * u.y).sin_cos();
        Frame::from_normal(chosen.frame_axis).to_world(Vec3::new(
            sin_theta * c,
            sin_theta * s,
            cos_theta,
        ))
    }

    /// Solid-angle density with which [`HotSampler::sample`] gives the direction `w`.
    pub fn pdf(&self, w: Vec3) -> f32 {
        self.cones[..self.count]
            .iter()
            // |w − axis|² = 2(1 − cos), precise for small angles; a relative slack keeps a
            // sample on the rim inside.
            .filter(|c| (w - c.frame_axis).length_squared() <= 2.0 * c.one_minus_cos * (1.0 + 1e-4))
            .map(|c| c.probability / (2.0 * PI * c.one_minus_cos))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Rng, uniform_sphere};

    fn sampler() -> HotSampler {
        let clusters = [
            HotCluster {
                center: Vec3::new(0.3, 2.0, 0.1),
                radius: 0.4,
                flux: 3.0,
            },
            HotCluster {
                center: Vec3::new(-1.0, 0.5, 0.0),
                radius: 0.3,
                flux: 1.0,
            },
            // Below the surface: never aimed at.
            HotCluster {
                center: Vec3::new(0.0, -1.0, 0.0),
                radius: 0.1,
                flux: 100.0,
            },
        ];
        HotSampler::new(&clusters, Vec3::ZERO, Vec3::Y, 0.0).expect("two clusters above")
    }

    #[test]
    fn density_integrates_to_one_and_matches_the_samples() {
        let s = sampler();
        assert_eq!(s.count, 2);
        let mut rng = Rng::keyed(1, &[]);
        // ∫ pdf dω = 1, by uniform directions on the sphere.
        let n = 2_000_000;
        let mut integral = 0.0f64;
        for _ in 0..n {
            integral += f64::from(s.pdf(uniform_sphere(rng.next_2d()))) * 4.0 * f64::from(PI);
        }
        integral /= f64::from(n);
        assert!((integral - 1.0).abs() < 0.02, "∫ pdf = {integral}");
        // Every sample has a positive density, and E[1/pdf] is the cones' total solid angle.
        let cones: f64 = s.cones[..s.count]
            .iter()
            .map(|c| 2.0 * f64::from(PI) * f64::from(c.one_minus_cos))
            .sum();
        let mut mean_inverse = 0.0f64;
        let m = 200_000;
        for _ in 0..m {
            let w = s.sample(rng.next_f32(), rng.next_2d());
            assert!((w.length() - 1.0).abs() < 1e-4);
            let p = s.pdf(w);
            assert!(p > 0.0, "sampled direction {w} has density 0");
            mean_inverse += 1.0 / f64::from(p) / f64::from(m);
        }
        assert!(
            (mean_inverse / cones - 1.0).abs() < 0.01,
            "E[1/pdf] {mean_inverse} vs solid angle {cones}"
        );
    }

    #[test]
    fn tiny_cones_sample_inside_their_density() {
        // One site far away: the cone is as narrow as allowed.
        let c = [HotCluster {
            center: Vec3::new(0.3, 40.0, -0.2),
            radius: 1e-4,
            flux: 1.0,
        }];
        let s = HotSampler::new(&c, Vec3::ZERO, Vec3::Y, 0.0).expect("above");
        let cone = s.cones[0];
        assert!(cone.one_minus_cos >= MIN_ONE_MINUS_COS);
        let inside = 1.0 / (2.0 * PI * cone.one_minus_cos);
        let mut rng = Rng::keyed(5, &[]);
        for _ in 0..100_000 {
            let w = s.sample(rng.next_f32(), rng.next_2d());
            let p = s.pdf(w);
            assert!(
                (p / inside - 1.0).abs() < 1e-3,
                "rim sample {w}: pdf {p} vs {inside}"
            );
        }
        // Just outside the cone: nothing.
        let axis = cone.frame_axis;
        let off = (axis + Frame::from_normal(axis).s * 3.0 * (2.0 * cone.one_minus_cos).sqrt())
            .normalize();
        assert_eq!(s.pdf(off), 0.0);
    }

    #[test]
    fn clusters_in_the_surface_plane_are_not_aimed_at() {
        let cluster = |center| {
            [HotCluster {
                center,
                radius: 0.01,
                flux: 1.0,
            }]
        };
        // Overhead at distance 1: Φ/π. In the surface's plane at distance 1: only the sliver
        // of its sphere above the plane counts, a hundredth of that.
        assert!(HotSampler::new(&cluster(Vec3::Y), Vec3::ZERO, Vec3::Y, 0.1).is_some());
        assert!(HotSampler::new(&cluster(Vec3::X), Vec3::ZERO, Vec3::Y, 0.1).is_none());
    }

    #[test]
    fn small_shares_do_not_aim() {
        let c = [HotCluster {
            center: Vec3::new(0.0, 2.0, 0.0),
            radius: 0.1,
            flux: 1.0,
        }];
        // Φ/π · cos/d² = 1/(4π) ≈ 0.08 W/m².
        assert!(HotSampler::new(&c, Vec3::ZERO, Vec3::Y, 0.2).is_some());
        assert!(HotSampler::new(&c, Vec3::ZERO, Vec3::Y, 0.4).is_none());
    }

    #[test]
    fn clusters_cover_every_site_and_keep_the_flux() {
        let mut rng = Rng::keyed(3, &[]);
        // A thin strip 1.2 m long: split along its length into small clusters.
        let sites: Vec<Vec3> = (0..5000)
            .map(|_| Vec3::new(rng.next_f32() * 1.2 - 0.6, 1.99, rng.next_f32() * 0.04))
            .collect();
        let out = clusters(sites.clone(), 0.002, 3.5);
        assert!(out.len() > 16 && out.len() <= MAX_CLUSTERS, "{}", out.len());
        let flux: f32 = out.iter().map(|c| c.flux).sum();
        assert!((flux - 10.0).abs() < 1e-3, "{flux}");
        for s in &sites {
            assert!(
                out.iter()
                    .any(|c| (*s - c.center).length() <= c.radius * 1.0001),
                "site {s} in no cluster"
            );
        }
        assert!(clusters(Vec::new(), 1.0, 1.0).is_empty());
    }
}
