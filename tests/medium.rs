//! Participating media against closed forms: the Henyey–Greenstein phase function's sampling
//! against its density (χ², as Mitsuba tests its phase functions), its normalisation, and
//! free-flight sampling against Beer–Lambert transmittance.

mod common;

use common::{chi2, chi2_z};
use photon::math::{Rgb, Vec3};
use photon::medium::{HenyeyGreenstein, Homogeneous};
use photon::sampling::Rng;

const N: u64 = 400_000;
const Z_MAX: f64 = 4.0;

/// The probability that the forward cosine μ = −wo·wi falls in [a, b] under HG(g):
/// ∫ (1 − g²) / 2 · (1 + g² − 2gμ)^(−3/2) dμ.
fn hg_cell(g: f64, a: f64, b: f64) -> f64 {
    if g.abs() < 1e-3 {
        return (b - a) / 2.0;
    }
    let f = |m: f64| (1.0 + g * g - 2.0 * g * m).powf(-0.5);
    (1.0 - g * g) / (2.0 * g) * (f(b) - f(a))
}

#[test]
fn henyey_greenstein_samples_its_own_density() {
    let wo = Vec3::new(0.3, -0.5, 0.8).normalize();
    for g in [-0.7f32, 0.0, 0.4, 0.9] {
        let phase = HenyeyGreenstein::new(g);
        let cells = 48usize;
        let mut counts = vec![0u64; cells];
        let mut rng = Rng::keyed(7, &[(g * 1000.0) as i64 as u64]);
        for _ in 0..N {
            let s = phase.sample(wo, rng.next_2d());
            assert!((s.wi.length() - 1.0).abs() < 1e-4);
            // Sampled exactly: the pdf is the phase function's value.
            let p = phase.eval(wo, s.wi);
            assert!(
                (s.pdf - p).abs() <= 1e-3 * p.max(1.0),
                "g {g}: pdf {} vs {p}",
                s.pdf
            );
            let mu = f64::from(-wo.dot(s.wi)).clamp(-1.0, 1.0 - 1e-12);
            counts[(((mu + 1.0) / 2.0) * cells as f64) as usize] += 1;
        }
        let probs: Vec<f64> = (0..cells)
            .map(|i| {
                let a = -1.0 + 2.0 * i as f64 / cells as f64;
                hg_cell(f64::from(phase.g()), a, a + 2.0 / cells as f64)
            })
            .collect();
        let (stat, dof) = chi2(&counts, &probs, N);
        let z = chi2_z(stat, dof);
        assert!(z < Z_MAX, "g {g}: χ² = {stat:.1}, {dof} dof (z = {z:.2})");
    }
}

#[test]
fn henyey_greenstein_integrates_to_one_and_peaks_forward() {
    let wo = Vec3::Z;
    for g in [-0.5f32, 0.0, 0.8] {
        let phase = HenyeyGreenstein::new(g);
        // Midpoint rule in μ (the function depends on μ alone): 2π ∫ p dμ = 1.
        let n = 20_000;
        let integral: f64 = (0..n)
            .map(|i| {
                let mu = -1.0 + (2.0 * i as f64 + 1.0) / n as f64;
                let wi = Vec3::new((1.0 - mu * mu).sqrt() as f32, 0.0, -mu as f32);
                f64::from(phase.eval(wo, wi)) * 2.0 / n as f64 * 2.0 * std::f64::consts::PI
            })
            .sum();
        assert!((integral - 1.0).abs() < 1e-3, "g {g}: ∫p = {integral}");
    }
    // Forward (g > 0) means on along the ray: wi = −wo.
    let forward = HenyeyGreenstein::new(0.8);
    assert!(forward.eval(Vec3::Z, -Vec3::Z) > 10.0 * forward.eval(Vec3::Z, Vec3::Z));
}

#[test]
fn free_flights_reproduce_the_transmittance_and_scattering_density_of_a_slab() {
    // A coloured medium; through a slab of depth d, light passes with exp(−σt d) and first
    // scatters within [0, d] with probability 1 − exp(−σt d); weighted by σs/σt it is the
    // single-scattering albedo times that.
    let m = Homogeneous {
        sigma_a: Rgb::new(0.1, 0.6, 1.2),
        sigma_s: Rgb::new(0.9, 0.4, 0.2),
        phase: HenyeyGreenstein::new(0.3),
    };
    let d = 0.8;
    let mut rng = Rng::keyed(3, &[]);
    let (mut passed, mut scattered) = (Rgb::ZERO, Rgb::ZERO);
    let n = 200_000;
    for _ in 0..n {
        let f = m.sample_free_flight(d, rng.next_f32(), rng.next_f32());
        if f.scattered {
            // The scattering weight carries σs; divide it out to count events.
            scattered += f.weight / m.sigma_s * m.sigma_t();
        } else {
            passed += f.weight;
        }
    }
    let (passed, scattered) = (passed / n as f32, scattered / n as f32);
    let tr = m.transmittance(d);
    assert!(
        (passed - tr).abs().max_element() < 0.01,
        "{passed:?} vs {tr:?}"
    );
    let events = Rgb::ONE - tr;
    assert!(
        (scattered - events).abs().max_element() < 0.01,
        "{scattered:?} vs {events:?}"
    );
}
