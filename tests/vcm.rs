//! Vertex connection and merging and its modes (bidirectional path tracing, light tracing):
//! closed forms where every technique takes part, the validation suite's references,
//! determinism over threads, resume and merge, and the command line.

use crate::common;

use common::{assert_usage_error, photon, stderr};
use photon::description::{build::build, builtin, toml_read::read_str};
use photon::film::Image;
use photon::progressive::{Method, ProgressiveConfig, ProgressiveState};
use photon::scene::Scene;
use photon::validate::{self, Budget, find_cases, load_case};
use std::path::Path;

const FAMILY: [Method; 3] = [Method::Vcm, Method::Bdpt, Method::LightTrace];

fn config(method: Method, size: u32, radius: Option<f32>) -> ProgressiveConfig {
    ProgressiveConfig {
        method,
        width: size,
        height: size,
        seed: 5,
        alpha: 2.0 / 3.0,
        photons_per_pass: 1,
        initial_radius: radius,
        max_depth: 64,
        light_samples: 1,
        spectral: false,
    }
}

fn render(scene: &Scene, c: &ProgressiveConfig, passes: u64) -> Image {
    let mut state = ProgressiveState::new(scene, c.clone(), 0).expect("valid");
    for _ in 0..passes {
        state.run_pass(scene).expect("pass");
    }
    state.image()
}

fn bits(img: &Image) -> Vec<u32> {
    img.pixels
        .iter()
        .flat_map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// The image size of the closed forms: light tracing's light reaches the camera from a
/// quarter of its vertices, so it gets 512 k light paths over the 512 passes, which hold its
/// mean to about 0.3%.
fn size(method: Method) -> u32 {
    if method == Method::LightTrace { 32 } else { 16 }
}

/// Inside a closed sphere of albedo ½ lit by a point light at its centre, every wall point
/// sends radiance 1 (see `builtin::sphere`): light from the point light reaches the eye by
/// next-event estimation, connections, merges and light tracing, and their weights must sum
/// to one on every path.
#[test]
fn closed_sphere_around_a_point_light_reads_one() {
    let scene = builtin::load("closed-sphere").expect("builds");
    for method in FAMILY {
        let image = render(&scene, &config(method, size(method), Some(0.05)), 512);
        let mean = image.mean();
        eprintln!("{}: closed sphere mean {mean}", method.name());
        assert!((mean.x - 1.0).abs() < 0.01, "{}: {mean}", method.name());
    }
}

/// The same closed form with an emitting wall: a sphere of albedo ½ whose inside emits ½
/// reads ½ / (1 − ½) = 1 everywhere. Here emission is found by camera paths too, so their
/// weights against light sampling and light tracing are tested.
#[test]
fn glowing_closed_sphere_reads_one() {
    let text = r#"
name = "glowing-sphere"
[camera]
position = [0.0, 0.2, -0.4]
look_at = [0.0, 0.0, 1.0]
up = [0.0, 1.0, 0.0]
fov = 80.0
resolution = [8, 8]
[materials.wall]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[shapes]]
type = "sphere"
radius = 1.0
material = "wall"
emission = { radiance = 0.5, two_sided = true }
"#;
    let desc = read_str(text, Path::new("glowing.toml"), Path::new(".")).expect("reads");
    let scene = build(&desc).expect("builds");
    for method in FAMILY {
        let image = render(&scene, &config(method, size(method), Some(0.05)), 512);
        let mean = image.mean();
        eprintln!("{}: glowing sphere mean {mean}", method.name());
        assert!((mean.x - 1.0).abs() < 0.01, "{}: {mean}", method.name());
    }
}

/// A closed sphere whose wall emits radiance 1 and reflects nothing, filled with a mist that
/// scatters but does not absorb (coloured: σs 1, 2, 4 per unit), with a ball of another,
/// backward-scattering medium behind an invisible boundary (`common::media::furnace_toml`):
/// radiance 1 everywhere solves the transport equation, so every pixel reads 1 however light
/// scatters. Bidirectional path
/// tracing, and vcm with a radius large enough that merges in the volume carry much of the
/// light: a merge normalised by the wrong measure, counting σs twice, or weighed against the
/// other techniques with a surface's η shows in some channel. (Light tracing alone is left
/// out: with the camera in the mist, its connections from vertices next to the lens have
/// unbounded variance, 1/d² with no cosine to tame it; `fog-box` tests it in a medium.)
#[test]
fn a_closed_sphere_of_scattering_media_reads_one() {
    let scene = mist_furnace();
    for (method, radius) in [(Method::Vcm, Some(0.1)), (Method::Bdpt, None)] {
        let image = render(&scene, &config(method, 16, radius), 1024);
        let mean = image.mean();
        eprintln!("{}: mist furnace mean {mean}", method.name());
        for c in 0..3 {
            let got = mean.to_array()[c];
            assert!(
                (got - 1.0).abs() < 0.015,
                "{}, channel {c}: {got}",
                method.name()
            );
        }
    }
}

