//! Participating media against closed forms: the Henyey–Greenstein phase function's sampling
//! against its density (χ², as Mitsuba tests its phase functions), its normalisation, and
//! free-flight sampling against Beer–Lambert transmittance.

use crate::common;

use common::media::{
    assert_every_integrator_renders_alike_on_one_and_two_threads, furnace_toml, image_mean, scene,
};
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
        let hero = photon::medium::hero_channel(rng.next_f32());
        let f = m.sample_free_flight(d, hero, rng.next_f32());
        // The balance heuristic over the channels' densities.
        let weight = f.weight / ((f.ratio.x + f.ratio.y + f.ratio.z) / 3.0);
        if f.scattered {
            // The scattering weight carries σs; divide it out to count events.
            scattered += weight / m.sigma_s * m.sigma_t();
        } else {
            passed += weight;
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

// ---- Media in scenes, rendered, against closed forms -------------------------------------

/// A camera in an absorbing atmosphere (σa = 0.1) looking through an invisible box of
/// coloured absorbing medium 1 m thick at a two-sided emitter of radiance 1, 5 m away:
/// exp(−0.1 · 4 − σa,box · 1) per channel, with no noise (neither medium scatters).
#[test]
fn light_through_absorbing_media_is_beer_lambert_across_boundaries() {
    let s = scene(
        r#"
medium = "haze"
[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 1.0
resolution = [4, 4]

[media.haze]
sigma_a = 0.1

[media.ink]
sigma_a = [0.5, 1.0, 2.0]

[[shapes]]
type = "box"
min = [-1.0, -1.0, -0.5]
max = [1.0, 1.0, 0.5]
interior = "ink"

[[shapes]]
type = "quad"
vertices = [[-2.0, -2.0, -2.0], [2.0, -2.0, -2.0], [2.0, 2.0, -2.0], [-2.0, 2.0, -2.0]]
emission = { radiance = 1.0, two_sided = true }
"#,
    );
    for integrator in ["path", "direct", "photon", "sppm", "ppm"] {
        let mean = image_mean(&s, integrator, 1);
        for (c, sigma) in [0.5f32, 1.0, 2.0].into_iter().enumerate() {
            let exact = (-0.4 - sigma).exp();
            let got = mean.to_array()[c];
            eprintln!("Beer–Lambert, {integrator}, channel {c}: {got:.6}, exact {exact:.6}");
            // The corner pixels' rays are up to 0.5° off the axis: 4e-5 longer.
            assert!(
                (got - exact).abs() < 2e-4 * exact,
                "{integrator}, channel {c}: {got} vs exp(−0.4 − {sigma}) = {exact}"
            );
        }
    }
}

/// Single scattering along a camera ray from a point light in an infinite homogeneous medium:
/// the ray x(t) = −t ẑ from the origin passes a light of intensity I at (0, h, −d), and
/// L = ∫₀^∞ σs p(μ(t)) I e^{−σt t} e^{−σt r(t)} / r(t)² dt, r = √(h² + (t − d)²), with the
/// scattering cosine μ = (d − t) / r between the light's direction of travel and the
/// camera's. The integral is taken by the midpoint rule on a substitution t = d + h tan θ
/// that makes it smooth.
fn single_scattering_integral(
    sigma_s: f64,
    sigma_t: f64,
    g: f64,
    intensity: f64,
    (h, d): (f64, f64),
) -> f64 {
    let n = 200_000;
    let mut sum = 0.0;
    let (start, end) = ((-d / h).atan(), std::f64::consts::FRAC_PI_2);
    for i in 0..n {
        let theta = start + (i as f64 + 0.5) / n as f64 * (end - start);
        let t = d + h * theta.tan();
        let dt = h / (theta.cos() * theta.cos()) * (end - start) / n as f64;
        let r = (h * h + (t - d) * (t - d)).sqrt();
        let mu = (d - t) / r;
        let phase =
            (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * mu).powf(1.5));
        sum += sigma_s * phase * intensity * (-sigma_t * (t + r)).exp() / (r * r) * dt;
    }
    sum
}

/// The medium of the single-scattering tests: coloured, so that each channel's distances are
/// drawn with the others' densities too (spectral MIS) and a wrong weight shows in some
/// channel.
const FOG_SIGMA_A: [f64; 3] = [0.2, 0.1, 0.5];
const FOG_SIGMA_S: [f64; 3] = [0.3, 0.6, 0.1];
const FOG_G: f64 = 0.5;
const LIGHT_INTENSITY: f64 = 10.0;

/// Where the camera of [`point_light_in_fog`] stands.
#[derive(Clone, Copy, Debug)]
enum Camera {
    /// At the origin, in fog filling the scene.
    InFog,
    /// Half a unit before the origin, in vacuum, looking into fog that fills a box beyond
    /// z = 0 behind an invisible boundary: the light it sees is the same.
    Outside,
}

/// A camera looking down −z through a narrow field (every pixel's ray within 0.005° of the
/// axis) into coloured fog that starts at the origin, with a point light at (0, h, −d).
fn point_light_in_fog((h, d): (f64, f64), camera: Camera, resolution: u32) -> photon::scene::Scene {
    let (atmosphere, z, fog_box) = match camera {
        Camera::InFog => ("medium = \"fog\"", 0.0, ""),
        Camera::Outside => (
            "",
            0.5,
            "[[shapes]]\ntype = \"box\"\nmin = [-50.0, -50.0, -100.0]\nmax = [50.0, 50.0, 0.0]\ninterior = \"fog\"",
        ),
    };
    scene(&format!(
        r#"
{atmosphere}
[camera]
position = [0.0, 0.0, {z}]
look_at = [0.0, 0.0, -1.0]
fov = 0.01
resolution = [{resolution}, {resolution}]

[media.fog]
sigma_a = {FOG_SIGMA_A:?}
sigma_s = {FOG_SIGMA_S:?}
g = {FOG_G}

{fog_box}

[[lights]]
type = "point"
position = [0.0, {h}, {}]
intensity = {LIGHT_INTENSITY}
"#,
        -d
    ))
}

fn assert_single_scattering(integrator: &str, light: (f64, f64), mean: Rgb, tolerance: f64) {
    let (h, _) = light;
    for c in 0..3 {
        let sigma_t = FOG_SIGMA_A[c] + FOG_SIGMA_S[c];
        let exact =
            single_scattering_integral(FOG_SIGMA_S[c], sigma_t, FOG_G, LIGHT_INTENSITY, light);
        let got = f64::from(mean.to_array()[c]);
        eprintln!(
            "single scattering, h {h}, channel {c}: {integrator} {got:.5}, integral {exact:.5}"
        );
        assert!(
            (got - exact).abs() < tolerance * exact,
            "h {h}, channel {c}: {integrator} {got} vs the single-scattering integral {exact}"
        );
    }
}

/// `direct`, and `path` at one scattering vertex: their light samples at the points free
/// flight finds and their samples of distances drawn toward the light (equiangular),
/// weighted against each other, must sum to the integral, with the light far from the ray
/// and close beside it, and with the camera in the fog and outside it.
#[test]
fn single_scattering_from_a_point_light_in_an_infinite_medium_matches_its_integral() {
    for integrator in ["direct", "path"] {
        for (light, camera, spp) in [
            ((1.0, 0.0), Camera::InFog, 2048),
            ((0.05, 2.0), Camera::InFog, 16384),
            ((0.05, 2.0), Camera::Outside, 16384),
        ] {
            let scene = point_light_in_fog(light, camera, 2);
            let image = render_single_scattering(&scene, integrator, spp);
            let mean = image.pixels.iter().sum::<Rgb>() / image.pixels.len() as f32;
            eprintln!("camera {camera:?}:");
            assert_single_scattering(integrator, light, mean, 0.01);
        }
    }
}

/// With the light 0.05 from the ray, free flight alone rarely scatters where the light's 1/r²
/// is large: the pixels of `path` and `direct` spread over ±29% of their mean at 64 samples.
/// Sampling distances toward the light too brings that to ±4%. Every pixel here sees the same
/// light.
#[test]
fn a_point_light_beside_a_ray_in_fog_is_sampled_by_distance() {
    for (integrator, camera) in [
        ("direct", Camera::InFog),
        ("path", Camera::InFog),
        ("path", Camera::Outside),
    ] {
        let scene = point_light_in_fog((0.05, 2.0), camera, 8);
        let image = render_single_scattering(&scene, integrator, 64);
        let values: Vec<f32> = image.pixels.iter().map(|p| p.y).collect();
        let n = values.len() as f32;
        let mean = values.iter().sum::<f32>() / n;
        let sd = (values.iter().map(|v| (v - mean) * (v - mean)).sum::<f32>() / n).sqrt();
        eprintln!(
            "{integrator}, camera {camera:?}: pixels' relative spread {}",
            sd / mean
        );
        assert!(
            sd < 0.1 * mean,
            "{integrator}, camera {camera:?}: pixels spread {sd} about {mean}"
        );
    }
}

/// Light scattered once: `scene` rendered by `direct`, or by `path` with paths of one
/// vertex.
fn render_single_scattering(
    scene: &photon::scene::Scene,
    integrator: &str,
    spp: u32,
) -> photon::film::Image {
    let path = integrator == "path";
    let options = photon::settings::RenderOptions {
        integrator: Some(match path {
            true => photon::settings::IntegratorKind::Path,
            false => photon::settings::IntegratorKind::Direct,
        }),
        spp: Some(spp),
        max_depth: path.then_some(1),
        ..Default::default()
    };
    let job = photon::render_job::RenderJob::new(scene, &Default::default(), options)
        .unwrap_or_else(|e| panic!("{e}"));
    job.render(&|_| {}, &std::sync::atomic::AtomicBool::new(false))
        .expect("renders")
        .image
}

/// A furnace: a closed sphere whose wall emits radiance 1 and reflects nothing, filled with
/// media that scatter but do not absorb (an atmosphere, and a ball of another medium behind an
/// invisible boundary). Radiance 1 everywhere solves the transport equation there, so every
/// pixel reads 1 however light scatters: light counted twice (emission found both by light
/// sampling and by phase sampling, or by light sampling and photons) or lost at a boundary
/// shows.
fn furnace(camera_z: f32, cloud_z: f32, resolution: u32) -> photon::scene::Scene {
    scene(&furnace_toml(camera_z, cloud_z, resolution))
}

#[test]
fn a_closed_sphere_of_scattering_media_reads_its_wall_radiance_everywhere() {
    let s = furnace(0.5, -0.4, 4);
    let mean = image_mean(&s, "path", 256);
    for c in 0..3 {
        let got = mean.to_array()[c];
        eprintln!("furnace, channel {c}: path {got:.4}, exact 1");
        assert!((got - 1.0).abs() < 0.02, "channel {c}: {got}, not 1");
    }
}

/// The furnace with photons: direct light from the wall by light sampling at the camera
/// path's point in the medium, the rest from the photons scattered around it (the volume
/// radiance estimate). A photon estimate off by σs, by the ball's volume or by the photons
/// that came straight from the wall shows in some channel.
#[test]
fn progressive_photon_mapping_reads_the_furnace_wall_radiance_in_media() {
    // The camera at the centre, so that its points in the media are mostly a ball's radius
    // from the wall, and the cloud behind it, so that few balls reach into it (see
    // `image_mean`; a ball's photons are those of its own medium). Photons still cross it.
    let s = furnace(0.0, 0.6, 8);
    for integrator in ["sppm", "ppm"] {
        let mean = image_mean(&s, integrator, 40);
        for c in 0..3 {
            let got = mean.to_array()[c];
            eprintln!("furnace, channel {c}: {integrator} {got:.4}, exact 1");
            assert!(
                (got - 1.0).abs() < 0.05,
                "{integrator}, channel {c}: {got}, not 1"
            );
        }
    }
}

/// The furnace by the two-pass integrator: the wall's light through the mist by
/// transmittance, and everything the mist scatters toward the camera by the beam radiance
/// estimate over the volume photons (Jarosz et al. 2008). A kernel or sphere radius off by a
/// factor, σs counted twice or photons from the wall left out shows in some channel.
#[test]
fn the_beam_radiance_estimate_reads_the_furnace_wall_radiance_in_media() {
    let s = furnace(0.0, 0.6, 4);
    // Spheres of a fixed radius 0.3 (see `render`): the furnace's light is the same
    // everywhere, so the estimate is unbiased at any radius, and large spheres average more
    // photons, which keeps the noise within the bound.
    let mean = image_mean(&s, "photon", 4);
    for c in 0..3 {
        let got = mean.to_array()[c];
        eprintln!("furnace, channel {c}: photon {got:.4}, exact 1");
        assert!((got - 1.0).abs() < 0.05, "channel {c}: {got}, not 1");
    }
}

/// Mistakes in media are reported at their line and column, with what was expected.
#[test]
fn bad_media_are_errors_at_their_place() {
    let head = "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n";
    let cases = [
        (
            format!("medium = \"fgo\"\n{head}[media.fog]\nsigma_s = 0.1\n"),
            "1:10",
            "medium 'fgo' is not defined in [media] (defined: fog)",
        ),
        (
            format!("{head}[media.fog]\nsigma_s = 0.1\ng = 1.0\n"),
            "6:5",
            "must be between -1 and 1",
        ),
        (
            format!("{head}[media.fog]\nsigma_s = 0.1\ndensity = 2.0\n"),
            "4:1",
            "gives both sigma_a/sigma_s and albedo/density",
        ),
        (
            format!("{head}[media.fog]\nalbedo = 1.5\n"),
            "5:10",
            "must be at most 1",
        ),
        (
            format!("{head}[media.fog]\nsigma_a = -0.1\n"),
            "5:11",
            "must not be negative",
        ),
        (
            format!(
                "{head}[media.fog]\nsigma_s = 0.1\n[[shapes]]\ntype = \"sphere\"\nradius = 1.0\ninterior = \"smoke\"\n"
            ),
            "9:12",
            "medium 'smoke' is not defined in [media]",
        ),
        (
            format!("{head}[[shapes]]\ntype = \"sphere\"\nradius = 1.0\n"),
            "4:1",
            "needs a 'material' (or an 'interior' medium",
        ),
    ];
    for (text, at, needle) in cases {
        let e = photon::description::toml_read::read_str(
            &text,
            std::path::Path::new("fog.toml"),
            std::path::Path::new("."),
        )
        .expect_err(&text)
        .to_string();
        assert!(
            e.contains(&format!("fog.toml:{at}")),
            "{e}\n--- for ---\n{text}"
        );
        assert!(e.contains(needle), "{e}\n--- for ---\n{text}");
    }
}

/// The same scene and seed give the same image on one thread and on two, in media too (the
/// photons scattered in media, the hero channels, the volume gathers).
#[test]
fn media_render_identically_on_one_and_two_threads() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/fog.toml");
    let desc = photon::description::toml_read::read_file(std::path::Path::new(path))
        .unwrap_or_else(|e| panic!("{e}"));
    let s = photon::description::build::build(&desc).unwrap_or_else(|e| panic!("{e}"));
    assert_every_integrator_renders_alike_on_one_and_two_threads(&s, Some((12, 8)));
}

