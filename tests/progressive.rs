//! Progressive photon mapping: convergence on analytic and reference scenes, resume and merge.

use crate::common;

use photon::compare::{CORNELL_CAUSTIC_CROP, compare};
use photon::description::builtin;
use photon::io::image::read_image;
use photon::progressive::{Method, ProgressiveConfig, ProgressiveState};

fn config(method: Method, w: u32, h: u32, photons: u64) -> ProgressiveConfig {
    ProgressiveConfig {
        method,
        width: w,
        height: h,
        seed: 3,
        alpha: 2.0 / 3.0,
        photons_per_pass: photons,
        initial_radius: None,
        max_depth: 16,
        light_samples: 1,
        spectral: false,
    }
}

#[test]
fn closed_sphere_converges_to_one_within_one_percent() {
    let scene = builtin::load("closed-sphere").expect("builds");
    for method in [Method::Sppm, Method::Ppm] {
        let mut c = config(method, 8, 8, 20_000);
        c.initial_radius = Some(0.1);
        let mut state = ProgressiveState::new(&scene, c, 0).expect("valid");
        for _ in 0..128 {
            state.run_pass(&scene).expect("pass");
        }
        let mean = state.image().mean();
        eprintln!(
            "{}: closed sphere mean {mean} after 128 passes",
            method.name()
        );
        assert!((mean.x - 1.0).abs() < 0.01, "{}: {mean}", method.name());
    }
}

#[test]
fn resumed_and_merged_renders_equal_one_run() {
    let scene = builtin::load("cornell").expect("builds");
    for method in [Method::Sppm, Method::Ppm] {
        let c = config(method, 16, 16, 5_000);
        let mut straight = ProgressiveState::new(&scene, c.clone(), 0).expect("valid");
        for _ in 0..6 {
            straight.run_pass(&scene).expect("pass");
        }
        // Interrupted after 2 passes, saved, loaded, continued.
        let dir = common::temp_dir(&format!("resume-{}", method.name()));
        let mut first = ProgressiveState::new(&scene, c.clone(), 0).expect("valid");
        for _ in 0..2 {
            first.run_pass(&scene).expect("pass");
        }
        let path = dir.join("c.checkpoint");
        photon::io::checkpoint::save(&first, &path).expect("saves");
        let mut resumed = photon::io::checkpoint::load(&path).expect("loads");
        assert_eq!(resumed, first);
        for _ in 0..4 {
            resumed.run_pass(&scene).expect("pass");
        }
        assert_eq!(
            resumed.image(),
            straight.image(),
            "{}: resume",
            method.name()
        );
        if method == Method::Ppm {
            let mut parts = Vec::new();
            for (a, b) in [(4u64, 6u64), (0, 1), (1, 4)] {
                let mut p = ProgressiveState::new(&scene, c.clone(), a).expect("valid");
                for _ in a..b {
                    p.run_pass(&scene).expect("pass");
                }
                parts.push(p);
            }
            let merged = ProgressiveState::merge(parts).expect("joins");
            let bits = |img: &photon::film::Image| {
                img.pixels
                    .iter()
                    .flat_map(|p| p.to_array().map(f32::to_bits))
                    .collect::<Vec<_>>()
            };
            assert_eq!(
                bits(&merged.image()),
                bits(&straight.image()),
                "merge is bit-identical"
            );
        }
    }
}

#[test]
fn cornell_error_falls_with_passes() {
    let scene = builtin::load("cornell").expect("builds");
    let reference = read_image(&common::shared_dir().join("scenes/cornell-box/reference.exr"))
        .expect("reference")
        .downsample(4)
        .expect("divides");
    for method in [Method::Sppm, Method::Ppm] {
        let mut state =
            ProgressiveState::new(&scene, config(method, 128, 128, 20_000), 0).expect("valid");
        let mut errors = Vec::new();
        let mut caustic = Vec::new();
        let crop = photon::compare::Crop {
            x0: CORNELL_CAUSTIC_CROP.x0 / 4,
            x1: CORNELL_CAUSTIC_CROP.x1 / 4,
            y0: CORNELL_CAUSTIC_CROP.y0 / 4,
            y1: CORNELL_CAUSTIC_CROP.y1.div_ceil(4),
        };
        for target in [2u64, 8, 32] {
            while state.passes < target {
                state.run_pass(&scene).expect("pass");
            }
            let img = state.image();
            errors.push(
                compare(&img, &reference, None)
                    .expect("size")
                    .overall
                    .rel_mse,
            );
            caustic.push(
                compare(&img, &reference, Some(crop))
                    .expect("size")
                    .overall
                    .rmse,
            );
        }
        eprintln!(
            "{}: relMSE at 2/8/32 passes {errors:?}, caustic RMSE {caustic:?}",
            method.name()
        );
        assert!(
            errors[0] > errors[1] && errors[1] > errors[2],
            "{}: {errors:?}",
            method.name()
        );
        assert!(caustic[0] > caustic[2], "{}: {caustic:?}", method.name());
    }
}

/// PPM sums its passes in fixed point: 64 bits wrapped for a light of radiance 3·10¹¹ at two
/// passes (pixels down to −2.5·10¹¹). Now the light reads as itself and nothing is negative.
#[test]
fn ppm_sums_do_not_wrap_for_bright_lights() {
    let text = r#"
[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
[materials.white]
type = "diffuse"
[[shapes]]
type = "quad"
vertices = [[-2.0, -2.0, -1.0], [2.0, -2.0, -1.0], [2.0, 2.0, -1.0], [-2.0, 2.0, -1.0]]
material = "white"
[[lights]]
type = "quad"
vertices = [[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]]
radiance = 3e11
"#;
    let desc = photon::description::toml_read::read_str(
        text,
        std::path::Path::new("bright.toml"),
        std::path::Path::new("."),
    )
    .expect("reads");
    let scene = photon::description::build::build(&desc).expect("builds");
    let mut state =
        ProgressiveState::new(&scene, config(Method::Ppm, 8, 8, 2000), 0).expect("state");
    for _ in 0..3 {
        state.run_pass(&scene).expect("pass");
    }
    let img = state.image();
    let min = img
        .pixels
        .iter()
        .map(|p| p.min_element())
        .fold(f32::MAX, f32::min);
    let centre = img.get(4, 4).x;
    assert!(min >= 0.0, "a negative pixel: {min}");
    assert!(
        (centre / 3e11 - 1.0).abs() < 1e-3,
        "the light reads {centre}"
    );
}
