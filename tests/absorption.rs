//! Beer–Lambert absorption inside glass (a glass's `attenuation`, glTF's
//! `KHR_materials_volume`): the light every integrator sees through an absorbing sphere, and
//! the photon power an absorbing slab lets through, against their closed forms.

use photon::description::build::build;
use photon::description::toml_read;
use photon::math::Rgb;
use photon::photon::{PhotonConfig, trace_photons};
use photon::render_job::RenderJob;
use photon::scene::Scene;
use photon::settings::{IntegratorKind, RenderOptions};
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// Fresnel reflectance of glass (n = 1.5) at normal incidence: ((n − 1)/(n + 1))².
const F: f64 = 0.04;

/// The colour white light turns into over the attenuation distance (1 m here): red keeps a
/// quarter, green half, blue all of it.
const COLOR: [f64; 3] = [0.25, 0.5, 1.0];

/// Light crossing a glass layer whose one pass keeps τ of it, at normal incidence: it enters
/// (1 − F), crosses (τ), and leaves (1 − F) after 0, 2, 4, … internal reflections (F² τ² each):
/// (1 − F)² τ / (1 − F² τ²). With τ = 1 this is (1 − F)/(1 + F).
fn through_layer(tau: f64) -> f64 {
    (1.0 - F) * (1.0 - F) * tau / (1.0 - F * F * tau * tau)
}

fn scene(toml: &str) -> Scene {
    let desc = toml_read::read_str(toml, Path::new("scene.toml"), Path::new(".")).expect("reads");
    build(&desc).expect("builds")
}

