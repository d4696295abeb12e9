//! Photon emission, tracing, maps, files: the photon-map issue's required evidence.

use crate::common;

use common::{chi2, chi2_z};
use photon::description::builtin;
use photon::geometry::{Disk, Shape};
use photon::io::phm;
use photon::light::{AreaLight, Light, PointLight, SpotLight};
use photon::math::{Frame, Rgb, Vec3};
use photon::photon::{Channel, MapKind, PhotonConfig, PhotonMaps, kdtree, trace_photons};
use photon::sampling::Rng;
use photon::spectrum::{Lambda, Spectrum};
use std::f64::consts::PI;

fn trace(scene: &str, config: &PhotonConfig) -> PhotonMaps {
    let scene = builtin::load(scene).expect("built-in");
    trace_photons(&scene, config, &|_, _| {}).expect("traces")
}

fn rel_close(a: Rgb, b: Rgb, tol: f32) -> bool {
    ((a - b).abs() / b.abs().max(Rgb::splat(1e-12))).max_element() < tol
}

#[test]
fn emitted_photon_powers_sum_to_each_lights_power() {
    let lights = [
        Light::Point(PointLight {
            position: Vec3::ONE,
            intensity: Spectrum::illuminant(Rgb::new(1.0, 2.0, 0.5)),
        }),
        Light::Spot(SpotLight::new(
            Vec3::ZERO,
            Vec3::new(0.2, -1.0, 0.1),
            Spectrum::illuminant(Rgb::new(3.0, 3.0, 1.0)),
            30.0,
            10.0,
        )),
        Light::Area(
            AreaLight::new(
                vec![Shape::Disk(Disk {
                    center: Vec3::Y,
                    normal: -Vec3::Y,
                    radius: 0.5,
                })],
                Spectrum::illuminant(Rgb::new(17.0, 12.0, 4.0)),
                false,
            )
            .expect("area"),
        ),
    ];
    let n = 400_000;
    for (k, light) in lights.iter().enumerate() {
        let mut rng = Rng::keyed(1, &[k as u64]);
        let mut sum = glam::DVec3::ZERO;
        for _ in 0..n {
            if let Some(e) = light.emit(rng.next_f32(), rng.next_2d(), rng.next_2d(), &Lambda::Rgb)
            {
                sum += e.flux.as_dvec3();
                assert!((e.dir.length() - 1.0).abs() < 1e-4);
                if let Light::Spot(s) = light {
                    assert!(
                        e.dir.dot(s.direction) >= s.cos_cutoff - 1e-5,
                        "spot photon outside its cone"
                    );
                }
            }
        }
        let mean = (sum / f64::from(n)).as_vec3();
        assert!(
            rel_close(mean, light.power(), 0.01),
            "light {k}: photons {mean} vs power {}",
            light.power()
        );
    }
}

#[test]
fn area_light_photon_directions_are_cosine_distributed() {
    let normal = Vec3::new(0.3, -0.9, 0.2).normalize();
    let light = AreaLight::new(
        vec![Shape::Disk(Disk {
            center: Vec3::ZERO,
            normal,
            radius: 1.0,
        })],
        Spectrum::illuminant(Rgb::ONE),
        false,
    )
    .expect("area");
    let frame = Frame::from_normal(normal);
    let (nt, np, n) = (20usize, 16usize, 300_000u64);
    let mut counts = vec![0u64; nt * np];
    let mut rng = Rng::keyed(2, &[]);
    for _ in 0..n {
        let e = light
            .emit(rng.next_f32(), rng.next_2d(), rng.next_2d(), &Lambda::Rgb)
            .expect("emits");
        let w = frame.to_local(e.dir);
        let c = f64::from(w.z).clamp(0.0, 1.0 - 1e-12);
        let phi = f64::from(w.y).atan2(f64::from(w.x)).rem_euclid(2.0 * PI);
        counts[(c * nt as f64) as usize * np
            + ((phi / (2.0 * PI) * np as f64) as usize).min(np - 1)] += 1;
    }
    let probs: Vec<f64> = (0..nt * np)
        .map(|k| {
            let (c0, c1) = ((k / np) as f64 / nt as f64, (k / np + 1) as f64 / nt as f64);
            (c1 * c1 - c0 * c0) / np as f64
        })
        .collect();
    let (stat, dof) = chi2(&counts, &probs, n);
    assert!(chi2_z(stat, dof) < 4.0, "chi² {stat} with {dof} dof");
}

