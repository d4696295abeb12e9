//! A hashed uniform grid over a pass's light vertices for the merging range search: cells
//! twice the radius wide, so a ball of the radius meets at most the 2×2×2 cells around its
//! centre's nearest cell corner (the grid of SmallVCM's `HashGrid`).

use super::LightVertex;
use crate::math::Vec3;

pub struct VertexGrid {
    radius: f32,
    inv_cell: f32,
    /// Where each hash bucket's vertices start in `order` (and end at the next bucket's).
    starts: Vec<u32>,
    /// Vertex indices, grouped by bucket, in vertex order within a bucket.
    order: Vec<u32>,
    /// The vertices' positions in the order of `order`: the range search scans these
    /// contiguous 12 bytes and reads a whole vertex only where it merges.
    positions: Vec<Vec3>,
    mask: u64,
}

impl VertexGrid {
    pub fn new(vertices: &[LightVertex], radius: f32) -> Self {
        let buckets = vertices.len().max(1).next_power_of_two();
        let mut grid = Self {
            radius,
            inv_cell: 1.0 / (2.0 * radius),
            starts: vec![0; buckets + 1],
            order: vec![0; vertices.len()],
            positions: Vec::new(),
            mask: buckets as u64 - 1,
        };
        let keys: Vec<u32> = vertices
            .iter()
            .map(|v| grid.bucket(grid.cell(v.position())))
            .collect();
        // Counting sort by bucket: stable, so the order within a bucket is the vertices'.
        for &k in &keys {
            grid.starts[k as usize + 1] += 1;
        }
        for b in 0..buckets {
            grid.starts[b + 1] += grid.starts[b];
        }
        let mut next = grid.starts.clone();
        for (i, &k) in keys.iter().enumerate() {
            grid.order[next[k as usize] as usize] = i as u32;
            next[k as usize] += 1;
        }
        grid.positions = grid
            .order
            .iter()
            .map(|&i| vertices[i as usize].position())
            .collect();
        grid
    }

    fn cell(&self, p: Vec3) -> [i64; 3] {
        (p * self.inv_cell).floor().as_i64vec3().to_array()
    }

    fn bucket(&self, c: [i64; 3]) -> u32 {
        // Teschner et al. 2003's spatial hash.
        let h = (c[0].wrapping_mul(73_856_093))
            ^ (c[1].wrapping_mul(19_349_663))
            ^ (c[2].wrapping_mul(83_492_791));
        (h as u64 & self.mask) as u32
    }

    /// Calls `visit` with every vertex within the radius of `p` (and a few beyond, from
    /// cells sharing a bucket: the caller measures the distance), in a fixed order.
    pub fn for_each_near(
        &self,
        p: Vec3,
        vertices: &[LightVertex],
        mut visit: impl FnMut(&LightVertex),
    ) {
        let q = p * self.inv_cell;
        let base = (q - Vec3::splat(0.5)).floor().as_i64vec3();
        let mut seen = [u32::MAX; 8];
        let mut k = 0;
        for dz in 0..2 {
            for dy in 0..2 {
                for dx in 0..2 {
                    let c = [base.x + dx, base.y + dy, base.z + dz];
                    let b = self.bucket(c);
                    // Two cells may share a bucket: visit it once.
                    if seen[..k].contains(&b) {
                        continue;
                    }
                    seen[k] = b;
                    k += 1;
                    let (s, e) = (
                        self.starts[b as usize] as usize,
                        self.starts[b as usize + 1] as usize,
                    );
                    for (q, &i) in self.positions[s..e].iter().zip(&self.order[s..e]) {
                        if (*q - p).length_squared() <= self.radius * self.radius {
                            visit(&vertices[i as usize]);
                        }
                    }
                }
            }
        }
    }
}
