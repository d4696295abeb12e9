//! Light-transport biases found on scenes nobody tuned for (issue 11), each against a closed
//! form or a brute-force computation: the grazing patch beside a quad light, unbiased k-nearest
//! estimates at small k, the irradiance cache against brute force and against the exact
//! irradiance, final gathering independent of k, and non-finite samples.

use crate::common;

use photon::compare::compare;
use photon::description::build::build;
use photon::description::{builtin, toml_read};
use photon::film::PixelFilter;
use photon::integrator::{DirectConfig, Integrator, PathConfig, PhotonIntegrator, PhotonSettings};
use photon::io::image::read_image;
use photon::math::{Rgb, Vec3};
use photon::photon::estimate::{GatherParams, Kernel, irradiance};
use photon::photon::{Channel, MapKind, Photon, PhotonConfig, PhotonMap, trace_photons};
use photon::photon::{IrradianceCache, is_cache_site};
use photon::progressive::{Method, ProgressiveConfig, ProgressiveState};
use photon::render::{RenderSettings, render};
use photon::sampling::Rng;
use photon::scene::Scene;
use std::path::Path;
use std::sync::Arc;

/// The issue's analytic case, as it is: a 1×1 m quad light (radiance 1, facing down) at
/// y = 0.1, and a 10×10 cm patch (albedo 0.5) at (0, 0, −0.6) tilted toward it, just outside
/// its footprint. The camera looks at the middle of the patch from its front side.
const GRAZING_PATCH: &str = r#"
[camera]
position = [0.0, 0.05, 0.3]
look_at = [0.0, 0.0, -0.6]
up = [0.0, 1.0, 0.0]
fov = 3.0
resolution = [8, 8]

[materials.grey]
type = "diffuse"
albedo = 0.5

[[shapes]]
type = "quad"
vertices = [[-0.5, 0.1, -0.5], [0.5, 0.1, -0.5], [0.5, 0.1, 0.5], [-0.5, 0.1, 0.5]]
emission = { radiance = 1.0 }

[[shapes]]
type = "quad"
vertices = [[-0.05, -0.0353553, -0.5646447], [0.05, -0.0353553, -0.5646447], [0.05, 0.0353553, -0.6353553], [-0.05, 0.0353553, -0.6353553]]
material = "grey"
"#;

/// ρ/π · E at the patch's centre, E = ∫ cos θ cos θ′ / r² dA over the light (midpoint rule).
fn grazing_patch_radiance() -> f64 {
    let c = [0.0, 0.0, -0.6f64];
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let n = [0.0, s, s];
    let m = 1000;
    let mut e = 0.0;
    for i in 0..m {
        for j in 0..m {
            let x = (i as f64 + 0.5) / m as f64 - 0.5;
            let z = (j as f64 + 0.5) / m as f64 - 0.5;
            let d = [x - c[0], 0.1 - c[1], z - c[2]];
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let r = r2.sqrt();
            let cos_patch = (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / r;
            let cos_light = d[1] / r;
            e += cos_patch.max(0.0) * cos_light / r2 / (m * m) as f64;
        }
    }
    0.5 / std::f64::consts::PI * e
}

fn grazing_patch() -> Scene {
    let desc =
        toml_read::read_str(GRAZING_PATCH, Path::new("patch.toml"), Path::new(".")).expect("reads");
    build(&desc).expect("builds")
}

fn settings(w: u32, h: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        seed: 5,
        filter: PixelFilter::Box,
        ..RenderSettings::new(w, h, spp)
    }
}

fn photon_integrator(scene: &Scene, global: u64, caustic: u64, k: usize) -> Integrator {
    let config = PhotonConfig {
        photons: caustic,
        global_photons: Some(global),
        ..PhotonConfig::default()
    };
    let maps = trace_photons(scene, &config, &|_, _| {}).expect("traces");
    let mut s = PhotonSettings::for_scene(scene);
    s.global.k = k;
    s.caustic.k = k;
    s.light_samples = 16;
    Integrator::Photon(Box::new(PhotonIntegrator::new(s, Arc::new(maps))))
}