#[test]
fn closed_sphere_photons_carry_exactly_the_analytic_power() {
    // Every photon of the point light (Φ = 4πI = 4π²) hits the wall; with albedo ρ = 0.5 the
    // photons stored at all depths carry Φ (1 + ρ + ρ² + …) = 2Φ in expectation.
    let phi = 4.0 * std::f32::consts::PI * std::f32::consts::PI;
    for (absorption, per_channel) in [(None, false), (Some(0.5), false), (None, true)] {
        let config = PhotonConfig {
            photons: 200_000,
            absorption,
            per_channel,
            ..PhotonConfig::default()
        };
        let maps = trace("closed-sphere", &config);
        assert!(maps.caustic.is_empty(), "no specular surfaces, no caustics");
        let g = &maps.global;
        let direct: Rgb = (0..g.len())
            .filter(|&i| g.photons()[i].is_direct())
            .map(|i| g.power(i))
            .sum();
        assert!(
            rel_close(direct, Rgb::splat(phi), 1e-3),
            "{absorption:?}/{per_channel}: direct {direct}"
        );
        let total = g.total_power();
        assert!(
            rel_close(total, Rgb::splat(2.0 * phi), 0.01),
            "{absorption:?}/{per_channel}: total {total}"
        );
        if per_channel {
            for c in [Channel::Red, Channel::Green, Channel::Blue] {
                let n = g.photons().iter().filter(|p| p.channel() == c).count();
                assert!(n > 300_000, "{c:?}: {n} photons");
            }
        }
    }
}

fn random_points(n: usize, seed: u64, f: impl Fn(Vec3) -> Vec3) -> Vec<photon::photon::Photon> {
    let mut rng = Rng::keyed(seed, &[]);
    (0..n)
        .map(|_| {
            let p = f(Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()));
            photon::photon::Photon::new(p, Vec3::Y, Vec3::Z, Rgb::ONE, 1, Channel::Rgb)
        })
        .collect()
}

#[test]
fn kdtree_queries_equal_brute_force() {
    let sets = [
        ("volume", random_points(20_000, 1, |p| p)),
        (
            "plane",
            random_points(20_000, 2, |p| Vec3::new(p.x, 0.25, p.z)),
        ),
        (
            "duplicates",
            random_points(20_000, 3, |p| (p * 8.0).floor() / 8.0),
        ),
        (
            "line",
            random_points(5_000, 4, |p| Vec3::new(p.x, 0.5, 0.5)),
        ),
    ];
    let mut rng = Rng::keyed(9, &[]);
    for (name, points) in sets {
        let mut tree = points.clone();
        // `build` sorts the points into tree order; a saved map keeps only that order and
        // rebuilds its index with `from_order`, which must answer queries as brute force does.
        // The rebuilt index is queried below, not compared with the one `build` made from it.
        kdtree::build(&mut tree);
        let index = kdtree::KdIndex::from_order(&tree);
        for q in 0..300 {
            let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 1.2 - 0.1;
            let c = if name == "plane" && q % 2 == 0 {
                Vec3::new(c.x, 0.25, c.z)
            } else {
                c
            };
            let r = 0.01 + 0.1 * rng.next_f32();
            let mut brute: Vec<f32> = tree
                .iter()
                .map(|p| (p.position() - c).length_squared())
                .filter(|&d| d <= r * r)
                .collect();
            brute.sort_by(f32::total_cmp);
            let found = index.within(&tree, c, r * r);
            assert_eq!(
                found.iter().map(|x| x.1).collect::<Vec<_>>(),
                brute,
                "{name}: radius query {q}"
            );
            for &(i, d2) in &found {
                assert_eq!((tree[i].position() - c).length_squared(), d2);
            }
            for k in [1, 8, 50] {
                let got: Vec<f32> = index
                    .nearest(&tree, c, k, r * r)
                    .iter()
                    .map(|x| x.1)
                    .collect();
                let want: Vec<f32> = brute.iter().copied().take(k).collect();
                assert_eq!(got, want, "{name}: {k}-nearest query {q}");
            }
        }
    }
}

#[test]
fn glass_sphere_makes_a_caustic_on_the_short_block() {
    let maps = trace(
        "cornell",
        &PhotonConfig {
            photons: 500_000,
            ..PhotonConfig::default()
        },
    );
    let glass_centre = Vec3::new(0.1855, 0.245, 0.169);
    let mirror_centre = Vec3::new(0.3685, 0.41, 0.35125);
    // Nothing is stored on (or piles up at) the specular spheres; the block tops they rest on
    // touch them, so photons on those planes are not on a sphere.
    for map in [&maps.caustic, &maps.global] {
        for p in map.photons() {
            for (c, top) in [(glass_centre, 0.165), (mirror_centre, 0.33)] {
                let d = ((p.position() - c).length() - 0.08).abs();
                assert!(
                    d > 1e-3 || (p.position().y - top).abs() < 1e-5,
                    "{} photon stored on a sphere at {}",
                    map.kind.name(),
                    p.position()
                );
            }
        }
    }
    // Caustic photons on the short block's top (y = 0.165): dense in a disc under the sphere.
    let top: Vec<Vec3> = maps
        .caustic
        .photons()
        .iter()
        .map(|p| p.position())
        .filter(|p| {
            (p.y - 0.165).abs() < 1e-4 && p.x > 0.082 && p.x < 0.29 && p.z > 0.065 && p.z < 0.272
        })
        .collect();
    // The caustic lies where the line from the light's centre through the sphere's centre
    // meets the block top, spread over a few centimetres (the top is inside the focal length).
    let light_centre = Vec3::new(0.278, 0.5478, 0.2795);
    let to_top = (glass_centre.y - 0.165) / (light_centre.y - glass_centre.y);
    let focus = glass_centre + (glass_centre - light_centre) * to_top;
    let radius = 0.04;
    let under = |p: &Vec3| Vec3::new(p.x - focus.x, 0.0, p.z - focus.z).length() < radius;
    let inside = top.iter().filter(|p| under(p)).count() as f32;
    let outside = top.len() as f32 - inside;
    // The top is ≈ 0.0296 m².
    let disc = std::f32::consts::PI * radius * radius;
    let density_in = inside / disc;
    let density_out = outside.max(1.0) / (0.0296 - disc);
    eprintln!(
        "caustic under the glass sphere: {inside} photons, density ratio {:.1}",
        density_in / density_out
    );
    assert!(
        inside > 1000.0,
        "only {inside} caustic photons under the sphere"
    );
    assert!(
        density_in > 20.0 * density_out,
        "caustic density {density_in} vs elsewhere {density_out}"
    );
}

