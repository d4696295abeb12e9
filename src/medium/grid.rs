//! Heterogeneous media: a density on a voxel grid, scaling the medium's coefficients, with
//! distances sampled by delta tracking and transmittance estimated by ratio tracking against
//! a coarse grid of majorants (Woodcock et al. 1965; Novák et al. 2014, "Residual ratio
//! tracking"; pbrt-v4 §11.4 and §14.2).
//!
//! The grid fills the unit cube of its own space: voxel (i, j, k) of an n_x × n_y × n_z grid
//! has its centre at ((i + ½)/n_x, (j + ½)/n_y, (k + ½)/n_z), the density between centres is
//! trilinear, held at the edge voxels' values up to the cube's faces, and zero outside
//! (Mitsuba 3's `gridvolume` convention). An affine map places the cube in the world.
//!
//! The majorant of a ray segment is grey: the largest channel of σt per unit density, times
//! the largest density the segment's majorant cell can interpolate. Tracking in colour uses
//! the path's hero channel for its choices (see [`crate::medium`]); with a grey majorant the
//! majorant's transmittance cancels from every ratio, which leaves σs/σt_hero at a scattering
//! point and (μ − σt)/(μ − σt_hero) at a null collision.

use super::{Coefficients, FreeFlight, HenyeyGreenstein};
use crate::math::{Ray, Rgb, Vec3};
use crate::sampling::Sampler;
use glam::Affine3A;
use rayon::prelude::*;
use std::fmt;

/// Majorant cells per axis: pbrt-v4's 16³, a few kilobytes whatever the grid's size.
pub const MAJORANT_CELLS: usize = 16;

/// The most voxels a grid may have once read densely: 2²⁸ (1 GiB of densities), past 512³.
pub const MAX_VOXELS: usize = 1 << 28;

/// Ratio tracking ends a shadow ray by Russian roulette once every channel's transmittance
/// is below this (pbrt-v4's `TraceTransmittance`), keeping the cost of thick media bounded.
const ROULETTE_BELOW: f32 = 0.05;
const ROULETTE_SURVIVAL: f32 = 0.25;

/// Densities on a grid, x fastest: `values[x + n_x (y + n_y z)]`. Negative and non-finite
/// densities are read as zero.
#[derive(Clone)]
pub struct DensityGrid {
    resolution: [usize; 3],
    values: Vec<f32>,
    /// FNV-1a of the values' bits: what the scene's content hash sees of them.
    content: u64,
}

/// The resolution and a hash of the values: a scene's content hash (for resuming and merging
/// renders) is taken from its `Debug` text, and must change with any voxel.
impl fmt::Debug for DensityGrid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.resolution;
        write!(f, "DensityGrid({x}×{y}×{z}, {:016x})", self.content)
    }
}

impl DensityGrid {
    /// A grid of `resolution` from its values, or why not: the count must match and the
    /// grid must have at least one voxel and at most [`MAX_VOXELS`].
    pub fn new(resolution: [usize; 3], mut values: Vec<f32>) -> Result<Self, String> {
        let count = resolution
            .iter()
            .try_fold(1usize, |n, &r| n.checked_mul(r))
            .filter(|&n| n > 0 && n <= MAX_VOXELS)
            .ok_or_else(|| {
                format!(
                    "a grid of {}×{}×{} voxels: a grid needs between 1 and {MAX_VOXELS}",
                    resolution[0], resolution[1], resolution[2]
                )
            })?;
        if values.len() != count {
            return Err(format!(
                "{} values for a grid of {count} voxels",
                values.len()
            ));
        }
        for v in &mut values {
            if !(*v > 0.0 && v.is_finite()) {
                *v = 0.0;
            }
        }
        let content = crate::hash::fnv1a(bytemuck::cast_slice(&values));
        Ok(Self {
            resolution,
            values,
            content,
        })
    }

    pub fn resolution(&self) -> [usize; 3] {
        self.resolution
    }

    pub fn max(&self) -> f32 {
        self.values.iter().copied().fold(0.0, f32::max)
    }

    #[inline]
    fn value(&self, x: usize, y: usize, z: usize) -> f32 {
        let [nx, ny, _] = self.resolution;
        self.values[x + nx * (y + ny * z)]
    }