fn progressive(
    scene: &Scene,
    method: Method,
    passes: u32,
    photons: u64,
    radius: Option<f32>,
) -> Rgb {
    let c = ProgressiveConfig {
        method,
        width: 8,
        height: 8,
        seed: 3,
        alpha: 2.0 / 3.0,
        photons_per_pass: photons,
        initial_radius: radius,
        max_depth: 16,
        light_samples: 16,
        spectral: false,
    };
    let mut state = ProgressiveState::new(scene, c, 0).expect("valid");
    for _ in 0..passes {
        state.run_pass(scene).expect("pass");
    }
    state.image().mean()
}

#[test]
fn grazing_patch_beside_a_quad_light_gets_its_analytic_radiance() {
    // The shadow ray used to start off the surface but keep the direction and length measured
    // from the surface, so it crossed the light's own plane: 0.055 instead of 0.147.
    let want = grazing_patch_radiance();
    assert!((want - 0.1474).abs() < 5e-4, "closed form {want}");
    let scene = grazing_patch();
    let direct = DirectConfig {
        light_samples: 16,
        ..DirectConfig::default()
    };
    let mean = |integrator: &Integrator, spp| {
        render(&scene, integrator, &settings(8, 8, spp), &|_, _| {})
            .expect("renders")
            .image
            .mean()
    };
    let mut got = vec![
        ("direct", mean(&Integrator::Direct(direct), 64)),
        ("path", mean(&Integrator::Path(PathConfig::default()), 1024)),
        (
            "photon",
            mean(&photon_integrator(&scene, 20_000, 20_000, 32), 64),
        ),
    ];
    for method in [Method::Sppm, Method::Ppm] {
        got.push((method.name(), progressive(&scene, method, 64, 20_000, None)));
    }
    for (name, l) in got {
        eprintln!("grazing patch, {name}: {l} (closed form {want:.4})");
        assert!(
            (f64::from(l.x) / want - 1.0).abs() < 0.02,
            "{name}: {l} vs {want}"
        );
    }
}

/// A ceiling patch (albedo 0.5, facing down) 1 cm above a two-sided 1×1 m panel (radiance 1)
/// and overhanging its edge, as Blender writes a ceiling light; the camera looks straight up at
/// the patch 1 cm beside the panel's edge, a 3.9 mm square of it.
const PANEL_EDGE: &str = r#"
[camera]
position = [0.51, -1.0, 0.0]
look_at = [0.51, 0.11, 0.0]
up = [0.0, 0.0, 1.0]
fov = 0.2
resolution = [8, 8]

[materials.grey]
type = "diffuse"
albedo = 0.5

[[shapes]]
type = "quad"
vertices = [[-0.5, 0.1, -0.5], [0.5, 0.1, -0.5], [0.5, 0.1, 0.5], [-0.5, 0.1, 0.5]]
emission = { radiance = 1.0, two_sided = true }

[[shapes]]
type = "quad"
vertices = [[0.3, 0.11, -0.2], [0.3, 0.11, 0.2], [0.7, 0.11, 0.2], [0.7, 0.11, -0.2]]
material = "grey"
"#;

/// ρ/π · E averaged over the camera's footprint on the patch (8 × 8 points, one per pixel).
/// E at height c over the corner of a parallel a × b rectangle of radiance 1 is π times the
/// form factor (1/2π)[X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))], X = a/c,
/// Y = b/c (Howell's catalogue, B-5); the panel is four such rectangles, signed.
/// The relative standard deviation of the closed form's 8 × 8 pixels: the light falls off
/// across the footprint.
const CLOSED_FORM_SPREAD: f64 = 0.134;

