//! Sampling routines (each with its pdf), a piecewise-constant 1-D distribution, and an alias
//! table for picking among many items in constant time.
//!
//! Every warp maps uniform numbers in [0,1)² to a point or direction and has a matching `*_pdf`
//! function; `tests/sampling_chi2.rs` checks each against its pdf with a chi-square test.

mod alias;
mod equiangular;
mod rng;
mod sobol;

pub use alias::AliasTable;
pub use equiangular::Equiangular;
pub use rng::{Rng, Sampler, mix64};
pub use sobol::PixelSampler;

pub mod halton;

use crate::math::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Concentric map of the unit square to the unit disk (Shirley & Chiu 1997): uniform by area,
/// and low distortion, so stratification survives the warp.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, PI / 4.0 * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - PI / 4.0 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Uniform point on a disk of radius `radius` by the polar map the original project used
/// (`r = R·sqrt(u)`). Density 1 / (π R²).
pub fn uniform_disk_polar(u: Vec2, radius: f32) -> Vec2 {
    let r = radius * u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// Cosine-weighted direction on the hemisphere around +z (Malley's method).
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Solid-angle density of [`cosine_hemisphere`]: cos θ / π.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform direction on the unit sphere. Density 1 / (4π).
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// Uniform direction inside the cone around +z whose half-angle has cosine `cos_max`:
/// cos θ uniform in [cos_max, 1].
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_theta = 1.0 - u.x * (1.0 - cos_max);
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// Solid-angle density of [`uniform_cone`] inside the cone.
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// The original project's cone "spread" s ∈ [0, 1] as the cosine of the cone's half-angle:
/// cos θ is uniform in [1 − 2s, 1], so 0 is the axis, 0.5 the hemisphere and 1 the whole sphere.
pub fn cone_cos_from_spread(spread: f32) -> f32 {
    1.0 - 2.0 * spread.clamp(0.0, 1.0)
}

/// Uniform barycentrics (b0, b1, b2) on a triangle (the square-root map, Turk 1990).
pub fn uniform_triangle(u: Vec2) -> Vec3 {
    let su = u.x.sqrt();
    let b0 = 1.0 - su;
    let b1 = u.y * su;
    Vec3::new(b0, b1, 1.0 - b0 - b1)
}

/// Up to this many items, [`Distribution1D::sample`] scans the CDF rather than bisecting it.
const LINEAR_SEARCH_MAX: usize = 8;

/// A piecewise-constant distribution over `n` discrete items, sampled by inverting its CDF.
/// Used where the map from `u` to items must be monotonic, so that stratified numbers stay
/// stratified: the photons' choice of light, environment maps' rows and columns. Elsewhere
/// [`AliasTable`] picks in constant time.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    cdf: Vec<f64>,
    weights: Weights,
}

/// A discrete distribution's weights (negative ones as zero) and their sum: what the chance of
/// each item is, however it is sampled.
#[derive(Clone, Debug)]
struct Weights {
    values: Vec<f64>,
    total: f64,
}

impl Weights {
    /// `None` if there are no weights, or they do not sum to a positive finite number.
    fn new(weights: &[f64]) -> Option<Self> {
        let values: Vec<f64> = weights.iter().map(|w| w.max(0.0)).collect();
        let total: f64 = values.iter().sum();
        (!values.is_empty() && total > 0.0 && total.is_finite()).then_some(Self { values, total })
    }

    fn pmf(&self, i: usize) -> f32 {
        (self.values[i] / self.total) as f32
    }
}

impl Distribution1D {
    /// Build from non-negative weights. Returns `None` if there are none or they sum to zero.
    pub fn new(weights: &[f64]) -> Option<Self> {
        let weights = Weights::new(weights)?;
        let mut cdf = Vec::with_capacity(weights.values.len() + 1);
        let mut acc = 0.0;
        cdf.push(0.0);
        for &w in &weights.values {
            acc += w;
            cdf.push(acc);
        }
        Some(Self { cdf, weights })
    }

    pub fn len(&self) -> usize {
        self.weights.values.len()
    }

    pub fn is_empty(&self) -> bool {
        self.weights.values.is_empty()
    }

    pub fn total(&self) -> f64 {
        self.weights.total
    }

    /// Probability of item `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        self.weights.pmf(i)
    }

    /// Pick an item with probability proportional to its weight; also returns `u` remapped to
    /// [0, 1) within the chosen item so it can be reused.
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let target = f64::from(u) * self.weights.total;
        // The first item whose cdf exceeds target (a linear scan over a few items, a binary
        // search over more), skipping zero-weight items.
        let n = self.len();
        let i = if n <= LINEAR_SEARCH_MAX {
            self.cdf[1..]
                .iter()
                .position(|&c| c > target)
                .unwrap_or(n - 1)
        } else {
            self.cdf
                .partition_point(|&c| c <= target)
                .saturating_sub(1)
                .min(n - 1)
        };
        let i = self.first_nonzero_from(i);
        let w = self.weights.values[i];
        let rest = ((target - self.cdf[i]) / w).clamp(0.0, 1.0 - f64::EPSILON) as f32;
        (i, rest.min(1.0 - f32::EPSILON))
    }

    fn first_nonzero_from(&self, i: usize) -> usize {
        if self.weights.values[i] > 0.0 {
            return i;
        }
        (i..self.len())
            .chain((0..i).rev())
            .find(|&j| self.weights.values[j] > 0.0)
            .unwrap_or(i)
    }
}

