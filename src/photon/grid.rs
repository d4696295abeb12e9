//! A hashed uniform grid of photons for fixed-radius queries: what a progressive pass uses
//! instead of a kd-tree (Hachisuka, Ogaki & Jensen 2008 keep their photons in such a grid, and
//! Teschner et al. 2003 give the hash). Building it is one counting sort; a query visits the
//! cells its sphere overlaps and reads their photons from one contiguous run each.
//!
//! Photons are sorted by bucket, keeping their given order within a bucket, so the same photons
//! give the same grid and every query visits its photons in the same order.

use super::record::Photon;
use crate::math::Vec3;

/// Cells a query may visit one by one; a larger query reads every photon instead (it is then
/// a scan, but still exact).
const MAX_QUERY_CELLS: usize = 4096;

/// Anything a grid can hold: it has a position.
pub trait Located: Copy + Default {
    fn location(&self) -> Vec3;
}

impl Located for super::VolumePhoton {
    #[inline]
    fn location(&self) -> Vec3 {
        self.position
    }
}

impl Located for Photon {
    #[inline]
    fn location(&self) -> Vec3 {
        self.position()
    }
}

/// Photons in buckets of a hashed uniform grid: bucket `b` holds
/// `photons[starts[b]..starts[b + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct PhotonGrid<T = Photon> {
    lower: Vec3,
    inv_cell: f32,
    mask: u64,
    starts: Vec<u32>,
    photons: Vec<T>,
}

/// Per-thread memory of grid queries, so that a query allocates nothing once it is warm.
#[derive(Clone, Debug, Default)]
pub struct QueryScratch {
    buckets: Vec<u32>,
}

impl<T: Located> PhotonGrid<T> {
    /// Grid of `photons` with cubic cells of side `cell` (a query of radius r ≤ cell/2 visits
    /// at most 8 cells). As many buckets as photons, rounded up to a power of two.
    pub fn build(photons: Vec<T>, cell: f32) -> Self {
        let buckets = photons.len().max(1).next_power_of_two();
        let lower = photons
            .iter()
            .fold(Vec3::splat(f32::INFINITY), |m, p| m.min(p.location()));
        let cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            f32::MAX
        };
        let mut grid = Self {
            lower: if lower.is_finite() { lower } else { Vec3::ZERO },
            inv_cell: 1.0 / cell,
            mask: buckets as u64 - 1,
            starts: vec![0; buckets + 1],
            photons: Vec::new(),
        };
        let keys: Vec<u32> = photons
            .iter()
            .map(|p| grid.bucket(grid.cell_of(p.location())))
            .collect();
        for &k in &keys {
            grid.starts[k as usize + 1] += 1;
        }
        for b in 0..buckets {
            grid.starts[b + 1] += grid.starts[b];
        }
        let mut next = grid.starts.clone();
        let mut sorted = vec![T::default(); photons.len()];
        for (p, &k) in photons.iter().zip(&keys) {
            sorted[next[k as usize] as usize] = *p;
            next[k as usize] += 1;
        }
        grid.photons = sorted;
        grid
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// The photons, in bucket order.
    pub fn photons(&self) -> &[T] {
        &self.photons
    }

    fn cell_of(&self, p: Vec3) -> [i64; 3] {
        // `as` saturates: far-away or absurd coordinates still land in some cell.
        let c = ((p - self.lower) * self.inv_cell).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    }