#[test]
fn red_bleeds_onto_the_tall_block_face_toward_the_red_wall() {
    let maps = trace(
        "cornell",
        &PhotonConfig {
            photons: 500_000,
            ..PhotonConfig::default()
        },
    );
    // Tall block face from (0.4230, y, 0.2470) to (0.4720, y, 0.4060): faces +x, the red wall.
    let a = Vec3::new(0.4230, 0.0, 0.2470);
    let b = Vec3::new(0.4720, 0.0, 0.4060);
    let along = (b - a).normalize();
    let normal = along.cross(Vec3::Y).normalize();
    let normal = if normal.x < 0.0 { -normal } else { normal };
    let mut power = Rgb::ZERO;
    let g = &maps.global;
    let mut count = 0;
    for (i, p) in g.photons().iter().enumerate() {
        let d = p.position() - a;
        let t = d.dot(along);
        if d.dot(normal).abs() < 1e-4 && t > 0.0 && t < (b - a).length() && p.position().y < 0.33 {
            power += g.power(i);
            count += 1;
        }
    }
    let (rg, rb) = (power.x / power.y, power.x / power.z);
    eprintln!(
        "tall block face toward the red wall: {count} photons, red/green {rg:.2}, red/blue {rb:.2}"
    );
    assert!(count > 500);
    assert!(rg > 4.0 && rb > 10.0, "power {power}");
}

#[test]
fn maps_save_load_and_refuse_bad_files() {
    let dir = common::temp_dir("phm");
    let maps = trace(
        "cornell",
        &PhotonConfig {
            photons: 20_000,
            seed: 5,
            ..PhotonConfig::default()
        },
    );
    let path = dir.join("c.phm");
    phm::save(&maps, &path).expect("saves");
    let loaded = phm::load(&path).expect("loads");
    assert_eq!(loaded, maps, "save → load gives identical maps");
    // Queries on the loaded tree agree without a rebuild.
    let q = Vec3::new(0.3, 0.0, 0.3);
    assert_eq!(loaded.global.within(q, 0.05), maps.global.within(q, 0.05));

    let cornell = builtin::load("cornell").expect("builds");
    let seed = builtin::load("seed").expect("builds");
    phm::check_scene(&loaded, &path, &cornell.name, cornell.content_hash(), false)
        .expect("same scene");
    let err = phm::check_scene(&loaded, &path, &seed.name, seed.content_hash(), false)
        .expect_err("other scene");
    assert!(
        err.to_string().contains("traced for scene 'cornell'"),
        "{err}"
    );
    phm::check_scene(&loaded, &path, &seed.name, seed.content_hash(), true).expect("--force");

    let bytes = std::fs::read(&path).expect("read");
    let bad = dir.join("bad.phm");
    for (what, data) in [
        ("truncated", bytes[..bytes.len() / 2].to_vec()),
        ("truncated header", bytes[..30].to_vec()),
        ("empty", Vec::new()),
        ("bit flip", {
            let mut b = bytes.clone();
            let k = b.len() * 2 / 3;
            b[k] ^= 0x10;
            b
        }),
        ("bad magic", {
            let mut b = bytes.clone();
            b[0] = b'X';
            b
        }),
        ("future version", {
            let mut b = bytes.clone();
            b[8] = 99;
            b
        }),
    ] {
        std::fs::write(&bad, &data).expect("write");
        let err = phm::load(&bad).expect_err(what);
        assert!(err.to_string().contains("bad.phm"), "{what}: {err}");
    }
}

#[test]
fn one_thread_and_two_threads_give_identical_maps() {
    let scene = builtin::load("cornell").expect("builds");
    let config = PhotonConfig {
        photons: 30_000,
        ..PhotonConfig::default()
    };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| trace_photons(&scene, &config, &|_, _| {}).expect("traces"))
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a, b);
    assert!(!a.map(MapKind::Caustic).is_empty() && !a.map(MapKind::Global).is_empty());
}
