//! Spectral transport against closed forms: a prism under a collimated white beam (Snell's
//! law with the glass's Sellmeier coefficients, ray by ray and as the rainbow on a screen),
//! white furnaces at every wavelength, and spectral rendering of RGB scenes against RGB
//! rendering.

use crate::common;

use common::media::scene;

use photon::film::Image;
use photon::integrator::{Integrator, PathConfig, RayStats};
use photon::material::{Dispersion, TransportMode};
use photon::math::{Ray, Rgb, Vec3};
use photon::render_job::RenderJob;
use photon::sampling::Rng;
use photon::scene::Scene;
use photon::settings::RenderOptions;
use photon::spectrum::{
    Lambda, Wavelengths, cie_xyz, d65, visible_wavelength_cdf, xyz_to_linear_srgb,
};

/// The prism: N-SF11, a dense flint (a large spread for a short throw), apex 60°, in the
/// xz plane, extruded along y.
const GLASS: &str = "sf11";
/// Cross-section vertices (x, z): the base and the apex.
const BASE_LEFT: [f32; 2] = [-0.3, 0.0];
const BASE_RIGHT: [f32; 2] = [0.3, 0.0];
const APEX: [f32; 2] = [0.0, 0.519_615_2];
/// Incidence angle on the left face, degrees.
const INCIDENCE_DEG: f32 = 60.0;
/// Distance from the prism's exit to the screen along the exit ray of 550 nm.
const THROW: f32 = 1.5;
/// The wavelength the camera is aimed at: the middle of the rainbow (blue spreads most).
const AIM_NM: f32 = 470.0;

/// Wavelengths whose hero is `lambda_nm`.
fn hero(lambda_nm: f32) -> Lambda {
    Lambda::sampled(Wavelengths::sample_visible(visible_wavelength_cdf(
        lambda_nm,
    )))
}

fn v(x: f32, z: f32) -> Vec3 {
    Vec3::new(x, 0.0, z)
}

/// The left face's outward normal, and the beam: its direction, and the point where its
/// axis enters (the middle of the left face).
fn beam() -> (Vec3, Vec3, Vec3) {
    let (l, a) = (v(BASE_LEFT[0], BASE_LEFT[1]), v(APEX[0], APEX[1]));
    let along = (a - l).normalize();
    let normal = Vec3::new(-along.z, 0.0, along.x); // outward: away from the base's right end
    let t = INCIDENCE_DEG.to_radians();
    // Arriving from below the normal, so the ray bends toward the base.
    let dir = (-normal * t.cos() + along * t.sin()).normalize();
    (normal, dir, 0.5 * (l + a))
}

/// Snell's law in vector form, `eta` = n_incident / n_transmitted, `n` facing the incident
/// side: the refracted direction (the closed form the renderer is checked against).
fn snell(d: Vec3, n: Vec3, eta: f32) -> Vec3 {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    assert!(sin2_t < 1.0, "no total internal reflection in this prism");
    (d * eta + n * (eta * cos_i - (1.0 - sin2_t).sqrt())).normalize()
}

/// Where the beam's axis leaves the prism at wavelength `lambda_nm`, and which way.
fn analytic_exit(lambda_nm: f32) -> (Vec3, Vec3) {
    let n = Dispersion::named(GLASS)
        .and_then(|d| d.ior(lambda_nm))
        .expect("a dispersive glass");
    let (left_normal, dir, entry) = beam();
    let inside = snell(dir, left_normal, 1.0 / n);
    let (r, a) = (v(BASE_RIGHT[0], BASE_RIGHT[1]), v(APEX[0], APEX[1]));
    let along = (r - a).normalize();
    let right_normal = Vec3::new(-along.z, 0.0, along.x);
    // Meet the right face: (entry + t·inside − a)·right_normal = 0.
    let t = (a - entry).dot(right_normal) / inside.dot(right_normal);
    let exit = entry + inside * t;
    (exit, snell(inside, -right_normal, n))
}

