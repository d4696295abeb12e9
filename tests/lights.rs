//! Every light's reported power against a Monte Carlo integral of its emission, and light
//! sampling against closed-form irradiance.

use crate::common;

use photon::description::builtin;
use photon::geometry::{Disk, Shape, Triangle};
use photon::light::{AreaLight, Light, PointLight, SpotLight};
use photon::math::{Rgb, Vec2, Vec3};
use photon::sampling::{Rng, uniform_sphere};
use photon::spectrum::{Lambda, Spectrum};
use std::f32::consts::PI;

const N: usize = 1_000_000;

fn close(a: Rgb, b: Rgb, rel: f32) -> bool {
    ((a - b).abs() / b.abs().max(Rgb::splat(1e-12))).max_element() < rel
}

/// Φ = ∫_A ∫_S² L(x, ω) max(n·ω, 0) dω dA, sampled uniformly in area and direction.
fn area_power_mc(l: &AreaLight, seed: u64) -> Rgb {
    let mut rng = Rng::keyed(seed, &[]);
    let areas: Vec<f32> = l.shapes.iter().map(Shape::area).collect();
    let total: f32 = areas.iter().sum();
    let mut sum = [0.0f64; 3];
    for _ in 0..N {
        // Pick a shape by area, then a point on it: overall uniform by area.
        let mut u = rng.next_f32() * total;
        let mut k = 0;
        while k + 1 < areas.len() && u >= areas[k] {
            u -= areas[k];
            k += 1;
        }
        let s = l.shapes[k].sample_area(rng.next_2d());
        let w = uniform_sphere(rng.next_2d());
        let e = l.emitted(s.n, w, &Lambda::Rgb) * s.n.dot(w).abs() * total * 4.0 * PI;
        for c in 0..3 {
            sum[c] += f64::from(e[c]);
        }
    }
    Rgb::new(sum[0] as f32, sum[1] as f32, sum[2] as f32) / N as f32
}

#[test]
fn area_light_power_matches_monte_carlo() {
    let quad = vec![
        Shape::Triangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0))),
        Shape::Triangle(Triangle::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y)),
    ];
    let disk = vec![Shape::Disk(Disk {
        center: Vec3::ONE,
        normal: Vec3::new(0.0, 0.6, 0.8),
        radius: 0.7,
    })];
    for (shapes, two_sided) in [(quad.clone(), false), (quad, true), (disk, false)] {
        let l = AreaLight::new(
            shapes,
            Spectrum::illuminant(Rgb::new(17.0, 12.0, 4.0)),
            two_sided,
        )
        .expect("has area");
        let mc = area_power_mc(&l, 9);
        assert!(
            close(mc, l.power(), 0.01),
            "two-sided {two_sided}: MC {mc} vs reported {}",
            l.power()
        );
    }
}

#[test]
fn point_and_spot_power_match_monte_carlo() {
    let mut rng = Rng::keyed(11, &[]);
    let point = PointLight {
        position: Vec3::ZERO,
        intensity: Spectrum::illuminant(Rgb::new(1.0, 2.0, 3.0)),
    };
    let spot = SpotLight::new(
        Vec3::ZERO,
        Vec3::new(0.3, -1.0, 0.2),
        Spectrum::illuminant(Rgb::new(5.0, 5.0, 1.0)),
        40.0,
        15.0,
    );
    // Power = ∮ I(ω) dω, with the intensity I(ω) = radiance · d² that next-event estimation
    // sees from a point at distance d in direction ω: the lights' sampling against their power.
    let intensity = |light: &Light, w: Vec3| {
        let d = 2.5f32;
        light
            .sample_li(w * d, 0.5, Vec2::splat(0.5), &Lambda::Rgb)
            .map_or(Rgb::ZERO, |s| s.radiance * s.pdf.recip() * d * d)
    };
    let (point_light, spot_light) = (Light::Point(point), Light::Spot(spot));
    let (mut sp, mut ss) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for _ in 0..N {
        let w = uniform_sphere(rng.next_2d());
        sp += (intensity(&point_light, w) * 4.0 * PI).as_dvec3();
        ss += (intensity(&spot_light, w) * 4.0 * PI).as_dvec3();
    }
    let point_mc = (sp / N as f64).as_vec3();
    assert!(
        close(point_mc, point_light.power(), 1e-4),
        "point MC {point_mc} vs {}",
        point_light.power()
    );
    let spot_mc = (ss / N as f64).as_vec3();
    assert!(
        close(spot_mc, spot.power(), 0.01),
        "spot MC {spot_mc} vs {}",
        spot.power()
    );
}

