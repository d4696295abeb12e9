//! Irradiance precomputed at photon positions for final gathering (Christensen, "Faster
//! Photon Map Global Illumination", JGT 1999), and the hot regions among them that gather rays
//! aim at (see [`super::hot`]).

use super::estimate::{
    Filter, GatherParams, STORED_NORMAL_ERROR, disc_distance2, irradiance_filtered,
};
use super::hot::{HOT_FACTOR, HotCluster, HotSampler, clusters};
use super::kdtree::{KdIndex, KdPoint};
use super::map::PhotonMap;
use super::record::{decode_octahedral, encode_octahedral};
use crate::math::{Rgb, Vec3, luminance, plane_tolerance};
use rayon::prelude::*;

/// Whether a photon is one of the irradiance cache's sites for `stride`: about one photon in
/// `stride`, chosen by a hash of its position bits, so that the sites are an independent random
/// thinning of the map (every `stride`-th photon in kd-tree order would be spatially
/// stratified instead).
pub fn is_cache_site(ph: &super::Photon, stride: usize) -> bool {
    if stride <= 1 {
        return true;
    }
    let p = ph.position();
    let bits = (u64::from(p.x.to_bits()) << 32 | u64::from(p.y.to_bits()))
        ^ u64::from(p.z.to_bits()).rotate_left(17);
    splitmix64(bits).is_multiple_of(stride as u64)
}

/// SplitMix64's finaliser (Steele et al. 2014): a well-mixed 64-bit hash.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Irradiance precomputed at a subset of the global map's photons (Christensen, "Faster
/// Photon Map Global Illumination", JGT 1999), so that a final-gather ray costs one nearest
/// lookup instead of a full density estimate.
///
/// A gather ray reads the nearest site, so each site is read in proportion to the area of its
/// Voronoi cell. If a site's estimate used the photons that also place the sites, a chance
/// cluster of photons would both raise the estimate and shrink the cells of the sites in it
/// (and a sparse spot lower the estimate and widen the cells): the area-weighted mean would be
/// too dark (−5% at k = 32 on `cornell`, more at small k). And a site counted in its own
/// estimate adds the kernel's peak (+k/(k−2) with Epanechnikov). So the sites are an
/// independent random thinning of the map (see [`is_cache_site`]), and the estimates use only
/// the other photons, scaled by stride/(stride − 1): positions and estimates are independent,
/// and the lookup is unbiased up to the estimate's smoothing.
///
/// Whether a site is *hot* (far brighter than the scene: a gather hit there is estimated at
/// the hit instead, and gather rays aim at such regions) is decided by a second, coarse
/// estimate made from the sites' own photons only, independent of the site's irradiance: a
/// site picked because its own estimate was high and then re-estimated would take the top off
/// its noise (the closed sphere at k = 1 lost 18%).
#[derive(Clone, Debug)]
pub struct IrradianceCache {
    points: Vec<CachePoint>,
    index: KdIndex,
    hot: Vec<HotCluster>,
    /// The scene's mean irradiance (luminance), by the sites' own photons.
    mean_irradiance: f32,
    stride: usize,
}

#[derive(Clone, Copy, Debug)]
struct CachePoint {
    position: Vec3,
    normal: [u8; 2],
    irradiance: Rgb,
    /// Luminance of the coarse estimate from the sites' own photons.
    coarse: f32,
    hot: bool,
}

/// Photons per coarse estimate (of the sites' photons only).
const COARSE_K: usize = 8;

impl KdPoint for CachePoint {
    fn position(&self) -> Vec3 {
        self.position
    }
}

impl IrradianceCache {
    /// Irradiance at about one photon in `stride` of `sites` (at least 2), from the other
    /// photons of `sites` and all photons of `others`.
    pub fn build(
        sites: &PhotonMap,
        others: &[&PhotonMap],
        stride: usize,
        g: &GatherParams,
    ) -> Self {
        let stride = stride.max(2);
        let coarse_g = GatherParams { k: COARSE_K, ..*g };
        let only_sites = Filter {
            only_sites: stride,
            ..Filter::default()
        };
        let mut points: Vec<CachePoint> = sites
            .photons()
            .par_iter()
            .filter(|ph| is_cache_site(ph, stride))
            .map(|ph| {
                let (p, n) = (ph.position(), ph.normal());
                // The same hash splits every map, so caustics count too.
                let coarse = over_maps(sites, others, p, n, &coarse_g, only_sites) * stride as f32;
                CachePoint {
                    position: p,
                    normal: encode_octahedral(n),
                    irradiance: estimate_apart_from_sites(sites, others, stride, p, n, g),
                    coarse: luminance(coarse),
                    hot: false,
                }
            })
            .collect();
        let index = super::kdtree::build(&mut points);
        let mean_irradiance = area_weighted_mean(&points);
        let threshold = HOT_FACTOR * mean_irradiance;
        for c in &mut points {
            c.hot = c.coarse > threshold;
        }
        // Sites are as dense as the sites' map's photons, so each stands for an equal share of
        // its flux (caustic regions, lit by the other maps, are underrated: they are aimed at
        // less often, which costs variance, not bias).
        let flux_per_site = luminance(sites.total_power()) / points.len().max(1) as f32;
        let hot_sites = points
            .iter()
            .filter(|c| c.hot)
            .map(|c| c.position)
            .collect();
        let hot = clusters(hot_sites, flux_per_site, sites.bounds().extent().length());
        Self {
            points,
            index,
            hot,
            mean_irradiance,
            stride,
        }
    }