/// The prism, lit by a narrow spot light along the beam, and a white screen across the exit
/// ray of 550 nm, seen square on by the camera.
fn prism_scene(width: u32, height: u32) -> String {
    let (_, dir, entry) = beam();
    let light = entry - dir * 3.0;
    let (exit, out) = analytic_exit(550.0);
    let centre = exit + out * THROW;
    let aim = on_screen(AIM_NM);
    let right = out.cross(Vec3::Y).normalize();
    let corner = |s: f32, t: f32| centre + right * s + Vec3::Y * t;
    let quad = [
        corner(-0.6, -0.3),
        corner(0.6, -0.3),
        corner(0.6, 0.3),
        corner(-0.6, 0.3),
    ];
    let camera = aim - out;
    let f = |p: Vec3| format!("[{}, {}, {}]", p.x, p.y, p.z);
    let (bl, br, ap) = (BASE_LEFT, BASE_RIGHT, APEX);
    // Triangular prism, y from −0.5 to 0.5; each face's normal (v1 − v0) × (v2 − v0) out.
    format!(
        r#"
[camera]
position = {camera}
look_at = {aim}
up = [0.0, 1.0, 0.0]
fov = {fov}

[render]
width = {width}
height = {height}
filter = "box"

[materials.prism]
type = "glass"
glass = "{GLASS}"

[materials.screen]
type = "diffuse"
albedo = 0.8

[[shapes]]
type = "triangles"
material = "prism"
positions = [[{blx}, -0.5, {blz}], [{brx}, -0.5, {brz}], [{apx}, -0.5, {apz}],
             [{blx}, 0.5, {blz}], [{brx}, 0.5, {brz}], [{apx}, 0.5, {apz}]]
indices = [[0, 1, 2], [3, 5, 4], [0, 4, 1], [0, 3, 4], [1, 5, 2], [1, 4, 5],
           [2, 3, 0], [2, 5, 3]]

[[shapes]]
type = "quad"
material = "screen"
vertices = [{q0}, {q1}, {q2}, {q3}]

[[lights]]
type = "spot"
position = {light}
look_at = {entry}
intensity = 1000.0
angle = 0.3
falloff = 0.0
"#,
        camera = f(camera),
        aim = f(aim),
        fov = FOV_Y_DEG,
        blx = bl[0],
        blz = bl[1],
        brx = br[0],
        brz = br[1],
        apx = ap[0],
        apz = ap[1],
        q0 = f(quad[0]),
        q1 = f(quad[1]),
        q2 = f(quad[2]),
        q3 = f(quad[3]),
        light = f(light),
        entry = f(entry),
    )
}

/// The camera's vertical field of view: 0.6 × 0.15 of the screen at 64 × 16, the whole
/// visible spectrum.
const FOV_Y_DEG: f32 = 8.578;