/// `flush-light`'s panel hangs 1 cm below the ceiling, and the camera sees its lower face.
/// The ceiling above the panel faces the same way and is lit hundreds of times more, by the
/// panel's top face: a merge at the lower face must not take the ceiling's light vertices,
/// which lie in its radius but off its plane. At a radius of 5 cm `vcm` reads the reference's
/// mean within 0.4% at this budget; taking the ceiling's vertices read 1.28×.
#[test]
fn merges_stay_on_their_own_surface() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("validation");
    let cases = find_cases(&dir, false).expect("reads validation/");
    let case = cases
        .iter()
        .find(|c| c.name == "flush-light")
        .expect("scene");
    let loaded = load_case(case, 32).expect("loads");
    let image = render(&loaded.scene, &config(Method::Vcm, 32, Some(0.05)), 256);
    let (got, want) = (image.mean(), loaded.reference.mean());
    for c in 0..3 {
        let ratio = got.to_array()[c] / want.to_array()[c];
        assert!(
            (ratio - 1.0).abs() < 0.02,
            "channel {c}: mean ratio {ratio}"
        );
    }
}

/// The furnace of [`a_closed_sphere_of_scattering_media_reads_one`], seen from its centre
/// with the cloud behind the camera.
fn mist_furnace() -> Scene {
    common::media::scene(&common::media::furnace_toml(0.0, 0.6, 16))
}

/// The image does not depend on the thread count; a render resumed from a checkpoint and
/// one merged from pass ranges in any order are bit-identical to one run.
#[test]
fn threads_resume_and_merge_give_the_same_bits() {
    let scene = builtin::load("cornell").expect("builds");
    let c = config(Method::Vcm, 16, None);
    let straight = render(&scene, &c, 5);
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool")
        .install(|| render(&scene, &c, 5));
    assert_eq!(bits(&one_thread), bits(&straight), "one thread");
    // In media too, where subpaths draw distances and connections estimate transmittance.
    let mist = mist_furnace();
    let c_mist = config(Method::Vcm, 8, Some(0.1));
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool")
        .install(|| render(&mist, &c_mist, 3));
    assert_eq!(
        bits(&one_thread),
        bits(&render(&mist, &c_mist, 3)),
        "one thread, in media"
    );

    let dir = common::temp_dir("vcm-resume");
    let mut first = ProgressiveState::new(&scene, c.clone(), 0).expect("valid");
    for _ in 0..2 {
        first.run_pass(&scene).expect("pass");
    }
    let path = dir.join("v.checkpoint");
    photon::io::checkpoint::save(&first, &path).expect("saves");
    let mut resumed = photon::io::checkpoint::load(&path).expect("loads");
    assert_eq!(resumed, first);
    for _ in 0..3 {
        resumed.run_pass(&scene).expect("pass");
    }
    assert_eq!(bits(&resumed.image()), bits(&straight), "resume");

    let mut parts = Vec::new();
    for (a, b) in [(3u64, 5u64), (0, 1), (1, 3)] {
        let mut p = ProgressiveState::new(&scene, c.clone(), a).expect("valid");
        for _ in a..b {
            p.run_pass(&scene).expect("pass");
        }
        parts.push(p);
    }
    let merged = ProgressiveState::merge(parts).expect("joins");
    assert_eq!(bits(&merged.image()), bits(&straight), "merge");
}

/// relMSE bounds of vcm at [`budget`] per validation scene (about twice what was measured).
const VCM_BOUNDS: &[(&str, f64)] = &[
    ("absorbing-glass", 0.004),
    ("absorbing-water", 0.002),
    ("alpha-fence", 0.002),
    ("coloured-fog", 0.008),
    ("curved-ceiling", 0.001),
    ("directional", 0.0008),
    ("door-ajar", 0.0025),
    ("env-spheres", 0.004),
    ("flush-light", 0.003),
    ("fog-box", 0.0015),
    ("fog-spot", 0.005),
    ("glass-caustics", 0.012),
    ("glossy-cornell", 0.002),
    ("glossy-floor-spot", 0.0015),
    ("grazing-area", 0.0012),
    ("indirect-only", 0.0015),
    ("lamp-shade", 0.002),
    ("light-strip", 0.002),
    ("millimetres", 0.0015),
    ("mirror-caustic", 0.006),
    ("normal-mapped", 0.003),
    ("point-light", 0.0015),
    ("rough-glass", 0.002),
    ("smoke-grid", 0.0008),
    ("smooth-box", 0.003),
    ("spot-light", 0.001),
    ("textured-mesh", 0.0012),
    ("thick-medium", 0.0012),
];

/// Scenes whose whole-image mean is noisier at [`budget`] than the 1% the test allows, and
/// the tolerance taken there. `coloured-fog`: blue's mean from `bdpt` at 32² and 1024 passes
/// reads 0.9907, 1.0005 and 0.9952 over seeds 0, 1 and 2, and 0.9982 at 4096 passes (a
/// pass draws every pixel's distances for one channel, so pixels are not independent).
const NOISY_MEANS: &[(&str, f64)] = &[("coloured-fog", 0.02)];