    /// The density at `u` in the unit cube (zero outside it), trilinear between voxel centres.
    pub fn at(&self, u: Vec3) -> f32 {
        if !(u.cmpge(Vec3::ZERO).all() && u.cmple(Vec3::ONE).all()) {
            return 0.0;
        }
        let mut lo = [0usize; 3];
        let mut hi = [0usize; 3];
        let mut frac = [0f32; 3];
        for a in 0..3 {
            let n = self.resolution[a];
            let x = (u[a] * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            lo[a] = (x as usize).min(n - 1);
            hi[a] = (lo[a] + 1).min(n - 1);
            frac[a] = x - lo[a] as f32;
        }
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let row =
            |y: usize, z: usize| lerp(self.value(lo[0], y, z), self.value(hi[0], y, z), frac[0]);
        let plane = |z: usize| lerp(row(lo[1], z), row(hi[1], z), frac[1]);
        lerp(plane(lo[2]), plane(hi[2]), frac[2])
    }

    /// The largest density trilinear interpolation can give inside the box [lo, hi] of the
    /// unit cube: the largest of the voxels around it.
    fn max_in(&self, lo: Vec3, hi: Vec3) -> f32 {
        let range = |a: usize| {
            let n = self.resolution[a];
            let first = (lo[a] * n as f32 - 0.5).floor().max(0.0) as usize;
            let last = ((hi[a] * n as f32 - 0.5).ceil().max(0.0) as usize).min(n - 1);
            first.min(n - 1)..=last
        };
        let (xs, ys, zs) = (range(0), range(1), range(2));
        let mut max = 0.0f32;
        for z in zs {
            for y in ys.clone() {
                for x in xs.clone() {
                    max = max.max(self.value(x, y, z));
                }
            }
        }
        max
    }
}

/// The largest density in each of [`MAJORANT_CELLS`]³ cells of the unit cube.
#[derive(Clone, Debug)]
struct Majorants {
    max: Vec<f32>,
}

impl Majorants {
    fn new(grid: &DensityGrid) -> Self {
        let m = MAJORANT_CELLS;
        let max = (0..m * m * m)
            .into_par_iter()
            .map(|i| {
                let cell = Vec3::new((i % m) as f32, ((i / m) % m) as f32, (i / (m * m)) as f32);
                grid.max_in(cell / m as f32, (cell + 1.0) / m as f32)
            })
            .collect();
        Self { max }
    }

    #[inline]
    fn at(&self, cell: [usize; 3]) -> f32 {
        let m = MAJORANT_CELLS;
        self.max[cell[0] + m * (cell[1] + m * cell[2])]
    }
}

/// A medium whose coefficients are `sigma_a` and `sigma_s` times the grid's density.
#[derive(Clone, Debug)]
pub struct GridMedium {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    pub phase: HenyeyGreenstein,
    grid: DensityGrid,
    majorants: Majorants,
    /// World to the grid's unit cube.
    world_to_unit: Affine3A,
}

impl GridMedium {
    /// `unit_to_world` places the grid's unit cube; it must be invertible.
    pub fn new(
        sigma_a: Rgb,
        sigma_s: Rgb,
        phase: HenyeyGreenstein,
        grid: DensityGrid,
        unit_to_world: Affine3A,
    ) -> Result<Self, String> {
        let world_to_unit = unit_to_world.inverse();
        let finite = |a: &Affine3A| a.matrix3.is_finite() && a.translation.is_finite();
        if unit_to_world.matrix3.determinant() == 0.0
            || !finite(&unit_to_world)
            || !finite(&world_to_unit)
        {
            return Err(
                "the grid's placement is not invertible (a scale of zero?) or not finite".into(),
            );
        }
        let majorants = Majorants::new(&grid);
        Ok(Self {
            sigma_a,
            sigma_s,
            phase,
            grid,
            majorants,
            world_to_unit,
        })
    }

    pub fn grid(&self) -> &DensityGrid {
        &self.grid
    }

    pub fn density(&self, p: Vec3) -> f32 {
        self.grid.at(self.world_to_unit.transform_point3(p))
    }

    /// σa and σs per unit density, in RGB.
    pub fn coefficients(&self) -> Coefficients {
        Coefficients {
            sigma_a: self.sigma_a,
            sigma_s: self.sigma_s,
        }
    }