/// The description `toml` gives (its `[render]` table is what [`render`] starts from).
fn desc(toml: &str) -> photon::description::SceneDesc {
    let here = std::path::Path::new(".");
    photon::description::toml_read::read_str(toml, &here.join("scene.toml"), here)
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_prism_bends_each_wavelength_as_snell_and_sellmeier_say() {
    // Ray by ray through the renderer's own scene: the glass's index at the path's hero
    // wavelength, its refraction, in and out.
    let scene = scene(&prism_scene(64, 16));
    let (_, dir, entry) = beam();
    for lambda_nm in [450.0, 550.0, 650.0] {
        let mut lambda = hero(lambda_nm);
        let mut ray = Ray::new(entry - dir * 0.5, dir);
        let mut refractions = 0;
        for _ in 0..2 {
            let hit = scene
                .intersect(&ray, f32::INFINITY)
                .expect("meets the prism");
            let wo = -ray.dir;
            let (material, frame) = scene.surface(&hit, wo, &mut lambda);
            // u_lobe just below 1 takes refraction wherever Fresnel leaves any.
            let s = material
                .sample(
                    frame.to_local(wo),
                    0.999_99,
                    glam::Vec2::ZERO,
                    TransportMode::Radiance,
                )
                .expect("refracts");
            let wi = frame.to_world(s.wi);
            assert!(wi.dot(hit.ng) * wo.dot(hit.ng) < 0.0, "went through");
            refractions += 1;
            ray = Ray::new(hit.offset_origin(wi), wi);
        }
        assert_eq!(refractions, 2);
        assert!(
            lambda.is_hero_only(),
            "a dispersive glass keeps the hero alone"
        );
        let (exit, out) = analytic_exit(lambda_nm);
        let angle = ray.dir.dot(out).clamp(-1.0, 1.0).acos().to_degrees();
        eprintln!(
            "{lambda_nm} nm: deviation {:.4}° (Snell: {:.4}°), {angle:.5}° apart",
            dir.dot(ray.dir).clamp(-1.0, 1.0).acos().to_degrees(),
            dir.dot(out).clamp(-1.0, 1.0).acos().to_degrees()
        );
        assert!(
            angle < 0.01,
            "{lambda_nm} nm leaves at {:?}, Snell says {out:?} ({angle}° apart)",
            ray.dir
        );
        assert!(
            (ray.origin - exit).length() < 1e-3,
            "{:?} vs {exit:?}",
            ray.origin
        );
    }
    // The deviations the test stands on: blue bends most.
    let deviation = |l: f32| beam().1.dot(analytic_exit(l).1).acos().to_degrees();
    let (b, g, r) = (deviation(450.0), deviation(550.0), deviation(650.0));
    assert!(b > g && g > r, "{b} {g} {r}");
    assert!(b - r > 2.5, "SF11 spreads 450 to 650 nm by {}°", b - r);
}

/// The pixel column (continuous, 0 at the left edge) where the camera of [`prism_scene`]
/// sees the point `p`.
fn column_of(p: Vec3, width: u32, height: u32) -> f32 {
    let out = analytic_exit(550.0).1;
    let camera = on_screen(AIM_NM) - out;
    let forward = out;
    let right = forward.cross(Vec3::Y).normalize();
    let d = p - camera;
    let sx = d.dot(right) / d.dot(forward);
    let aspect = width as f32 / height as f32;
    let tan_half = (0.5 * FOV_Y_DEG.to_radians()).tan();
    (sx / (tan_half * aspect) + 1.0) * 0.5 * width as f32
}

/// Where the beam's axis at `lambda_nm` meets the screen.
fn on_screen(lambda_nm: f32) -> Vec3 {
    let (exit550, out550) = analytic_exit(550.0);
    let centre = exit550 + out550 * THROW;
    let (exit, out) = analytic_exit(lambda_nm);
    let t = (centre - exit).dot(out550) / out.dot(out550);
    exit + out * t
}

/// Where the beam's axis at `lambda_nm` meets the screen, as a pixel column.
fn predicted_column(lambda_nm: f32, width: u32, height: u32) -> f32 {
    column_of(on_screen(lambda_nm), width, height)
}

/// The column centroid of each RGB channel the formula predicts: the beam's white (an RGB
/// white light is D65) times each wavelength's colour-matching weights, placed where Snell
/// sends it.
fn predicted_centroids(width: u32, height: u32) -> Rgb {
    let (mut num, mut den) = (Rgb::ZERO, Rgb::ZERO);
    for l in (380..=780).map(|l| l as f32) {
        let rgb = xyz_to_linear_srgb(cie_xyz(l)) * d65(l);
        // What lands off the image (the far ultraviolet end, through the Sellmeier pole's
        // steep rise) is in neither sum.
        let x = predicted_column(l, width, height);
        let inside = (0.0..width as f32).contains(&x);
        assert!(
            inside || !(400.0..=700.0).contains(&l),
            "{l} nm lands off the image, at {x}"
        );
        if inside {
            num += rgb * x;
            den += rgb;
        }
    }
    num / den
}

fn column_centroids(img: &Image) -> Rgb {
    let (mut num, mut den) = (Rgb::ZERO, Rgb::ZERO);
    for y in 0..img.height {
        for x in 0..img.width {
            let c = img.get(x, y);
            num += c * (x as f32 + 0.5);
            den += c;
        }
    }
    num / den
}

fn render(toml: &str, options: &[(&str, &str)]) -> Image {
    let desc = desc(toml);
    let scene = photon::description::build::build(&desc).unwrap_or_else(|e| panic!("{e}"));
    let mut o = RenderOptions::default();
    for (k, v) in options {
        o.set_text(k, v).expect(k);
    }
    let job = RenderJob::new(&scene, &desc.render, o).expect("valid settings");
    job.render(&|_| {}, &std::sync::atomic::AtomicBool::new(false))
        .expect("renders")
        .image
}

#[test]
fn the_rainbow_of_a_prism_lies_where_the_formula_puts_it() {
    let (w, h) = (64, 16);
    let toml = prism_scene(w, h);
    let img = render(
        &toml,
        &[
            ("integrator", "sppm"),
            ("spectral", "true"),
            ("passes", "48"),
            ("photons_per_pass", "40000"),
            ("radius", "0.002"),
        ],
    );
    let measured = column_centroids(&img);
    let predicted = predicted_centroids(w, h);
    let (c450, c650) = (predicted_column(450.0, w, h), predicted_column(650.0, w, h));
    eprintln!(
        "channel centroids: measured {measured:?}, predicted {predicted:?}; 450 nm at {c450}, 650 nm at {c650}"
    );
    assert!(
        (c450 - c650).abs() > 15.0,
        "the spread 450–650 nm covers {} columns",
        (c450 - c650).abs()
    );
    for (c, (m, p)) in ["R", "G", "B"]
        .iter()
        .zip(measured.to_array().into_iter().zip(predicted.to_array()))
    {
        assert!(
            (m - p).abs() < 1.5,
            "{c} centroid at column {m}, the formula puts it at {p} (450 nm at {c450}, 650 at {c650})"
        );
    }
    // Blue lies toward where 450 nm lands, red toward 650.
    assert!((measured.z - c450).abs() < (measured.x - c450).abs());
    // RGB rendering has no dispersion: the beam stays white, in one spot where the d line
    // goes.
    let rgb = render(
        &toml,
        &[
            ("integrator", "sppm"),
            ("passes", "8"),
            ("photons_per_pass", "40000"),
            ("radius", "0.002"),
        ],
    );
    let white = column_centroids(&rgb);
    let d_line = predicted_column(photon::material::LINE_D_NM, w, h);
    for m in white.to_array() {
        assert!(
            (m - d_line).abs() < 1.0,
            "{white:?} vs the d line at {d_line}"
        );
    }
}

/// Radiance a path of `lambda` brings back along `ray`, at its wavelengths.
fn values(scene: &Scene, ray: &Ray, lambda: Lambda, samples: u32) -> Rgb {
    let integrator = Integrator::Path(PathConfig::default());
    let mut sum = Rgb::ZERO;
    let mut stats = RayStats::default();
    for i in 0..samples {
        let mut rng = Rng::keyed(7, &[u64::from(i)]);
        let mut l = lambda;
        sum += integrator
            .sample(scene, ray, &mut l, &mut rng, &mut stats)
            .beauty;
    }
    sum / samples as f32
}

/// What comes back along rays from (0, 0, 4) toward each target, over what a uniform white
/// sky around the scene of `shapes` sends, checked to be 1 at every wavelength. `hero_only`:
/// the paths toward the targets meet a dispersive glass, after which the hero goes on alone
/// (its value tripled, the others zero).
fn check_furnace(shapes: &str, targets: &[(&str, Vec3)], hero_only: bool, samples: u32) {
    let toml = format!(
        r#"
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov = 40

{shapes}

[[lights]]
type = "environment"
radiance = 1.0
"#
    );
    let scene = scene(&toml);
    for lambda_nm in (380..=780).step_by(50).map(|l| l as f32) {
        let lambda = hero(lambda_nm);
        let sky = lambda.illuminant(Rgb::ONE);
        for &(what, target) in targets {
            let origin = Vec3::new(0.0, 0.0, 4.0);
            let ray = Ray::new(origin, (target - origin).normalize());
            let ratio = values(&scene, &ray, lambda, samples) / sky;
            let measured = if hero_only {
                vec![ratio.x / 3.0]
            } else {
                ratio.to_array().to_vec()
            };
            for m in measured {
                assert!(
                    (m - 1.0).abs() < 0.02,
                    "{lambda_nm} nm at {what}: {ratio:?} of the sky"
                );
            }
        }
    }
}

#[test]
fn a_white_furnace_stays_at_most_one_at_every_wavelength() {
    // Lossless things inside a uniform white sky: what comes back is what the sky sends, at
    // every wavelength, and never more. A white diffuse sphere and a dispersive diamond (the
    // light that enters it leaves it)...
    let white = r#"
[materials.white]
type = "diffuse"
albedo = 1.0

[[shapes]]
type = "sphere"
center = [-0.6, 0.0, 0.0]
radius = 0.5
material = "white"
"#;
    let diamond = r#"
[materials.gem]
type = "glass"
glass = "diamond"

[[shapes]]
type = "sphere"
center = [0.6, 0.0, 0.0]
radius = 0.5
material = "gem"
"#;
    let sphere = ("the white sphere", Vec3::new(-0.6, 0.1, 0.0));
    check_furnace(&format!("{white}{diamond}"), &[sphere], false, 4000);
    let gem = ("the diamond", Vec3::new(0.65, -0.1, 0.0));
    check_furnace(&format!("{white}{diamond}"), &[gem], true, 4000);
    // ... and a ball of fog that scatters without absorbing, its σs strongly coloured (0.5
    // to 8 per unit: a different free path at each wavelength, drawn with one wavelength's).
    // Beside the diamond, paths through the fog that meet it would leave their hero alone.
    let fog = r#"
[media.fog]
sigma_a = 0.0
sigma_s = [0.5, 2.0, 8.0]
g = 0.3

[[shapes]]
type = "sphere"
center = [0.6, 0.0, 0.0]
radius = 0.4
interior = "fog"
"#;
    let ball = ("the fog", Vec3::new(0.6, 0.05, 0.0));
    check_furnace(&format!("{white}{fog}"), &[ball], false, 64000);
}

/// CIE 1931 chromaticity (x, y) of the image's mean colour.
fn chromaticity(img: &Image) -> (f32, f32) {
    let rgb = img.pixels.iter().sum::<Rgb>() / img.pixels.len() as f32;
    let xyz = photon::spectrum::linear_srgb_to_xyz(rgb);
    let s = xyz.x + xyz.y + xyz.z;
    (xyz.x / s, xyz.y / s)
}

#[test]
fn a_blackbody_light_has_the_chromaticity_of_its_temperature() {
    // The Planckian locus, CIE 1931 2° observer (Wyszecki and Stiles 1982, table 1(3.11);
    // 2856 K is illuminant A).
    for (kelvin, x, y) in [
        (2000.0, 0.5267, 0.4133),
        (2856.0, 0.44757, 0.40745),
        (4000.0, 0.3805, 0.3768),
        (6500.0, 0.3135, 0.3237),
        (10000.0, 0.2807, 0.2884),
    ] {
        let toml = format!(
            r#"
[camera]
position = [0.0, 0.0, 2.0]
look_at = [0.0, 0.0, 0.0]
fov = 30

[render]
width = 8
height = 8

[materials.white]
type = "diffuse"
albedo = 1.0

[[shapes]]
type = "quad"
material = "white"
vertices = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]

[[lights]]
type = "point"
position = [0.3, 0.2, 1.5]
power = 40.0
temperature = {kelvin}
"#
        );
        for (spectral, tolerance) in [("false", 2e-4), ("true", 2.5e-3)] {
            let img = render(
                &toml,
                &[
                    ("integrator", "direct"),
                    ("spectral", spectral),
                    ("spp", "256"),
                ],
            );
            let (mx, my) = chromaticity(&img);
            assert!(
                (mx - x).abs() < tolerance && (my - y).abs() < tolerance,
                "{kelvin} K, spectral {spectral}: ({mx}, {my}), the locus has ({x}, {y})"
            );
        }
    }
}