    /// The stride the sites were chosen with (see [`is_cache_site`]).
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The sites: (position, normal, irradiance), in the cache's order.
    pub fn points(&self) -> impl Iterator<Item = (Vec3, Vec3, Rgb)> + '_ {
        self.points
            .iter()
            .map(|c| (c.position, decode_octahedral(c.normal), c.irradiance))
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Irradiance of the nearest cache point on the same surface within `max_radius`.
    pub fn lookup(&self, p: Vec3, n: Vec3, max_radius: f32) -> Option<Rgb> {
        self.nearest(p, n, max_radius).map(|c| c.irradiance)
    }

    /// The nearest site's irradiance, and whether that site is hot.
    pub fn lookup_site(&self, p: Vec3, n: Vec3, max_radius: f32) -> Option<(Rgb, bool)> {
        self.nearest(p, n, max_radius)
            .map(|c| (c.irradiance, c.hot))
    }

    /// The hot regions: sites far brighter than the rest, in clusters.
    pub fn hot_clusters(&self) -> &[HotCluster] {
        &self.hot
    }

    /// Directions toward the hot regions from `p` (normal `n`), if any is above the surface
    /// and would bring a good share of the scene's mean irradiance there. (Comparing with the
    /// irradiance at `p` itself would cost a lookup per shading point: +15% render time on
    /// `cornell`, whose only hot region is its caustic.)
    pub fn hot_sampler(&self, p: Vec3, n: Vec3) -> Option<HotSampler> {
        if self.hot.is_empty() {
            return None;
        }
        HotSampler::new(&self.hot, p, n, self.mean_irradiance)
    }

    fn nearest(&self, p: Vec3, n: Vec3, max_radius: f32) -> Option<&CachePoint> {
        let tolerance = plane_tolerance(p);
        let metric = |_, c: &CachePoint, d2: f32| {
            disc_distance2(
                c.position - p,
                d2,
                n,
                decode_octahedral(c.normal),
                tolerance,
                STORED_NORMAL_ERROR,
            )
        };
        let best = self
            .index
            .nearest_by(&self.points, p, 1, max_radius * max_radius, &metric);
        best.found().first().map(|&(_, i)| &self.points[i])
    }
}

/// Irradiance at `p` from the photons of `sites` and `others` that are not in the cache sites'
/// hash class, scaled by stride/(stride − 1): what every site holds, and what a gather hit on
/// a hot site is estimated with, so that both are independent of the sites' positions and of
/// the coarse estimates that decide hotness (which use the sites' class of every map).
pub fn estimate_apart_from_sites(
    sites: &PhotonMap,
    others: &[&PhotonMap],
    stride: usize,
    p: Vec3,
    n: Vec3,
    g: &GatherParams,
) -> Rgb {
    let stride = stride.max(2);
    let thinned = Filter {
        skip_sites: stride,
        ..Filter::default()
    };
    let rest = stride as f32 / (stride - 1) as f32;
    over_maps(sites, others, p, n, g, thinned) * rest
}

/// The irradiance estimate of `filter`'s photons, summed over `sites` and `others`.
fn over_maps(
    sites: &PhotonMap,
    others: &[&PhotonMap],
    p: Vec3,
    n: Vec3,
    g: &GatherParams,
    filter: Filter,
) -> Rgb {
    std::iter::once(sites)
        .chain(others.iter().copied())
        .map(|m| irradiance_filtered(m, p, n, g, filter))
        .sum()
}

/// The scene's mean irradiance by the coarse estimates. Sites are about as dense as the
/// photons, so each stands for an area ∝ 1/E: the area-weighted mean is the sites' harmonic
/// mean (their plain mean is dominated by the hot regions). Infinite if nothing is lit.
fn area_weighted_mean(points: &[CachePoint]) -> f32 {
    let lit: Vec<f32> = points
        .iter()
        .map(|c| c.coarse)
        .filter(|&e| e > 0.0)
        .collect();
    if lit.is_empty() {
        return f32::INFINITY;
    }
    let inverse_sum: f64 = lit.iter().map(|&e| 1.0 / f64::from(e)).sum();
    (lit.len() as f64 / inverse_sum) as f32
}