fn panel_edge_radiance() -> f64 {
    let corner = |x: f64, z: f64| {
        let (a, b) = (x.abs() / 0.01, z.abs() / 0.01);
        let (sa, sb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
        x.signum() * z.signum() * (a / sa * (b / sa).atan() + b / sb * (a / sb).atan()) / 2.0
    };
    let irradiance = |x0: f64, z0: f64| {
        let (x1, x2, z1, z2) = (-0.5 - x0, 0.5 - x0, -0.5 - z0, 0.5 - z0);
        corner(x2, z2) - corner(x1, z2) - corner(x2, z1) + corner(x1, z1)
    };
    let half = 1.11 * 0.1f64.to_radians().tan();
    let mut sum = 0.0;
    for (i, j) in (0..8).flat_map(|i| (0..8).map(move |j| (i, j))) {
        let x0 = 0.51 - half + (f64::from(i) + 0.5) * half / 4.0;
        let z0 = -half + (f64::from(j) + 0.5) * half / 4.0;
        sum += irradiance(x0, z0);
    }
    0.5 / std::f64::consts::PI * sum / 64.0
}

#[test]
fn a_ceiling_one_centimetre_above_a_panel_gets_its_closed_form_radiance() {
    // Light sampling alone has unbounded variance here (the 1/r² of the area measure): at
    // 16 spp × 4 light samples the direct estimate's mean ranged from 0.41 to 1.36 of the
    // closed form between seeds, and at 256 spp its pixels spread by 0.94 about their mean.
    // Sampling the BSDF too (multiple importance sampling) bounds it: a spread of 0.18-0.23,
    // where the closed form's own is 0.134, and means within 3%.
    let want = panel_edge_radiance();
    assert!((want - 0.0740).abs() < 5e-4, "closed form {want}");
    let desc =
        toml_read::read_str(PANEL_EDGE, Path::new("panel.toml"), Path::new(".")).expect("reads");
    let scene = build(&desc).expect("builds");
    let direct = Integrator::Direct(DirectConfig::default());
    let photon = photon_integrator(&scene, 20_000, 20_000, 32);
    for seed in 1..=4 {
        for (name, integrator) in [("direct", &direct), ("photon", &photon)] {
            let s = RenderSettings {
                seed,
                ..settings(8, 8, 256)
            };
            let image = render(&scene, integrator, &s, &|_, _| {})
                .expect("renders")
                .image;
            let l = f64::from(image.mean().x);
            let spread = (image
                .pixels
                .iter()
                .map(|p| (f64::from(p.x) - l).powi(2))
                .sum::<f64>()
                / 64.0)
                .sqrt()
                / l;
            eprintln!(
                "ceiling above a panel, {name}, seed {seed}: {l:.5} (closed form {want:.5}), \
                 pixels' relative spread {spread:.3} (closed form {CLOSED_FORM_SPREAD})"
            );
            assert!(
                (l / want - 1.0).abs() < 0.05,
                "{name}, seed {seed}: {l} vs {want}"
            );
            assert!(spread < 0.35, "{name}, seed {seed}: spread {spread}");
        }
    }
}

/// Independent uniform photons (a binomial, nearly Poisson, process) of equal power on the
/// unit square of the plane y = 0, facing up: irradiance n·Φ exactly.
fn uniform_plane_map(n: usize, seed: u64) -> (PhotonMap, f32) {
    let mut rng = Rng::keyed(seed, &[]);
    let photons = (0..n)
        .map(|_| {
            let p = Vec3::new(rng.next_f32(), 0.0, rng.next_f32());
            Photon::new(p, Vec3::Y, Vec3::Y, Rgb::ONE, 2, Channel::Rgb)
        })
        .collect();
    let power = 1.0 / n as f32;
    (PhotonMap::build(MapKind::Global, photons, power), 1.0)
}

#[test]
fn k_nearest_estimates_are_unbiased_at_small_k_with_every_kernel() {
    // Counting the photon that closes the disc made the box kernel k/(k−1) too bright (+14%
    // at k = 8) and the Gaussian several per cent; k = 400 hid it.
    let (map, want) = uniform_plane_map(200_000, 17);
    let mut rng = Rng::keyed(23, &[]);
    let queries: Vec<Vec3> = (0..20_000)
        .map(|_| Vec3::new(0.1 + 0.8 * rng.next_f32(), 0.0, 0.1 + 0.8 * rng.next_f32()))
        .collect();
    for kernel in Kernel::ALL {
        for k in [1, 8, 16] {
            let g = GatherParams {
                k,
                max_radius: 0.2,
                kernel,
            };
            let mean: f64 = queries
                .iter()
                .map(|&q| f64::from(irradiance(&map, q, Vec3::Y, &g).x))
                .sum::<f64>()
                / queries.len() as f64;
            // k = 1 has a heavy tail; its mean converges slowly.
            let tol = if k == 1 { 0.04 } else { 0.012 };
            eprintln!(
                "{} k={k}: mean irradiance {mean:.4} (exact {want})",
                kernel.name()
            );
            assert!(
                (mean / f64::from(want) - 1.0).abs() < tol,
                "{} k={k}: {mean} vs {want}",
                kernel.name()
            );
        }
    }
}

/// Photons on a floor (y = 0, facing up) and on a wall (x = 0, facing +x) of a corner, with
/// varying power: a disc search that ignores the normal filter or the flattening reads the
/// other surface.
fn corner_map(n: usize, seed: u64, kind: MapKind) -> PhotonMap {
    let mut rng = Rng::keyed(seed, &[]);
    let photons = (0..n)
        .map(|i| {
            let (a, b) = (rng.next_f32(), rng.next_f32());
            let (p, normal) = if i % 2 == 0 {
                (Vec3::new(a, 0.0, b), Vec3::Y)
            } else {
                (Vec3::new(0.0, a, b), Vec3::X)
            };
            let power = Rgb::new(0.5 + rng.next_f32(), 1.0, 0.2 + a);
            Photon::new(p, -normal, normal, power, 1 + (i % 3) as u32, Channel::Rgb)
        })
        .collect();
    PhotonMap::build(kind, photons, 1e-3)
}

/// Irradiance at `p` (normal `n`) by brute force over every photon: the disc-shaped distance
/// (normal within 25°, the offset along the normal counted 3×), the k + 1 nearest, the
/// farthest closing the disc, Epanechnikov weights; photons for which `skip` holds left out.
fn brute_irradiance(
    map: &PhotonMap,
    p: Vec3,
    n: Vec3,
    k: usize,
    max_r: f32,
    skip: &dyn Fn(&Photon) -> bool,
) -> Rgb {
    let mut near: Vec<(f32, usize)> = map
        .photons()
        .iter()
        .enumerate()
        .filter(|(_, ph)| !skip(ph) && ph.normal().dot(n) >= 0.9)
        .map(|(i, ph)| {
            let d = ph.position() - p;
            let h = d.dot(n);
            (d.length_squared() + 8.0 * h * h, i)
        })
        .filter(|&(m, _)| m <= max_r * max_r)
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    // k + 1 found: the last closes the disc; 2 ≤ n ≤ k: the farthest does; one: the maximum.
    let (used, r2) = match near.len() {
        0 => return Rgb::ZERO,
        1 => (&near[..], max_r * max_r),
        n if n > k => (&near[..k], near[k].0),
        n => (&near[..n - 1], near[n - 1].0),
    };
    let mut e = Rgb::ZERO;
    for &(m, i) in used {
        let w = (1.0 - m / r2) * 2.0 / (std::f32::consts::PI * r2);
        e += map.power(i) * w;
    }
    e
}

#[test]
fn irradiance_cache_equals_a_brute_force_estimate_at_its_sites() {
    let global = corner_map(40_000, 5, MapKind::Global);
    let caustic = corner_map(10_000, 6, MapKind::Caustic);
    let g = GatherParams {
        k: 16,
        max_radius: 0.05,
        kernel: Kernel::Epanechnikov,
    };
    let stride = 4;
    let cache = IrradianceCache::build(&global, &[&caustic], stride, &g);
    let sites = global
        .photons()
        .iter()
        .filter(|ph| is_cache_site(ph, stride))
        .count();
    assert_eq!(cache.len(), sites);
    assert!(
        (sites as f64 / 40_000.0 - 0.25).abs() < 0.01,
        "a quarter of the photons are sites: {sites}"
    );
    let rest = stride as f32 / (stride - 1) as f32;
    for (i, (p, n, e)) in cache.points().enumerate().step_by(37) {
        // Every map leaves out the sites' hash class (which decides hotness) and makes up
        // for it by stride/(stride − 1).
        let apart = |map: &PhotonMap| {
            brute_irradiance(map, p, n, g.k, g.max_radius, &|ph| {
                is_cache_site(ph, stride)
            })
        };
        let want = (apart(&global) + apart(&caustic)) * rest;
        assert!(
            (e - want).abs().max_element() <= 1e-4 * want.max_element().max(1e-3),
            "site {i} at {p}: cache {e} vs brute force {want}"
        );
    }
}

#[test]
fn disc_filtered_k_nearest_irradiance_equals_brute_force() {
    let map = corner_map(20_000, 8, MapKind::Global);
    let mut rng = Rng::keyed(41, &[]);
    for q in 0..400 {
        let (a, b) = (rng.next_f32(), rng.next_f32());
        // Half on the floor, half on the wall, some right at the corner.
        let (p, n) = if q % 2 == 0 {
            (Vec3::new(a * 0.2, 0.0, b), Vec3::Y)
        } else {
            (Vec3::new(0.0, a * 0.2, b), Vec3::X)
        };
        for k in [1, 8, 50] {
            let g = GatherParams {
                k,
                max_radius: 0.04,
                kernel: Kernel::Epanechnikov,
            };
            let got = irradiance(&map, p, n, &g);
            let want = brute_irradiance(&map, p, n, k, g.max_radius, &|_| false);
            assert!(
                (got - want).abs().max_element() <= 1e-4 * want.max_element().max(1e-3),
                "query {q} at {p}, k = {k}: {got} vs brute force {want}"
            );
        }
    }
}

#[test]
fn irradiance_cache_lookups_average_to_the_exact_irradiance() {
    // A lookup reads the nearest site, so each site counts by its Voronoi area. Sites that
    // counted themselves were k/(k−2) too bright, and estimates made from the photons that
    // also place the sites were too dark (clusters raise the estimate and shrink the cells).
    let (map, want) = uniform_plane_map(200_000, 29);
    let empty = PhotonMap::build(MapKind::Caustic, Vec::new(), 1.0);
    let mut rng = Rng::keyed(31, &[]);
    for k in [8, 32] {
        let g = GatherParams {
            k,
            max_radius: 0.2,
            kernel: Kernel::Epanechnikov,
        };
        let cache = IrradianceCache::build(&map, &[&empty], 4, &g);
        let n = 50_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let q = Vec3::new(0.1 + 0.8 * rng.next_f32(), 0.0, 0.1 + 0.8 * rng.next_f32());
            sum += f64::from(cache.lookup(q, Vec3::Y, 0.2).expect("a site near").x);
        }
        let mean = sum / f64::from(n);
        eprintln!("cache lookups k={k}: mean {mean:.4} (exact {want})");
        assert!((mean / f64::from(want) - 1.0).abs() < 0.01, "k={k}: {mean}");
    }
}

