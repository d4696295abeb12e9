//! The cost of heterogeneous media against the grid's size: a smoke-like density (three soft
//! blobs with fine ripples, the same shape at every resolution) at 64³, 128³, 256³ and 512³
//! voxels. For each: the time to build the medium (its 16³ majorant grid), the resident
//! memory it adds, and on one thread the free flights (delta tracking) and transmittances
//! (ratio tracking) per second along random rays through it, with the tentative collisions
//! per ray, which show how tight the fixed-size majorant grid stays as voxels shrink. Run with
//! `cargo bench --bench grids [-- RESOLUTION...]` (Linux: memory from /proc/self/status).

use photon::math::{Ray, Rgb, Vec3};
use photon::medium::{DensityGrid, GridMedium, HenyeyGreenstein, MAJORANT_CELLS};
use photon::sampling::{Rng, Sampler};
use rayon::prelude::*;
use std::time::Instant;

/// Resident memory in MB (0 where /proc is missing).
fn resident_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(0.0, |kb| kb / 1024.0)
}

/// The density at `p` in the unit cube: three Gaussian blobs, rippled.
fn plume(p: Vec3) -> f32 {
    let blob = |c: Vec3, s: f32| (-(p - c).length_squared() / (2.0 * s * s)).exp();
    let d = blob(Vec3::new(0.5, 0.3, 0.5), 0.15)
        + 0.8 * blob(Vec3::new(0.45, 0.55, 0.55), 0.12)
        + 0.6 * blob(Vec3::new(0.55, 0.75, 0.45), 0.09);
    let ripple = 0.75 + 0.25 * (40.0 * p.x).sin() * (37.0 * p.y).sin() * (43.0 * p.z).sin();
    (d * ripple).max(0.0)
}

fn grid(n: usize) -> DensityGrid {
    let values = (0..n * n * n)
        .into_par_iter()
        .map(|i| {
            let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
            let c = |k: usize| (k as f32 + 0.5) / n as f32;
            plume(Vec3::new(c(x), c(y), c(z)))
        })
        .collect();
    DensityGrid::new([n, n, n], values).expect("a valid grid")
}

/// A sampler that counts the numbers drawn.
struct Counting {
    rng: Rng,
    drawn: u64,
}

impl Sampler for Counting {
    fn next_f32(&mut self) -> f32 {
        self.drawn += 1;
        self.rng.next_f32()
    }
}

/// A ray from a random point on a sphere around the cube toward a random point inside it.
fn random_ray(rng: &mut Rng) -> Ray {
    let u = rng.next_2d();
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u.y;
    let origin = Vec3::splat(0.5) + 2.0 * Vec3::new(r * phi.cos(), r * phi.sin(), z);
    let target = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
    Ray::new(origin, (target - origin).normalize())
}

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![64, 128, 256, 512]
    } else {
        sizes
    };
    // σt up to 40 per unit at the densest point: a few mean free paths across the plume.
    let (sigma_a, sigma_s) = (Rgb::splat(2.0), Rgb::splat(38.0));
    let rays = 200_000u64;
    println!(
        "majorant grid: {MAJORANT_CELLS}³ cells ({} KB) at every resolution",
        MAJORANT_CELLS.pow(3) * 4 / 1024
    );
    println!(
        "| voxels | build (s) | memory (MB) | free flights/s (1 thread) | tentative collisions per flight | transmittances/s (1 thread) | tentative collisions per transmittance |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    for n in sizes {
        let before = resident_mb();
        let g = grid(n);
        let start = Instant::now();
        let medium = GridMedium::new(
            sigma_a,
            sigma_s,
            HenyeyGreenstein::new(0.3),
            g,
            glam::Affine3A::IDENTITY,
        )
        .expect("invertible");
        let build = start.elapsed().as_secs_f64();
        let memory = resident_mb() - before;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("a pool");
        let (flights, flight_draws) = pool.install(|| {
            let mut rays_rng = Rng::keyed(1, &[n as u64]);
            let mut s = Counting {
                rng: Rng::keyed(2, &[n as u64]),
                drawn: 0,
            };
            let start = Instant::now();
            let mut scattered = 0u64;
            for i in 0..rays {
                let ray = random_ray(&mut rays_rng);
                scattered += u64::from(
                    medium
                        .sample_free_flight(
                            medium.coefficients(),
                            &ray,
                            10.0,
                            (i % 3) as usize,
                            &mut s,
                        )
                        .scattered,
                );
            }
            std::hint::black_box(scattered);
            (rays as f64 / start.elapsed().as_secs_f64(), s.drawn)
        });
        let (transmittances, tr_draws) = pool.install(|| {
            let mut rays_rng = Rng::keyed(3, &[n as u64]);
            let mut s = Counting {
                rng: Rng::keyed(4, &[n as u64]),
                drawn: 0,
            };
            let start = Instant::now();
            let mut sum = Rgb::ZERO;
            for _ in 0..rays {
                sum += medium.transmittance(
                    medium.coefficients(),
                    &random_ray(&mut rays_rng),
                    10.0,
                    &mut s,
                );
            }
            std::hint::black_box(sum);
            (rays as f64 / start.elapsed().as_secs_f64(), s.drawn)
        });
        // Delta tracking draws two numbers per tentative collision (distance, event), ratio
        // tracking one (and one more for each roulette, rare).
        println!(
            "| {n}³ | {build:.3} | {memory:.0} | {:.2} M | {:.1} | {:.2} M | {:.1} |",
            flights / 1e6,
            flight_draws as f64 / 2.0 / rays as f64,
            transmittances / 1e6,
            tr_draws as f64 / rays as f64,
        );
        drop(medium);
    }
}
