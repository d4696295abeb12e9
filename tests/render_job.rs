//! `RenderJob` is the library call behind `photon render`: for one TOML scene with a
//! `[render]` table, the image it returns is the CLI's, byte for byte, for every kind of
//! integrator, and its settings take the flag > scene > default precedence.

use crate::common;

use common::{photon, stderr, temp_dir};
use photon::description::load_scene;
use photon::render_job::RenderJob;
use photon::settings::{IntegratorKind, RenderOptions};
use std::sync::atomic::AtomicBool;

const SCENE: &str = r#"
[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
resolution = [24, 16]
[render]
integrator = "path"
spp = 6
seed = 3
[materials.white]
type = "diffuse"
[materials.glass]
type = "glass"
[[shapes]]
type = "quad"
vertices = [[-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2]]
material = "white"
[[shapes]]
type = "sphere"
center = [0.0, 0.6, 0.0]
radius = 0.5
material = "glass"
[[lights]]
type = "point"
position = [0.5, 2.5, 1.0]
power = 100.0
"#;

#[test]
fn render_job_gives_the_command_lines_image_byte_for_byte() {
    let dir = temp_dir("render-job");
    let path = dir.join("s.toml");
    std::fs::write(&path, SCENE).expect("write");
    let (scene, loaded) = load_scene(&path.to_string_lossy()).expect("scene");
    let never = AtomicBool::new(false);
    for (options, flags) in [
        // The scene's own settings: path, 6 spp, seed 3.
        (RenderOptions::default(), vec![]),
        (
            RenderOptions {
                integrator: Some(IntegratorKind::Photon),
                spp: Some(2),
                photons: Some(10_000),
                ..RenderOptions::default()
            },
            vec!["--integrator", "photon", "--spp", "2", "--photons", "10000"],
        ),
        (
            RenderOptions {
                integrator: Some(IntegratorKind::Ppm),
                passes: Some(3),
                photons_per_pass: Some(4000),
                ..RenderOptions::default()
            },
            vec![
                "--integrator",
                "ppm",
                "--passes",
                "3",
                "--photons-per-pass",
                "4000",
            ],
        ),
    ] {
        let job = RenderJob::new(&scene, &loaded.desc.render, options).expect("job");
        let result = job.render(&|_| {}, &never).expect("renders");
        photon::io::image::write_image(&result.image, &dir.join("job.pfm"), Default::default())
            .expect("write");
        let mut args = vec!["render", "s.toml", "-q", "-o", "cli.pfm"];
        args.extend(&flags);
        let o = photon(&args, &dir);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            std::fs::read(dir.join("job.pfm")).expect("job")
                == std::fs::read(dir.join("cli.pfm")).expect("cli"),
            "RenderJob and the CLI differ for {flags:?}"
        );
    }
}

#[test]
fn options_take_precedence_over_the_scene_and_the_scene_over_defaults() {
    let dir = temp_dir("render-job-precedence");
    let path = dir.join("s.toml");
    std::fs::write(&path, SCENE).expect("write");
    let (scene, loaded) = load_scene(&path.to_string_lossy()).expect("scene");
    let spec = &loaded.desc.render;
    let job = RenderJob::new(&scene, spec, RenderOptions::default()).expect("job");
    assert_eq!(job.integrator(), IntegratorKind::Path);
    let s = job.settings();
    assert_eq!((s.spp, s.seed, s.width, s.height), (6, 3, 24, 16));
    let given = RenderOptions {
        spp: Some(9),
        width: Some(8),
        ..RenderOptions::default()
    };
    let s = RenderJob::new(&scene, spec, given).expect("job").settings();
    assert_eq!((s.spp, s.seed, s.width, s.height), (9, 3, 8, 16));
    // A photon-integrator setting from options is refused for path; progressive renders need
    // a budget.
    let bad = RenderOptions {
        gather_rays: Some(4),
        ..RenderOptions::default()
    };
    assert!(RenderJob::new(&scene, spec, bad).is_err());
    let no_budget = RenderOptions {
        integrator: Some(IntegratorKind::Sppm),
        ..RenderOptions::default()
    };
    assert!(RenderJob::new(&scene, spec, no_budget).is_err());
}

#[test]
fn a_cancelled_render_stops_with_an_error_and_progressive_keeps_its_passes() {
    let (scene, loaded) = load_scene("cornell").expect("scene");
    let cancelled = AtomicBool::new(true);
    let job = RenderJob::new(
        &scene,
        &loaded.desc.render,
        RenderOptions {
            integrator: Some(IntegratorKind::Path),
            ..RenderOptions::default()
        },
    )
    .expect("job");
    assert!(matches!(
        job.render(&|_| {}, &cancelled),
        Err(photon::Error::Cancelled)
    ));
    let progressive = RenderJob::new(
        &scene,
        &loaded.desc.render,
        RenderOptions {
            integrator: Some(IntegratorKind::Sppm),
            passes: Some(100),
            width: Some(8),
            height: Some(8),
            ..RenderOptions::default()
        },
    )
    .expect("job");
    let r = progressive.render(&|_| {}, &cancelled).expect("returns");
    assert!(r.cancelled);
    assert_eq!(r.state.expect("state").passes, 0);
}