#[test]
fn final_gathering_mean_does_not_depend_on_k() {
    // Was 1.035 at k = 8, 1.000 at 32 and 0.995 at 128: two biases cancelling at the default.
    // One photon trace serves every k, so the maps' own noise (about ±0.5% in the mean at
    // these counts) is common to all three and the spread between them is the k-dependence.
    let scene = builtin::load("cornell").expect("builds");
    let reference = read_image(&common::shared_dir().join("scenes/cornell-box/reference.exr"))
        .expect("reference")
        .downsample(8)
        .expect("divides");
    let config = PhotonConfig {
        photons: 1_000_000,
        global_photons: Some(250_000),
        seed: 0,
        ..PhotonConfig::default()
    };
    let maps = Arc::new(trace_photons(&scene, &config, &|_, _| {}).expect("traces"));
    let mut means = Vec::new();
    for k in [8, 32, 128] {
        let mut s = PhotonSettings::for_scene(&scene);
        s.global.k = k;
        s.caustic.k = k;
        let integrator = Integrator::Photon(Box::new(PhotonIntegrator::new(s, maps.clone())));
        let mut rs = settings(64, 64, 64);
        rs.seed = 0;
        let img = render(&scene, &integrator, &rs, &|_, _| {})
            .expect("renders")
            .image;
        let c = compare(&img, &reference, None).expect("same size");
        eprintln!(
            "cornell k={k}: mean ratios {:.4} {:.4} {:.4}, relMSE {:.5}",
            c.red.mean_ratio, c.green.mean_ratio, c.blue.mean_ratio, c.overall.rel_mse
        );
        // The estimate's blur darkens corners more as k grows: at k = 128 the red mean reads
        // 0.990 (0.9902 before surface offsets shrank to the hit points' own error, 0.9897
        // after: the photons' rounding differs), so its bound is wider; the spread below is
        // what this test is about.
        let bound = if k > 32 { 0.015 } else { 0.01 };
        for e in [c.red, c.green, c.blue] {
            assert!(
                (e.mean_ratio - 1.0).abs() < bound,
                "k={k}: {}",
                e.mean_ratio
            );
        }
        means.push(c.overall.mean_ratio);
    }
    let spread = means.iter().copied().fold(f64::MIN, f64::max)
        - means.iter().copied().fold(f64::MAX, f64::min);
    assert!(spread < 0.006, "mean ratios at k = 8, 32, 128: {means:?}");
}

