//! The environment light: its power against a Monte Carlo integral of its radiance, the power
//! its photons carry, its sampling against its density (χ²), and a white furnace: a white
//! diffuse sphere under a uniform sky of radiance 1 shows radiance 1 everywhere.

use crate::common;

use photon::description::{build::build, toml_read::read_str};
use photon::integrator::{Integrator, PathConfig, PhotonIntegrator, PhotonSettings};
use photon::light::{Aperture, EnvironmentLight, EnvironmentMap, Light};
use photon::math::{Rgb, Vec3};
use photon::photon::{PhotonConfig, trace_photons};
use photon::render::{RenderSettings, render};
use photon::sampling::{Rng, uniform_sphere};
use photon::spectrum::Lambda;
use std::f32::consts::PI;
use std::path::Path;
use std::sync::Arc;

/// A small sky with structure: a gradient, a bright patch (the sun) and a black row.
fn test_map() -> Arc<EnvironmentMap> {
    map_with_sun(true)
}

fn map_with_sun(sun: bool) -> Arc<EnvironmentMap> {
    let (w, h) = (16u32, 8u32);
    let mut texels = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let base = Rgb::new(0.2 + 0.05 * x as f32, 0.5, 1.0 - 0.1 * y as f32);
            texels.push(match (x, y) {
                (5, 2) | (6, 2) if sun => Rgb::new(40.0, 35.0, 30.0),
                (_, 7) => Rgb::ZERO,
                _ => base,
            });
        }
    }
    Arc::new(EnvironmentMap {
        width: w,
        height: h,
        texels,
    })
}

fn sky(view: Option<(Vec3, f32)>) -> EnvironmentLight {
    let mut sky = EnvironmentLight::image(test_map(), Rgb::new(1.0, 0.8, 1.2), 30.0);
    sky.aperture = Aperture {
        center: Vec3::new(0.5, 1.0, -0.5),
        radius: 2.0,
        view,
    };
    sky
}

#[test]
fn power_is_the_disc_times_the_integral_of_radiance() {
    let sky = sky(None);
    let mut rng = Rng::keyed(1, &[]);
    let n = 1_000_000;
    let mut sum = [0f64; 3];
    for _ in 0..n {
        let l = sky.radiance(uniform_sphere(rng.next_2d()), &Lambda::Rgb);
        for (c, s) in sum.iter_mut().enumerate() {
            *s += f64::from(l[c]);
        }
    }
    let disc = PI * 4.0;
    let mc = Rgb::new(sum[0] as f32, sum[1] as f32, sum[2] as f32) / n as f32 * 4.0 * PI * disc;
    let p = sky.power();
    assert!(
        ((mc - p) / p).abs().max_element() < 0.01,
        "Monte Carlo {mc} vs reported {p}"
    );
}

/// Photons carry the light's power on average, whether or not half of them are aimed at a
/// smaller sphere (the view): the mixture's density makes up for where they start.
#[test]
fn photons_carry_the_power_with_and_without_aiming() {
    for view in [None, Some((Vec3::new(0.8, 0.9, -0.2), 0.4))] {
        let sky = sky(view);
        let mut rng = Rng::keyed(2, &[]);
        let n = 1_000_000;
        let mut sum = [0f64; 3];
        for _ in 0..n {
            let Some(e) = Light::Environment(sky.clone()).emit(
                rng.next_f32(),
                rng.next_2d(),
                rng.next_2d(),
                &Lambda::Rgb,
            ) else {
                continue;
            };
            for (c, s) in sum.iter_mut().enumerate() {
                *s += f64::from(e.flux[c]);
            }
        }
        let mean = Rgb::new(sum[0] as f32, sum[1] as f32, sum[2] as f32) / n as f32;
        let p = sky.power();
        assert!(
            ((mean - p) / p).abs().max_element() < 0.02,
            "view {view:?}: mean photon flux {mean} vs power {p}"
        );
    }
}

/// Directions toward the sky are drawn with the density `pdf` reports (the black row
/// included), rotation and all. (Without the sun: its edges cut the test's cells, and the
/// midpoint rule cannot integrate a density that jumps a hundredfold inside one; the next test
/// covers it.)
#[test]
fn sky_sampling_matches_its_density_chi2() {
    let mut sky = EnvironmentLight::image(map_with_sun(false), Rgb::new(1.0, 0.8, 1.2), 30.0);
    sky.aperture.radius = 1.0;
    let z = common::chi2_directions(
        400_000,
        3,
        |rng| {
            let ls = Light::Environment(sky.clone()).sample_li(
                Vec3::ZERO,
                0.0,
                rng.next_2d(),
                &Lambda::Rgb,
            )?;
            assert!(
                (ls.pdf - sky.pdf(ls.wi)).abs() <= 1e-3 * ls.pdf,
                "sample pdf {} vs pdf() {}",
                ls.pdf,
                sky.pdf(ls.wi)
            );
            Some(ls.wi)
        },
        |w| f64::from(sky.pdf(w)),
    );
    assert!(z < 4.0, "χ² z-score {z:.2}");
}

