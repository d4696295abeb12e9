//! Every sampling routine against its pdf, by a chi-square test (as Mitsuba and pbrt do).

use crate::common;

use common::{chi2, chi2_z};
use photon::math::{Vec2, Vec3};
use photon::sampling::{
    Rng, concentric_disk, cone_cos_from_spread, cosine_hemisphere, uniform_cone,
    uniform_disk_polar, uniform_sphere, uniform_triangle,
};
use std::f64::consts::PI;

const N: u64 = 400_000;
/// z-score threshold: p ≈ 3·10⁻⁵, with fixed seeds so the tests are reproducible.
const Z_MAX: f64 = 4.0;

/// Histogram directions over (cos θ, φ) cells. Solid angle is dcosθ dφ, so a pdf in solid angle
/// integrates over a cell in closed form. `cell_prob(c0, c1, dphi)` gives a cell's probability.
fn direction_test(
    name: &str,
    sample: impl Fn(Vec2) -> Vec3,
    cell_prob: impl Fn(f64, f64, f64) -> f64,
) {
    let (nt, np) = (24usize, 32usize);
    let mut counts = vec![0u64; nt * np];
    let mut rng = Rng::keyed(42, &[name.len() as u64]);
    for _ in 0..N {
        let w = sample(rng.next_2d());
        assert!((w.length() - 1.0).abs() < 1e-4, "{name}: not unit length");
        let c = f64::from(w.z).clamp(-1.0, 1.0 - 1e-12);
        let phi = f64::from(w.y).atan2(f64::from(w.x)).rem_euclid(2.0 * PI);
        let i = (((c + 1.0) / 2.0) * nt as f64) as usize;
        let j = ((phi / (2.0 * PI)) * np as f64) as usize;
        counts[i.min(nt - 1) * np + j.min(np - 1)] += 1;
    }
    let mut probs = Vec::with_capacity(nt * np);
    for i in 0..nt {
        let c0 = -1.0 + 2.0 * i as f64 / nt as f64;
        let c1 = -1.0 + 2.0 * (i + 1) as f64 / nt as f64;
        for _ in 0..np {
            probs.push(cell_prob(c0, c1, 2.0 * PI / np as f64));
        }
    }
    let (stat, dof) = chi2(&counts, &probs, N);
    let z = chi2_z(stat, dof);
    assert!(
        z < Z_MAX,
        "{name}: chi² = {stat:.1} with {dof} dof (z = {z:.2})"
    );
}

#[test]
fn cosine_hemisphere_matches_cos_over_pi() {
    direction_test("cosine", cosine_hemisphere, |c0, c1, dphi| {
        // ∫ cosθ/π dcosθ dφ over the cell, zero below the horizon.
        let (a, b) = (c0.max(0.0), c1.max(0.0));
        (b * b - a * a) / 2.0 * dphi / PI
    });
}

#[test]
fn uniform_sphere_matches_one_over_four_pi() {
    direction_test("sphere", uniform_sphere, |c0, c1, dphi| {
        (c1 - c0) * dphi / (4.0 * PI)
    });
}

#[test]
fn uniform_cone_with_the_original_spread_parameter() {
    for spread in [0.05f32, 0.25, 0.5, 0.8, 1.0] {
        let cos_max = f64::from(cone_cos_from_spread(spread));
        direction_test(
            &format!("cone spread {spread}"),
            |u| uniform_cone(u, cone_cos_from_spread(spread)),
            |c0, c1, dphi| {
                // cos θ uniform in [1 − 2s, 1]: overlap of the cell with that interval.
                let overlap = (c1.min(1.0) - c0.max(cos_max)).max(0.0);
                overlap / (1.0 - cos_max) * dphi / (2.0 * PI)
            },
        );
    }
}

/// Disk samplers on polar cells: a cell [r0, r1] × [φ0, φ1] has area (r1² − r0²)Δφ/2.
fn disk_test(name: &str, sample: impl Fn(Vec2) -> Vec2) {
    let (nr, np) = (16usize, 32usize);
    let mut counts = vec![0u64; nr * np];
    let mut rng = Rng::keyed(7, &[name.len() as u64]);
    for _ in 0..N {
        let p = sample(rng.next_2d());
        let r = f64::from(p.length());
        assert!(r <= 1.0 + 1e-6, "{name}: outside the unit disk");
        let phi = f64::from(p.y).atan2(f64::from(p.x)).rem_euclid(2.0 * PI);
        let i = ((r * nr as f64) as usize).min(nr - 1);
        let j = ((phi / (2.0 * PI) * np as f64) as usize).min(np - 1);
        counts[i * np + j] += 1;
    }
    let mut probs = Vec::new();
    for i in 0..nr {
        let (r0, r1) = (i as f64 / nr as f64, (i + 1) as f64 / nr as f64);
        for _ in 0..np {
            probs.push((r1 * r1 - r0 * r0) * (2.0 * PI / np as f64) / 2.0 / PI);
        }
    }
    let (stat, dof) = chi2(&counts, &probs, N);
    let z = chi2_z(stat, dof);
    assert!(
        z < Z_MAX,
        "{name}: chi² = {stat:.1} with {dof} dof (z = {z:.2})"
    );
}

#[test]
fn disk_samplers_are_uniform_by_area() {
    disk_test("polar", |u| uniform_disk_polar(u, 1.0));
    disk_test("concentric", concentric_disk);
}

#[test]
fn triangle_sampler_is_uniform_by_area() {
    // Triangle (0,0) (1,0) (0,1) on an n×n grid: the hypotenuse cuts the anti-diagonal cells
    // exactly in half, so every cell's probability is known exactly.
    let n = 20usize;
    let mut counts = vec![0u64; n * n];
    let mut rng = Rng::keyed(3, &[]);
    for _ in 0..N {
        let b = uniform_triangle(rng.next_2d());
        assert!(b.min_element() >= -1e-6 && (b.x + b.y + b.z - 1.0).abs() < 1e-5);
        let (x, y) = (f64::from(b.y), f64::from(b.z));
        let i = ((x * n as f64) as usize).min(n - 1);
        let j = ((y * n as f64) as usize).min(n - 1);
        counts[j * n + i] += 1;
    }
    let cell = 1.0 / (n * n) as f64;
    let probs: Vec<f64> = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            match (i + j).cmp(&(n - 1)) {
                std::cmp::Ordering::Less => 2.0 * cell,
                std::cmp::Ordering::Equal => cell,
                std::cmp::Ordering::Greater => 0.0,
            }
        })
        .collect();
    let (stat, dof) = chi2(&counts, &probs, N);
    let z = chi2_z(stat, dof);
    assert!(
        z < Z_MAX,
        "triangle: chi² = {stat:.1} with {dof} dof (z = {z:.2})"
    );
}

#[test]
fn a_wrong_sampler_fails_the_test() {
    // The test must be able to fail: uniform hemisphere directions are not cosine distributed.
    let result = std::panic::catch_unwind(|| {
        direction_test(
            "wrong",
            |u| {
                let w = uniform_sphere(u);
                Vec3::new(w.x, w.y, w.z.abs())
            },
            |c0, c1, dphi| {
                let (a, b) = (c0.max(0.0), c1.max(0.0));
                (b * b - a * a) / 2.0 * dphi / PI
            },
        );
    });
    assert!(result.is_err());
}