/// Saved photon maps hold no volume photons: tracing maps for a scene with media is refused,
/// naming the integrators that render it, and nothing is written.
#[test]
fn saved_photon_maps_refuse_media_and_name_what_renders_them() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = common::temp_dir("media-photon-maps");
    let fog = repo.join("scenes/fog.toml");
    let o = common::photon(
        &[
            "photons",
            "trace",
            fog.to_str().expect("utf-8"),
            "-o",
            "maps.phm",
        ],
        &dir,
    );
    let needle = "render it with --integrator photon (which traces its own maps), sppm or ppm";
    common::assert_usage_error(&o, needle);
    assert!(!dir.join("maps.phm").exists());
    // Nor do maps saved for another scene render one with media, even when forced.
    let cornell = repo.join("scenes/cornell.toml");
    let cornell = cornell.to_str().expect("utf-8");
    let traced = common::photon(
        &[
            "photons",
            "trace",
            cornell,
            "--photons",
            "2000",
            "-o",
            "maps.phm",
        ],
        &dir,
    );
    assert!(traced.status.success(), "{}", common::stderr(&traced));
    let o = common::photon(
        &[
            "render",
            fog.to_str().expect("utf-8"),
            "--integrator",
            "photon",
            "--photon-map",
            "maps.phm",
            "--force",
            "-o",
            "x.png",
        ],
        &dir,
    );
    common::assert_usage_error(&o, needle);
}