#[test]
fn closed_sphere_with_one_photon_per_estimate_is_still_one() {
    // k = 1 closed its disc at the one photon found, often at distance 0: an infinite weight,
    // a NaN, and the whole sample (direct light included) dropped: the image was black.
    let scene = builtin::load("closed-sphere").expect("builds");
    let integrator = photon_integrator(&scene, 100_000, 100_000, 1);
    let mean = render(&scene, &integrator, &settings(16, 16, 16), &|_, _| {})
        .expect("renders")
        .image
        .mean();
    eprintln!("closed sphere k = 1: {mean}");
    assert!((mean.x - 1.0).abs() < 0.05, "{mean}");
}

#[test]
fn a_tiny_progressive_radius_keeps_the_direct_light() {
    // π r² of r = 1e-25 is zero in f32: every photon estimate was NaN and PPM dropped the
    // whole pixel, direct light included: a black image. Inside the closed sphere every pixel
    // sees the same emission plus direct light, so the comparison is free of edge noise.
    let scene = builtin::load("closed-sphere").expect("builds");
    let direct = render(
        &scene,
        &Integrator::Direct(DirectConfig {
            light_samples: 16,
            ..DirectConfig::default()
        }),
        &settings(8, 8, 64),
        &|_, _| {},
    )
    .expect("renders")
    .image
    .mean();
    for method in [Method::Ppm, Method::Sppm] {
        let l = progressive(&scene, method, 64, 1_000, Some(1e-25));
        eprintln!(
            "{} radius 1e-25: {l} (direct only: {direct})",
            method.name()
        );
        assert!(
            (l.x / direct.x - 1.0).abs() < 0.02,
            "{}: {l} vs direct {direct}",
            method.name()
        );
    }
}