/// The suite's budget for the vcm family: 32², 512 passes.
fn budget() -> Budget {
    Budget {
        vcm_passes: 512,
        ..Budget::QUICK
    }
}

/// Every validation scene, with vcm, against its Mitsuba reference: means within 1% and
/// relMSE within its bound.
#[test]
fn vcm_matches_every_reference() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("validation");
    let budget = budget();
    let mut failures = Vec::new();
    let mut rendered = Vec::new();
    for case in find_cases(&dir, false).expect("reads validation/") {
        let loaded = load_case(&case, budget.size).expect("loads");
        let bound = VCM_BOUNDS
            .iter()
            .find(|b| b.0 == case.name)
            .unwrap_or_else(|| panic!("no vcm bound for {}", case.name))
            .1;
        failures.extend(check(&case, &loaded, validate::Method::Vcm, bound, &budget));
        rendered.push(case.name.clone());
    }
    assert_eq!(
        rendered.len(),
        VCM_BOUNDS.len(),
        "a bound for each scene rendered"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Bidirectional path tracing alone, and light tracing alone where the camera sees no delta
/// surface (light tracing cannot find a path whose first vertex from the camera is a mirror
/// or smooth glass), on scenes of each kind of light.
#[test]
fn bdpt_and_light_tracing_alone_match_their_references() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("validation");
    let budget = budget();
    let cases = find_cases(&dir, false).expect("reads validation/");
    let mut failures = Vec::new();
    for (name, method, bound) in [
        ("glossy-cornell", validate::Method::Bdpt, 0.002),
        ("glass-caustics", validate::Method::Bdpt, 0.012),
        ("env-spheres", validate::Method::Bdpt, 0.004),
        ("point-light", validate::Method::LightTrace, 0.006),
        ("directional", validate::Method::LightTrace, 0.005),
        ("indirect-only", validate::Method::LightTrace, 0.004),
        ("textured-mesh", validate::Method::LightTrace, 0.006),
        ("lamp-shade", validate::Method::LightTrace, 0.0045),
        ("fog-box", validate::Method::LightTrace, 0.006),
        ("fog-spot", validate::Method::Bdpt, 0.005),
    ] {
        let case = cases.iter().find(|c| c.name == name).expect("scene");
        let loaded = load_case(case, budget.size).expect("loads");
        failures.extend(check(case, &loaded, method, bound, &budget));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn check(
    case: &validate::Case,
    loaded: &validate::Loaded,
    method: validate::Method,
    bound: f64,
    budget: &Budget,
) -> Option<String> {
    let o = validate::run(case, loaded, method, budget).expect("renders");
    let c = &o.comparison;
    let ratios = [c.red.mean_ratio, c.green.mean_ratio, c.blue.mean_ratio];
    eprintln!(
        "{:<18} {:<10} relMSE {:.5} (bound {bound}) mean ratios {:.4} {:.4} {:.4}",
        case.name,
        method.name(),
        c.overall.rel_mse,
        ratios[0],
        ratios[1],
        ratios[2]
    );
    let tolerance = NOISY_MEANS
        .iter()
        .find(|n| n.0 == case.name)
        .map_or(0.01, |n| n.1);
    let means_ok = ratios.iter().all(|r| (r - 1.0).abs() <= tolerance);
    let error_ok = c.overall.rel_mse.is_finite() && c.overall.rel_mse <= bound;
    (!means_ok || !error_ok).then(|| {
        format!(
            "{} {}: mean ratios {ratios:?} (±{tolerance}), relMSE {} (bound {bound})",
            case.name,
            method.name(),
            c.overall.rel_mse
        )
    })
}

#[test]
fn the_command_line_renders_vcm_and_refuses_what_is_not_its_setting() {
    let dir = common::temp_dir("vcm-cli");
    let small = ["--width", "12", "--height", "12", "-q"];
    for method in ["vcm", "bdpt", "lighttrace"] {
        let out = format!("{method}.pfm");
        let mut args = vec!["render", "cornell", "--integrator", method, "--passes", "2"];
        args.extend(small);
        args.extend(["-o", out.as_str()]);
        let o = photon(&args, &dir);
        assert!(o.status.success(), "{method}: {}", stderr(&o));
        assert!(dir.join(&out).exists(), "{method} wrote its image");
    }
    // vcm sets its own light paths per pass: photons per pass is not its setting.
    let o = photon(
        &[
            "render",
            "cornell",
            "--integrator",
            "vcm",
            "--passes",
            "2",
            "--photons-per-pass",
            "1000",
            "-o",
            "x.pfm",
        ],
        &dir,
    );
    assert_usage_error(&o, "photons-per-pass");
    // A scene with media renders too.
    let fog = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/fog.toml");
    let o = photon(
        &[
            "render",
            fog.to_str().expect("utf-8 path"),
            "--integrator",
            "vcm",
            "--passes",
            "1",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "fog.pfm",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("fog.pfm").exists(), "vcm wrote the fog's image");
}