/// Each texel is drawn in proportion to its luminance × sin θ (the sun's two texels hold 30%
/// of the draws), and the direction lands inside it.
#[test]
fn sky_texels_are_drawn_by_luminance_times_sin_theta() {
    let map = test_map();
    let sky = EnvironmentLight::image(map.clone(), Rgb::ONE, 0.0);
    let (w, h) = (map.width as usize, map.height as usize);
    let mut weights = Vec::new();
    for j in 0..h {
        let sin = (PI * (j as f32 + 0.5) / h as f32).sin();
        for i in 0..w {
            weights.push(f64::from(
                photon::math::luminance(map.texels[j * w + i]) * sin,
            ));
        }
    }
    let total: f64 = weights.iter().sum();
    let probs: Vec<f64> = weights.iter().map(|x| x / total).collect();
    let n = 400_000u64;
    let mut counts = vec![0u64; w * h];
    let mut rng = Rng::keyed(4, &[]);
    for _ in 0..n {
        // A draw whose direction, recomputed, falls into the black row at its edge fails.
        let Some(ls) =
            Light::Environment(sky.clone()).sample_li(Vec3::ZERO, 0.0, rng.next_2d(), &Lambda::Rgb)
        else {
            continue;
        };
        let d = ls.wi;
        let u = (d.x.atan2(-d.z) / (2.0 * PI)).rem_euclid(1.0);
        let v = d.y.clamp(-1.0, 1.0).acos() / PI;
        let (i, j) = (
            ((u * w as f32) as usize).min(w - 1),
            ((v * h as f32) as usize).min(h - 1),
        );
        counts[j * w + i] += 1;
    }
    let sun = (counts[2 * w + 5] + counts[2 * w + 6]) as f64 / n as f64;
    assert!(sun > 0.25, "the sun draws {sun}");
    let drawn: u64 = counts.iter().sum();
    assert!(n - drawn < n / 1000, "{} draws failed", n - drawn);
    let (stat, dof) = common::chi2(&counts, &probs, drawn);
    let z = common::chi2_z(stat, dof);
    assert!(z < 4.0, "χ² = {stat:.1} with {dof} dof (z = {z:.2})");
}

/// A white diffuse sphere in a uniform sky of radiance 1 reflects radiance 1 everywhere
/// (every path ends in the sky with weight 1); the sky seen around it is 1 too.
#[test]
fn white_furnace_under_a_uniform_sky() {
    let text = r#"
[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 50.0
[materials.white]
type = "diffuse"
albedo = 1.0
[[shapes]]
type = "sphere"
radius = 1.0
material = "white"
[[lights]]
type = "environment"
radiance = 1.0
"#;
    let desc = read_str(text, Path::new("furnace.toml"), Path::new(".")).expect("reads");
    let scene = build(&desc).expect("builds");
    let settings = RenderSettings {
        seed: 3,
        filter: photon::film::PixelFilter::Box,
        ..RenderSettings::new(12, 12, 64)
    };
    let config = PhotonConfig {
        photons: 200_000,
        ..PhotonConfig::default()
    };
    let maps = Arc::new(trace_photons(&scene, &config, &|_, _| {}).expect("traces"));
    let photon = Integrator::Photon(Box::new(PhotonIntegrator::new(
        PhotonSettings::for_scene(&scene),
        maps,
    )));
    // Single pixels keep their noise: 2% deviation for `path` at 64 samples (measured), so
    // 256 samples and 5%; the photon integrator's gather is smoother.
    for (integrator, spp, tolerance) in [
        (Integrator::Path(PathConfig::default()), 256, 0.05),
        (photon, 64, 0.05),
    ] {
        let settings = RenderSettings { spp, ..settings };
        let img = render(&scene, &integrator, &settings, &|_, _| {})
            .expect("renders")
            .image;
        let mean = img.mean();
        assert!(
            (mean - Rgb::ONE).abs().max_element() < 0.01,
            "{}: mean {mean}",
            integrator.name()
        );
        for p in &img.pixels {
            assert!(
                (p.x - 1.0).abs() < tolerance,
                "{}: pixel {p}",
                integrator.name()
            );
        }
    }
}