/// A glass sphere of radius 0.5 m (n = 1.5, GGX `alpha`) absorbing as [`COLOR`] per metre, in
/// front of a wide two-sided light of radiance 1, seen head-on through a 1° field of view: every
/// pixel looks along (nearly) the diameter, 1 m of glass.
fn sphere_before_light(alpha: f32) -> String {
    format!(
        r#"
[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 1.0
resolution = [4, 4]

[materials.glass]
type = "glass"
ior = 1.5
alpha = {alpha}
attenuation = {{ color = [{}, {}, {}], distance = 1.0 }}

[[shapes]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 0.5
material = "glass"

[[shapes]]
type = "quad"
vertices = [[-2.0, -2.0, -2.0], [2.0, -2.0, -2.0], [2.0, 2.0, -2.0], [-2.0, 2.0, -2.0]]
emission = {{ radiance = 1.0, two_sided = true }}
"#,
        COLOR[0], COLOR[1], COLOR[2]
    )
}

fn image_mean(scene: &Scene, options: RenderOptions) -> Rgb {
    let job = RenderJob::new(scene, &Default::default(), options).expect("job");
    let image = job
        .render(&|_| {}, &AtomicBool::new(false))
        .expect("renders")
        .image;
    image.pixels.iter().sum::<Rgb>() / image.pixels.len() as f32
}

/// The pixels off the axis see a chord shorter than the diameter (by 0.1% at the image's
/// corner, refraction included), so red, which loses most, reads up to ~0.2% above the axis's
/// closed form; the tolerances cover that and the noise.
fn assert_through_sphere(what: &str, mean: Rgb, tolerance: f64) {
    for c in 0..3 {
        let expected = through_layer(COLOR[c]);
        let got = f64::from(mean[c]);
        assert!(
            (got / expected - 1.0).abs() < tolerance,
            "{what}: channel {c} reads {got}, the closed form is {expected} (mean {mean})"
        );
    }
}

/// Every integrator sees the light through the smooth absorbing sphere as the closed form
/// (1 − F)² τ / (1 − F² τ²) per channel: path tracing and `direct` (camera paths), `photon`
/// (emission found along the smooth part), SPPM and PPM (the visible-point paths' delta
/// chains). Clear glass read (1 − F)/(1 + F) = 0.923 in every channel.
#[test]
fn every_integrator_sees_the_closed_form_through_an_absorbing_sphere() {
    let scene = scene(&sphere_before_light(0.0));
    let samples = |kind, spp| RenderOptions {
        integrator: Some(kind),
        spp: Some(spp),
        ..RenderOptions::default()
    };
    let passes = |kind| RenderOptions {
        integrator: Some(kind),
        passes: Some(64),
        photons_per_pass: Some(1000),
        ..RenderOptions::default()
    };
    let runs = [
        (samples(IntegratorKind::Path, 1024), 0.01),
        (samples(IntegratorKind::Direct, 16), 0.005),
        (
            RenderOptions {
                photons: Some(2000),
                ..samples(IntegratorKind::Photon, 16)
            },
            0.005,
        ),
        (passes(IntegratorKind::Sppm), 0.005),
        (passes(IntegratorKind::Ppm), 0.005),
    ];
    for (options, tolerance) in runs {
        let kind = options.integrator;
        let mean = image_mean(
            &scene,
            RenderOptions {
                seed: Some(7),
                ..options
            },
        );
        assert_through_sphere(&format!("{kind:?}"), mean, tolerance);
    }
}

/// Rough glass absorbs the same way: at GGX α = 0.005 the sphere is all but smooth, and the
/// path tracer (which also samples the light through the rough surface, MIS-weighted) and the
/// photon integrator read the smooth closed form.
#[test]
fn rough_glass_absorbs_as_smooth_glass_does() {
    let scene = scene(&sphere_before_light(0.005));
    for (kind, spp) in [(IntegratorKind::Path, 1024), (IntegratorKind::Photon, 64)] {
        let mean = image_mean(
            &scene,
            RenderOptions {
                integrator: Some(kind),
                spp: Some(spp),
                photons: (kind == IntegratorKind::Photon).then_some(2000),
                seed: Some(7),
                ..RenderOptions::default()
            },
        );
        assert_through_sphere(&format!("rough glass, {kind:?}"), mean, 0.015);
    }
}

/// A 1 × 1 m glass slab 0.2 m thick (n = 1.5) absorbing as [`COLOR`] per 0.2 m, under a sun of
/// irradiance 1 W/m² shining straight down, over a black floor.
const SLAB_UNDER_SUN: &str = r#"
[camera]
position = [0.0, 4.0, 0.01]
look_at = [0.0, 0.0, 0.0]
fov = 40.0
resolution = [8, 8]

[materials.glass]
type = "glass"
ior = 1.5
attenuation = { color = [0.25, 0.5, 1.0], distance = 0.2 }

[materials.black]
type = "diffuse"
albedo = 0.0

[[shapes]]
type = "box"
min = [-0.5, 0.5, -0.5]
max = [0.5, 0.7, 0.5]
material = "glass"

[[shapes]]
type = "quad"
vertices = [[-2.0, 0.0, -2.0], [-2.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0]]
material = "black"

[[lights]]
type = "directional"
direction = [0.0, -1.0, 0.0]
irradiance = 1.0
"#;

/// Photons that cross the slab land on the floor beneath it as caustic photons. The sun sends
/// E·A = 1 W onto the slab's top, and the floor receives (1 − F)² τ / (1 − F² τ²) of it per
/// channel (τ = [`COLOR`]: one crossing is one attenuation distance). Every photon carries all
/// three channels, so the ratio of red and green to blue, which does not depend on how many
/// photons hit the slab, must be exact up to the rare internal reflections (τ³ instead of τ);
/// the totals are within the count's noise. With one channel per photon, the absorbed ones
/// end by Russian roulette instead, and the totals agree all the same.
#[test]
fn photons_through_an_absorbing_slab_lose_exactly_the_expected_fraction() {
    let scene = scene(SLAB_UNDER_SUN);
    for per_channel in [false, true] {
        let config = PhotonConfig {
            photons: 200_000,
            per_channel,
            seed: 3,
            ..PhotonConfig::default()
        };
        let maps = trace_photons(&scene, &config, &|_, _| {}).expect("traces");
        let caustic = maps.caustic.total_power();
        let expected = COLOR.map(through_layer);
        for c in 0..3 {
            let got = f64::from(caustic[c]);
            let tolerance = if per_channel { 0.04 } else { 0.02 };
            assert!(
                (got / expected[c] - 1.0).abs() < tolerance,
                "per channel {per_channel}: channel {c} carries {got} W, expected {} W",
                expected[c]
            );
            if !per_channel {
                let ratio = got / f64::from(caustic[2]);
                let expected_ratio = expected[c] / expected[2];
                assert!(
                    (ratio / expected_ratio - 1.0).abs() < 0.002,
                    "channel {c} over blue: {ratio}, expected {expected_ratio}"
                );
            }
        }
    }
}