#[test]
fn disk_light_sampling_gives_the_closed_form_irradiance() {
    // On the axis of a disk of radius R at height h: E = π L R² / (h² + R²).
    let (r, h, radiance) = (1.0f32, 1.5f32, 3.0f32);
    let l = AreaLight::new(
        vec![Shape::Disk(Disk {
            center: Vec3::new(0.0, 0.0, h),
            normal: -Vec3::Z,
            radius: r,
        })],
        Spectrum::illuminant(Rgb::splat(radiance)),
        false,
    )
    .expect("has area");
    let mut rng = Rng::keyed(12, &[]);
    let mut e = 0.0f64;
    for _ in 0..N {
        let u = rng.next_f32();
        if let Some(s) = l.sample_li(Vec3::ZERO, u, rng.next_2d(), &Lambda::Rgb) {
            e += f64::from(s.radiance.x * s.wi.z / s.pdf);
        }
    }
    let e = e / N as f64;
    let want = f64::from(PI * radiance * r * r / (h * h + r * r));
    assert!((e - want).abs() / want < 0.005, "irradiance {e} vs {want}");
    // Seen from behind, a one-sided light gives nothing.
    assert!(
        l.sample_li(
            Vec3::new(0.0, 0.0, 3.0),
            0.5,
            glam::Vec2::splat(0.5),
            &Lambda::Rgb
        )
        .is_none()
    );
}

#[test]
fn built_in_lights_have_the_specified_power() {
    let seed = builtin::load("seed").expect("builds");
    assert_eq!(seed.lights().len(), 1);
    assert!(
        close(seed.total_power(), Rgb::splat(314.159), 1e-4),
        "{}",
        seed.total_power()
    );
    let cornell = builtin::load("cornell").expect("builds");
    // SCENE.md: Φ = π · 0.01365 m² · (17, 12, 4).
    let want = Rgb::new(0.72901, 0.51459, 0.17153);
    assert!(
        close(cornell.total_power(), want, 1e-3),
        "{}",
        cornell.total_power()
    );
}

/// A directional light of irradiance E at angle θ from a diffuse plane of albedo ρ: the plane
/// receives E cos θ (photons: Σ flux / area) and reflects radiance ρ E cos θ / π (direct light).
#[test]
fn directional_light_gives_the_closed_form_irradiance() {
    use photon::description::{build::build, toml_read::read_str};
    use photon::film::PixelFilter;
    use photon::integrator::{DirectConfig, Integrator};
    use photon::photon::{PhotonConfig, trace_photons};
    use photon::render::{RenderSettings, render};
    let theta = 35f32.to_radians();
    let (e, rho) = (Rgb::new(2.0, 3.0, 4.0), 0.5);
    let text = format!(
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nfov = 30\n\
         [materials.m]\ntype = \"diffuse\"\nalbedo = {rho}\n\
         [[shapes]]\ntype = \"quad\"\nvertices = [[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]]\nmaterial = \"m\"\n\
         [[lights]]\ntype = \"directional\"\ndirection = [{}, 0, {}]\nirradiance = [2, 3, 4]\n",
        theta.sin(),
        -theta.cos()
    );
    let scene = build(
        &read_str(
            &text,
            std::path::Path::new("d.toml"),
            std::path::Path::new(""),
        )
        .expect("reads"),
    )
    .expect("builds");
    // Power: E over the disk of the scene's bounding sphere.
    let light = &scene.lights()[0];
    let Light::Directional(d) = light else {
        panic!("{light:?}")
    };
    assert!(close(
        light.power(),
        e * PI * d.aperture.radius * d.aperture.radius,
        1e-5
    ));

    let integrator = Integrator::Direct(DirectConfig::default());
    let s = RenderSettings {
        seed: 0,
        filter: PixelFilter::Box,
        ..RenderSettings::new(8, 8, 1)
    };
    let img = render(&scene, &integrator, &s, &|_, _| {})
        .expect("renders")
        .image;
    let expected = e * rho * theta.cos() / PI;
    for p in &img.pixels {
        assert!(close(*p, expected, 1e-4), "{p} vs {expected}");
    }

    let config = PhotonConfig {
        photons: 400_000,
        ..PhotonConfig::default()
    };
    let maps = trace_photons(&scene, &config, &|_, _| {}).expect("traces");
    let g = &maps.global;
    let direct: Rgb = (0..g.len())
        .filter(|&i| g.photons()[i].is_direct())
        .map(|i| g.power(i))
        .sum();
    let irradiance = direct / 16.0;
    assert!(
        close(irradiance, e * theta.cos(), 0.02),
        "photon irradiance {irradiance} vs {}",
        e * theta.cos()
    );
}