#[test]
fn spectral_renders_are_the_same_bits_on_one_and_two_threads() {
    // The prism's dispersion, a rough dielectric, a blackbody light and a textured sky: what
    // spectral rendering adds, in every integrator.
    let toml = prism_scene(24, 8).replace(
        "[[lights]]",
        "[materials.frost]\ntype = \"glass\"\nabbe = 30\nalpha = 0.2\n\n[[shapes]]\ntype = \"sphere\"\ncenter = [0.6, 0.0, 1.0]\nradius = 0.2\nmaterial = \"frost\"\n\n[[lights]]\ntype = \"point\"\nposition = [0.0, 1.5, 0.5]\npower = 20.0\ntemperature = 3200\n\n[[lights]]",
    );
    for integrator in ["path", "direct", "photon", "sppm", "ppm"] {
        let samples = if integrator.ends_with("ppm") {
            "passes"
        } else {
            "spp"
        };
        let images = common::on_one_and_two_threads(|| {
            let mut options = vec![
                ("integrator", integrator),
                ("spectral", "true"),
                (samples, "2"),
            ];
            if integrator == "photon" {
                options.extend([("photons", "20000"), ("caustic_photons", "20000")]);
            }
            if integrator.ends_with("ppm") {
                options.push(("photons_per_pass", "5000"));
            }
            render(&toml, &options)
                .pixels
                .iter()
                .map(|p| p.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        });
        assert_eq!(images[0], images[1], "{integrator}");
        assert!(
            images[0].iter().flatten().any(|&b| f32::from_bits(b) > 0.0),
            "{integrator} renders something"
        );
    }
}