    /// Sample the next event along the segment of `ray` up to `t_max` by delta tracking with
    /// the `hero` channel's choices, the medium's coefficients per unit density at the path's
    /// channels being `c` (see [`super::Medium::at`]).
    pub fn sample_free_flight(
        &self,
        c: Coefficients,
        ray: &Ray,
        t_max: f32,
        hero: usize,
        sampler: &mut impl Sampler,
    ) -> FreeFlight {
        let hero = hero.min(2);
        let sigma_t = c.sigma_t();
        let mut weight = Rgb::ONE;
        let mut ratio = Rgb::ONE;
        let mut scattered_at = None;
        self.tentative_collisions(c, ray, t_max, sampler, |sampler, t, density, mu| {
            let st = sigma_t * density;
            if sampler.next_f32() * mu < st[hero] {
                weight *= c.sigma_s / sigma_t[hero];
                ratio *= sigma_t / sigma_t[hero];
                scattered_at = Some(t);
                return false;
            }
            let null = Rgb::splat(mu) - st;
            weight *= null / null[hero];
            ratio *= null / null[hero];
            true
        });
        FreeFlight {
            t: scattered_at.unwrap_or(t_max),
            scattered: scattered_at.is_some(),
            weight,
            ratio,
        }
    }

    /// An unbiased estimate of the transmittance along `ray` up to `t_max`, by ratio
    /// tracking, at coefficients `c`.
    pub fn transmittance(
        &self,
        c: Coefficients,
        ray: &Ray,
        t_max: f32,
        sampler: &mut impl Sampler,
    ) -> Rgb {
        let mut tr = Rgb::ONE;
        self.ratio_track(c, ray, t_max, sampler, |_, estimate| tr = estimate);
        tr
    }

    /// Ratio tracking along `ray` up to `t_max` at coefficients `c`, calling `step(t, Tr)` at each tentative
    /// collision with the estimate so far. The running product is an unbiased estimate of the
    /// transmittance to every distance at once (the collisions before t are those of a walk
    /// to t), so one walk serves a whole segment; it ends at zero when roulette stops it.
    pub fn ratio_track(
        &self,
        c: Coefficients,
        ray: &Ray,
        t_max: f32,
        sampler: &mut impl Sampler,
        mut step: impl FnMut(f32, Rgb),
    ) {
        let sigma_t = c.sigma_t();
        let mut tr = Rgb::ONE;
        self.tentative_collisions(c, ray, t_max, sampler, |sampler, t, density, mu| {
            tr *= Rgb::ONE - sigma_t * (density / mu);
            if tr.max_element() < ROULETTE_BELOW {
                if sampler.next_f32() >= ROULETTE_SURVIVAL {
                    step(t, Rgb::ZERO);
                    return false;
                }
                tr /= ROULETTE_SURVIVAL;
            }
            step(t, tr);
            true
        });
    }

    /// The tentative collisions along `ray` up to `t_max`, in order: distances drawn from
    /// each majorant cell's μ (the grey majorant of its largest density: times the largest
    /// channel of σt in `c`), calling `visit(sampler, t, density, μ)` at each while it
    /// returns true. Cells whose majorant is zero or not finite are passed.
    fn tentative_collisions<S: Sampler>(
        &self,
        c: Coefficients,
        ray: &Ray,
        t_max: f32,
        sampler: &mut S,
        mut visit: impl FnMut(&mut S, f32, f32, f32) -> bool,
    ) {
        let (o, d) = self.to_unit(ray);
        let sigma_t_max = c.sigma_t().max_element();
        self.for_each_cell(o, d, t_max, |t_enter, t_exit, max_density| {
            let mu = max_density * sigma_t_max;
            if !(mu > 0.0 && mu.is_finite()) {
                return true;
            }
            let mut t = t_enter;
            loop {
                match advance(t, mu, sampler.next_f32()) {
                    Some(next) if next < t_exit => t = next,
                    _ => return true,
                }
                if !visit(sampler, t, self.grid.at(o + d * t), mu) {
                    return false;
                }
            }
        });
    }

    /// The ray in the unit cube's space: the same parameter `t` reaches the same point.
    fn to_unit(&self, ray: &Ray) -> (Vec3, Vec3) {
        (
            self.world_to_unit.transform_point3(ray.origin),
            self.world_to_unit.transform_vector3(ray.dir),
        )
    }