/// An emissive texture: a quad light, black on its left half and white on its right (a 2 × 1
/// PNG, read bilinearly with wrap-around: a triangle wave of mean ½). Its power is half the
/// untextured light's; its photons carry that power; the floor is lit more under the white
/// half (light sampling reads the texture on the light's side); and the camera, looking up,
/// sees the white half on the same side (the scene reads it at the hit).
#[test]
fn emissive_texture_sets_power_sampling_and_appearance_alike() {
    use photon::description::{build::build, toml_read::read_str};
    use photon::integrator::{DirectConfig, Integrator};
    use photon::render::{RenderSettings, render};
    let dir = common::temp_dir("emissive-texture");
    let mut img = image::RgbImage::new(2, 1);
    img.put_pixel(1, 0, image::Rgb([255, 255, 255]));
    img.save(dir.join("half.png")).expect("png");
    let scene_text = |camera: &str| {
        format!(
            r#"
{camera}
[materials.floor]
type = "diffuse"
albedo = 0.5
[[shapes]]
type = "quad"
vertices = [[-2.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0], [-2.0, 0.0, -2.0]]
material = "floor"
[[lights]]
type = "quad"
vertices = [[-1.0, 2.0, -1.0], [1.0, 2.0, -1.0], [1.0, 2.0, 1.0], [-1.0, 2.0, 1.0]]
radiance = 4.0
texture = "half.png"
"#
        )
    };
    let load = |camera: &str| {
        let text = scene_text(camera);
        let desc = read_str(&text, &dir.join("t.toml"), &dir).expect("reads");
        build(&desc).expect("builds")
    };
    // From above, looking down at the floor; from below, looking up at the light.
    let down = load(
        "[camera]\nposition = [0.0, 1.0, 0.001]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\nfov = 100.0",
    );
    let up = load(
        "[camera]\nposition = [0.0, 0.5, 0.001]\nlook_at = [0.0, 2.0, 0.0]\nup = [0.0, 0.0, -1.0]\nfov = 90.0",
    );
    let Light::Area(light) = &down.lights()[0] else {
        panic!("an area light")
    };
    let untextured = 4.0 * PI * 4.0;
    assert!(
        (light.power().x / untextured - 0.5).abs() < 0.01,
        "power {} of {untextured}",
        light.power().x
    );
    let mut rng = Rng::keyed(21, &[]);
    let mut flux = 0.0f64;
    let n = 400_000;
    for _ in 0..n {
        if let Some(e) =
            down.lights()[0].emit(rng.next_f32(), rng.next_2d(), rng.next_2d(), &Lambda::Rgb)
        {
            flux += f64::from(e.flux.x);
        }
    }
    let mean = flux / f64::from(n);
    assert!(
        (mean / f64::from(light.power().x) - 1.0).abs() < 0.01,
        "photons carry {mean}, power {}",
        light.power().x
    );
    let settings = RenderSettings {
        seed: 1,
        filter: photon::film::PixelFilter::Box,
        ..RenderSettings::new(16, 16, 64)
    };
    let direct = Integrator::Direct(DirectConfig::default());
    let floor = render(&down, &direct, &settings, &|_, _| {})
        .expect("renders")
        .image;
    let sky = render(&up, &direct, &settings, &|_, _| {})
        .expect("renders")
        .image;
    // Looking down with up = −z, the image's right is world +x; looking up, its right is −x.
    // Compare the images' left and right thirds.
    let side = |img: &photon::film::Image, right: bool| {
        let mut s = 0.0;
        for y in 0..16 {
            for x in 0..5 {
                let x = if right { 15 - x } else { x };
                s += img.get(x, y).x;
            }
        }
        s
    };
    let (floor_l, floor_r) = (side(&floor, false), side(&floor, true));
    let (light_l, light_r) = (side(&sky, false), side(&sky, true));
    assert!(
        floor_r > 1.2 * floor_l,
        "the floor is brighter at +x, under the white half: {floor_l} vs {floor_r}"
    );
    assert!(
        light_l > 2.0 * light_r,
        "looking up, the white half (+x) is on the image's left: {light_l} vs {light_r}"
    );
}