#[test]
fn path_and_direct_fill_the_albedo_and_normal_aovs() {
    let scene = builtin::load("cornell").expect("builds");
    for integrator in [
        Integrator::Path(PathConfig::default()),
        Integrator::Direct(DirectConfig::default()),
    ] {
        let out = render(&scene, &integrator, &settings(32, 32, 2), &|_, _| {}).expect("renders");
        // The white back wall faces the camera (−z); the red wall is on the left.
        let (albedo, normal) = (out.aovs.albedo.get(16, 10), out.aovs.normal.get(16, 10));
        assert!(
            (albedo - Rgb::new(0.725, 0.71, 0.68)).abs().max_element() < 1e-3,
            "{}: back wall albedo {albedo}",
            integrator.name()
        );
        assert!(normal.z < -0.99, "{}: {normal}", integrator.name());
        let red = out.aovs.albedo.get(1, 16);
        assert!(
            red.x > 3.0 * red.y,
            "{}: left wall {red}",
            integrator.name()
        );
    }
}

/// Pixels of `img` brighter (in luminance) than `factor` times the median of their 3×3
/// neighbourhood: isolated speckles.
fn speckles(img: &photon::film::Image, factor: f32) -> usize {
    let lum = |x: u32, y: u32| photon::math::luminance(img.get(x, y));
    let mut count = 0;
    for y in 1..img.height - 1 {
        for x in 1..img.width - 1 {
            let mut around: Vec<f32> = (0..9).map(|i| lum(x + i % 3 - 1, y + i / 3 - 1)).collect();
            around.sort_by(f32::total_cmp);
            if lum(x, y) > factor * around[4].max(1e-6) {
                count += 1;
            }
        }
    }
    count
}