    /// Walk the majorant cells the ray `o + t d` (unit-cube space) crosses for t in
    /// [0, t_max], in order (a 3D DDA, Amanatides and Woo 1987), calling `visit` with each
    /// cell's entry and exit `t` and largest density, while it returns true. Cells of zero
    /// density are skipped.
    fn for_each_cell(
        &self,
        o: Vec3,
        d: Vec3,
        t_max: f32,
        mut visit: impl FnMut(f32, f32, f32) -> bool,
    ) {
        let Some((t0, t1)) = clip_to_unit_cube(o, d, t_max) else {
            return;
        };
        let m = MAJORANT_CELLS;
        let cells = m as f32;
        let start = (o + d * t0) * cells;
        let mut cell = [0usize; 3];
        let mut step = [0isize; 3];
        let mut t_next = [f32::INFINITY; 3];
        let mut t_delta = [f32::INFINITY; 3];
        for a in 0..3 {
            cell[a] = (start[a].max(0.0) as usize).min(m - 1);
            if d[a] > 0.0 {
                step[a] = 1;
                t_next[a] = ((cell[a] + 1) as f32 / cells - o[a]) / d[a];
                t_delta[a] = 1.0 / (cells * d[a]);
            } else if d[a] < 0.0 {
                step[a] = -1;
                t_next[a] = (cell[a] as f32 / cells - o[a]) / d[a];
                t_delta[a] = -1.0 / (cells * d[a]);
            }
        }
        let mut t = t0;
        loop {
            let axis = if t_next[0] < t_next[1] {
                if t_next[0] < t_next[2] { 0 } else { 2 }
            } else if t_next[1] < t_next[2] {
                1
            } else {
                2
            };
            let t_exit = t_next[axis].min(t1);
            let max_density = self.majorants.at(cell);
            if t_exit > t && max_density > 0.0 && !visit(t, t_exit, max_density) {
                return;
            }
            if t_exit >= t1 {
                return;
            }
            let next = cell[axis] as isize + step[axis];
            if next < 0 || next >= m as isize {
                return;
            }
            cell[axis] = next as usize;
            t = t_exit;
            t_next[axis] += t_delta[axis];
        }
    }
}

/// The part [t0, t1] of [0, t_max] in which `o + t d` is inside the unit cube.
fn clip_to_unit_cube(o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, f32)> {
    if !(o.is_finite() && d.is_finite()) || t_max.is_nan() {
        return None;
    }
    let mut t0 = 0.0f32;
    let mut t1 = t_max;
    for a in 0..3 {
        if d[a] == 0.0 {
            if !(0.0..=1.0).contains(&o[a]) {
                return None;
            }
            continue;
        }
        let (near, far) = {
            let ta = (0.0 - o[a]) / d[a];
            let tb = (1.0 - o[a]) / d[a];
            (ta.min(tb), ta.max(tb))
        };
        t0 = t0.max(near);
        t1 = t1.min(far);
    }
    (t0 < t1).then_some((t0, t1))
}

/// The next tentative collision after `t` at majorant `mu`, from a uniform number; `None`
/// where the step is lost to rounding (t too large for it), which ends the cell: the walk
/// stops rather than stall.
#[inline]
fn advance(t: f32, mu: f32, u: f32) -> Option<f32> {
    let step = -(1.0 - u).ln() / mu;
    let next = t + step;
    (next > t || step == 0.0).then_some(next)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// A grid whose density rises linearly along x from 0 to 2 over the unit cube, placed as
    /// the box [−1, 1]³.
    fn ramp(n: usize) -> GridMedium {
        let values = (0..n * n * n)
            .map(|i| 2.0 * ((i % n) as f32 + 0.5) / n as f32)
            .collect();
        GridMedium::new(
            Rgb::new(0.5, 0.0, 1.0),
            Rgb::new(0.2, 1.0, 0.5),
            HenyeyGreenstein::new(0.0),
            DensityGrid::new([n, n, n], values).unwrap(),
            Affine3A::from_translation(Vec3::splat(-1.0)) * Affine3A::from_scale(Vec3::splat(2.0)),
        )
        .unwrap()
    }

    /// ∫ density along the x axis from x = −1 to 1: the ramp's mean (1, at the centre) times
    /// 2, less what the edge half-voxels hold flat: exactly 2 for a linear ramp sampled at
    /// centres (the clamped halves at the two ends cancel).
    #[test]
    fn ratio_tracking_matches_beer_lambert_through_a_ramp() {
        let m = ramp(8);
        let ray = Ray::new(Vec3::new(-3.0, 0.1, -0.2), Vec3::X);
        let exact = (-(m.sigma_a + m.sigma_s) * 2.0).exp();
        let mut rng = Rng::keyed(7, &[0]);
        let n = 40_000;
        let mut sum = Rgb::ZERO;
        for _ in 0..n {
            sum += m.transmittance(m.coefficients(), &ray, 10.0, &mut rng);
        }
        let estimate = sum / n as f32;
        assert!(
            (estimate - exact).abs().max_element() < 0.01,
            "{estimate} vs {exact}"
        );
    }

    #[test]
    fn delta_tracking_passes_with_the_transmittance_and_scatters_with_the_albedo() {
        let m = ramp(8);
        let ray = Ray::new(Vec3::new(-3.0, 0.1, -0.2), Vec3::X);
        let exact = (-(m.sigma_a + m.sigma_s) * 2.0).exp();
        let mut rng = Rng::keyed(11, &[0]);
        let n = 40_000;
        let (mut passed, mut scattered) = (Rgb::ZERO, Rgb::ZERO);
        for i in 0..n {
            let f = m.sample_free_flight(m.coefficients(), &ray, 10.0, i % 3, &mut rng);
            let w = f.weight * super::super::spectral_mis(f.ratio);
            if f.scattered {
                scattered += w;
            } else {
                passed += w;
            }
        }
        let passed = passed / n as f32;
        let scattered = scattered / n as f32;
        assert!(
            (passed - exact).abs().max_element() < 0.01,
            "{passed} vs {exact}"
        );
        // What scatters is the albedo's share of what does not pass: σs/σt (1 − Tr).
        let albedo = m.sigma_s / (m.sigma_a + m.sigma_s);
        let expected = albedo * (Rgb::ONE - exact);
        assert!(
            (scattered - expected).abs().max_element() < 0.01,
            "{scattered} vs {expected}"
        );
    }

    /// The DDA visits, in order and without gaps, cells whose majorant bounds the density
    /// everywhere in them, for rays from inside and outside, along axes and backwards.
    #[test]
    fn the_majorant_walk_tiles_the_ray_and_bounds_the_density() {
        let mut rng = Rng::keyed(3, &[1]);
        let (n, m) = ([7usize, 5, 9], 7 * 5 * 9);
        let values = (0..m).map(|_| 0.05 + rng.next_f32()).collect();
        let medium = GridMedium::new(
            Rgb::ONE,
            Rgb::ONE,
            HenyeyGreenstein::new(0.0),
            DensityGrid::new(n, values).unwrap(),
            Affine3A::IDENTITY,
        )
        .unwrap();
        let axes = [Vec3::X, -Vec3::Y, Vec3::Z, -Vec3::X];
        for i in 0..400 {
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0 - 1.0;
            let d = if i % 5 == 0 {
                axes[(i / 5) % 4]
            } else {
                (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5).normalize()
            };
            let t_max = if i % 3 == 0 {
                f32::INFINITY
            } else {
                4.0 * rng.next_f32()
            };
            let mut cells = Vec::new();
            medium.for_each_cell(o, d, t_max, |a, b, max| {
                cells.push((a, b, max));
                true
            });
            let Some((t0, t1)) = clip_to_unit_cube(o, d, t_max) else {
                assert!(cells.is_empty());
                continue;
            };
            assert!(!cells.is_empty(), "ray {o} {d} {t_max}");
            // The walk's last boundary may round a few ulps short of the cube's face.
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * b.abs().max(1.0);
            assert_eq!(cells[0].0, t0);
            assert!(close(cells[cells.len() - 1].1, t1), "{cells:?} to {t1}");
            for w in cells.windows(2) {
                assert_eq!(w[0].1, w[1].0, "a gap between cells");
            }
            for &(a, b, max) in &cells {
                for k in 0..8 {
                    let t = a + (b - a) * (k as f32 + 0.5) / 8.0;
                    let density = medium.grid.at(o + d * t);
                    assert!(density <= max * (1.0 + 1e-5), "{density} above {max}");
                }
            }
        }
    }

    #[test]
    fn trilinear_density_is_zero_outside_and_held_at_the_faces() {
        let g = DensityGrid::new([2, 1, 1], vec![1.0, 3.0]).unwrap();
        assert_eq!(g.at(Vec3::new(0.0, 0.5, 0.5)), 1.0);
        assert_eq!(g.at(Vec3::new(0.5, 0.5, 0.5)), 2.0);
        assert_eq!(g.at(Vec3::new(1.0, 0.5, 0.5)), 3.0);
        assert_eq!(g.at(Vec3::new(1.01, 0.5, 0.5)), 0.0);
        assert!(DensityGrid::new([2, 2, 2], vec![0.0; 7]).is_err());
        assert!(DensityGrid::new([1 << 20, 1 << 20, 1], Vec::new()).is_err());
    }
}