    fn bucket(&self, c: [i64; 3]) -> u32 {
        // Teschner et al.'s primes (2003), then a multiply–xorshift so that the low bits the
        // mask keeps depend on every bit of the three coordinates.
        let h = (c[0] as u64).wrapping_mul(73_856_093)
            ^ (c[1] as u64).wrapping_mul(19_349_663)
            ^ (c[2] as u64).wrapping_mul(83_492_791);
        let h = (h ^ (h >> 29)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        ((h ^ (h >> 32)) & self.mask) as u32
    }

    /// Visit every photon within distance `r` of `q` as `f(photon, d²)`. Each photon is
    /// visited once, even when two of the sphere's cells hash to one bucket.
    #[inline]
    pub fn for_each_within(
        &self,
        q: Vec3,
        r: f32,
        scratch: &mut QueryScratch,
        f: &mut impl FnMut(&T, f32),
    ) {
        let r2 = r * r;
        let mut visit = |photons: &[T]| {
            for p in photons {
                let d2 = (p.location() - q).length_squared();
                if d2 <= r2 {
                    f(p, d2);
                }
            }
        };
        let lo = self.cell_of(q - r);
        let hi = self.cell_of(q + r);
        let cells: f64 = (0..3).map(|k| hi[k] as f64 - lo[k] as f64 + 1.0).product();
        if cells > MAX_QUERY_CELLS as f64 || cells > self.starts.len() as f64 {
            visit(&self.photons);
            return;
        }
        let buckets = &mut scratch.buckets;
        buckets.clear();
        // A few cells: skip repeats as they come; many: sort them out at the end.
        let few = cells <= 32.0;
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    let b = self.bucket([x, y, z]);
                    if !few || !buckets.contains(&b) {
                        buckets.push(b);
                    }
                }
            }
        }
        if !few {
            buckets.sort_unstable();
            buckets.dedup();
        }
        for &b in buckets.iter() {
            let b = b as usize;
            visit(&self.photons[self.starts[b] as usize..self.starts[b + 1] as usize]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::Channel;
    use crate::sampling::Rng;

    fn cloud(n: usize, seed: u64) -> Vec<Photon> {
        let mut rng = Rng::keyed(seed, &[]);
        (0..n)
            .map(|_| {
                // A dense clump and a sparse spread, so queries see both.
                let s = if rng.next_f32() < 0.5 { 0.05 } else { 1.0 };
                let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * s;
                Photon::new(p, Vec3::Z, Vec3::Z, crate::math::Rgb::ONE, 2, Channel::Rgb)
            })
            .collect()
    }

    /// Every query, small or larger than a cell, finds exactly the photons brute force finds,
    /// each once: the check that a bucket shared by two cells is not read twice.
    #[test]
    fn queries_match_brute_force() {
        let photons = cloud(5000, 1);
        let mut rng = Rng::keyed(2, &[]);
        let mut scratch = QueryScratch::default();
        for cell in [0.002, 0.02, 0.2, 5.0] {
            let grid = PhotonGrid::build(photons.clone(), cell);
            assert_eq!(grid.len(), photons.len());
            for _ in 0..300 {
                let q = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
                    * if rng.next_f32() < 0.5 { 0.06 } else { 1.1 };
                let r = [0.001, 0.01, 0.05, 0.3][(rng.next_u32() % 4) as usize];
                let mut found: Vec<[u32; 3]> = Vec::new();
                grid.for_each_within(q, r, &mut scratch, &mut |p, d2| {
                    assert!(d2 <= r * r);
                    found.push(p.position.map(f32::to_bits));
                });
                let mut expected: Vec<[u32; 3]> = photons
                    .iter()
                    .filter(|p| (p.position() - q).length_squared() <= r * r)
                    .map(|p| p.position.map(f32::to_bits))
                    .collect();
                found.sort_unstable();
                expected.sort_unstable();
                assert_eq!(found, expected, "cell {cell}, q {q}, r {r}");
            }
        }
    }

    /// The grid holds each photon once and does not depend on anything but the photons.
    #[test]
    fn build_is_a_permutation_and_repeatable() {
        let photons = cloud(3000, 3);
        let a = PhotonGrid::build(photons.clone(), 0.01);
        let b = PhotonGrid::build(photons.clone(), 0.01);
        assert_eq!(a.photons(), b.photons());
        let key = |p: &Photon| p.position.map(f32::to_bits);
        let mut x: Vec<_> = a.photons().iter().map(key).collect();
        let mut y: Vec<_> = photons.iter().map(key).collect();
        x.sort_unstable();
        y.sort_unstable();
        assert_eq!(x, y);
    }

    #[test]
    fn empty_and_degenerate_grids_answer_nothing_or_everything() {
        let mut scratch = QueryScratch::default();
        let empty: PhotonGrid = PhotonGrid::build(Vec::new(), 0.1);
        empty.for_each_within(Vec3::ZERO, 1.0, &mut scratch, &mut |_, _| panic!("empty"));
        let photons = cloud(100, 4);
        for cell in [0.0, f32::NAN, f32::INFINITY, 1e-30] {
            let grid = PhotonGrid::build(photons.clone(), cell);
            let mut n = 0;
            grid.for_each_within(Vec3::splat(0.5), 10.0, &mut scratch, &mut |_, _| n += 1);
            assert_eq!(n, 100, "cell {cell}");
        }
    }
}