/// The validation suite's light-strip scene, and its file's text.
fn light_strip() -> (Scene, String) {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/light-strip/light-strip.toml");
    let text = std::fs::read_to_string(&file).expect("reads");
    let desc = toml_read::read_str(&text, &file, file.parent().expect("dir")).expect("reads");
    (build(&desc).expect("builds"), text)
}

#[test]
fn a_light_strip_flush_with_the_ceiling_makes_no_speckles() {
    // The two-sided strip lights the ceiling beside it hundreds of times more than the room;
    // cosine gather rays that found it made white speckles over the whole indirect layer.
    let (scene, text) = light_strip();
    assert!(
        text.contains("two_sided = true"),
        "the strip emits from both faces"
    );
    let config = PhotonConfig {
        photons: 200_000,
        global_photons: Some(200_000),
        ..PhotonConfig::default()
    };
    let maps = Arc::new(trace_photons(&scene, &config, &|_, _| {}).expect("traces"));
    let mut layers = Vec::new();
    for aim in [false, true] {
        let mut s = PhotonSettings::for_scene(&scene);
        s.aim_at_hot_regions = aim;
        let integrator = Integrator::Photon(Box::new(PhotonIntegrator::new(s, maps.clone())));
        let out = render(&scene, &integrator, &settings(64, 64, 8), &|_, _| {}).expect("renders");
        let n = speckles(&out.aovs.indirect, 4.0);
        eprintln!(
            "light strip, aiming at hot regions {aim}: {n} speckles, indirect mean {}",
            out.aovs.indirect.mean()
        );
        layers.push((n, out.aovs.indirect.mean()));
    }
    let ((before, mean_before), (after, mean_after)) = (layers[0], layers[1]);
    assert!(
        before >= 20,
        "the scene shows the problem: {before} speckles"
    );
    assert!(after * 5 <= before, "speckles {before} → {after}");
    // Both estimators are unbiased: their means agree, up to the cosine one's heavy tail (its
    // rare speckles carry a good part of its mean). The bias itself is checked against
    // Mitsuba by the validation suite's light-strip scene.
    assert!(
        (mean_after / mean_before - Rgb::ONE).abs().max_element() < 0.08,
        "{mean_before} vs {mean_after}"
    );
}

#[test]
fn hot_region_gathering_is_identical_on_one_and_two_threads() {
    let (scene, _) = light_strip();
    let images = common::on_one_and_two_threads(|| {
        let integrator = photon_integrator(&scene, 50_000, 50_000, 32);
        let Integrator::Photon(p) = &integrator else {
            unreachable!()
        };
        assert!(p.hot_clusters() > 0, "the strip makes hot regions");
        render(&scene, &integrator, &settings(24, 24, 2), &|_, _| {})
            .expect("renders")
            .image
    });
    assert_eq!(images[0], images[1]);
}