/// A piecewise-constant density over the unit square, `width × height` cells in rows (row 0 at
/// v = 0): a marginal distribution over rows and a conditional one within each row (pbrt-v4
/// `PiecewiseConstant2D`). For environment maps.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    width: usize,
    height: usize,
    rows: Vec<Option<Distribution1D>>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// From non-negative cell weights, row-major. `None` if they sum to zero.
    pub fn new(weights: &[f64], width: usize, height: usize) -> Option<Self> {
        if weights.len() != width * height {
            return None;
        }
        Self::from_rows(width, height, |j, row| {
            row.copy_from_slice(&weights[j * width..(j + 1) * width]);
        })
    }

    /// As [`Distribution2D::new`], the weights of row `j` written by `row(j, weights)`: one row
    /// of them exists at a time (an environment map's would be as big as the map).
    pub fn from_rows(
        width: usize,
        height: usize,
        mut row: impl FnMut(usize, &mut [f64]),
    ) -> Option<Self> {
        if width == 0 || height == 0 {
            return None;
        }
        let mut weights = vec![0.0; width];
        let rows: Vec<_> = (0..height)
            .map(|j| {
                row(j, &mut weights);
                Distribution1D::new(&weights)
            })
            .collect();
        let totals: Vec<f64> = rows
            .iter()
            .map(|r| r.as_ref().map_or(0.0, Distribution1D::total))
            .collect();
        Some(Self {
            width,
            height,
            marginal: Distribution1D::new(&totals)?,
            rows,
        })
    }

    /// A point of the unit square and its density there.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (j, rest_y) = self.marginal.sample(u.y);
        let Some(row) = &self.rows[j] else {
            return (Vec2::ZERO, 0.0);
        };
        let (i, rest_x) = row.sample(u.x);
        let p = Vec2::new(
            (i as f32 + rest_x) / self.width as f32,
            (j as f32 + rest_y) / self.height as f32,
        );
        let pdf = self.marginal.pmf(j) * row.pmf(i) * (self.width * self.height) as f32;
        (p, pdf)
    }

    /// Density at a point of the unit square.
    pub fn pdf(&self, p: Vec2) -> f32 {
        let i = ((p.x * self.width as f32) as usize).min(self.width - 1);
        let j = ((p.y * self.height as f32) as usize).min(self.height - 1);
        self.rows[j].as_ref().map_or(0.0, |row| {
            self.marginal.pmf(j) * row.pmf(i) * (self.width * self.height) as f32
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distribution_picks_in_proportion() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]).expect("non-empty");
        let mut counts = [0usize; 3];
        let n = 40_000;
        for i in 0..n {
            let (k, rest) = d.sample((i as f32 + 0.5) / n as f32);
            assert!((0.0..1.0).contains(&rest));
            counts[k] += 1;
        }
        assert_eq!(counts[1], 0);
        assert!((counts[0] as f32 / n as f32 - 0.25).abs() < 0.001);
        assert!((d.pmf(2) - 0.75).abs() < 1e-6);
        assert!(Distribution1D::new(&[0.0, 0.0]).is_none());
        assert!(Distribution1D::new(&[]).is_none());
    }

    #[test]
    fn distribution_1d_bisects_long_lists_to_the_same_items() {
        // Past LINEAR_SEARCH_MAX items the search bisects: each item must still come up in
        // proportion to its weight, and a zero-weight item never.
        let weights: Vec<f64> = (0..20)
            .map(|i| if i == 7 { 0.0 } else { f64::from(i % 5 + 1) })
            .collect();
        let total: f64 = weights.iter().sum();
        let d = Distribution1D::new(&weights).expect("non-empty");
        let n = 200_000;
        let mut counts = vec![0usize; weights.len()];
        for i in 0..n {
            let (k, rest) = d.sample((i as f32 + 0.5) / n as f32);
            assert!((0.0..1.0).contains(&rest));
            counts[k] += 1;
        }
        for (k, w) in weights.iter().enumerate() {
            let share = counts[k] as f64 / f64::from(n);
            assert!(
                (share - w / total).abs() < 1e-3,
                "item {k}: {share} against {}",
                w / total
            );
        }
    }

    #[test]
    fn spread_parameter_matches_the_original_meaning() {
        assert_eq!(cone_cos_from_spread(0.0), 1.0);
        assert_eq!(cone_cos_from_spread(0.5), 0.0);
        assert_eq!(cone_cos_from_spread(1.0), -1.0);
    }
}
