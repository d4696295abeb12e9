//! Hardening, round two (issue #25): nothing lost on resume or interrupt, no input replaced by
//! an output, no render of zero passes.

use crate::common;

use common::{assert_usage_error, photon, stderr, temp_dir};
use photon::render_job::RenderJob;
use photon::settings::{IntegratorKind, RenderOptions};
use std::path::Path;
use std::sync::atomic::AtomicBool;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// A textured sphere under a point light.
const SCENE: &str = r#"
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
[materials.tiles]
type = "diffuse"
albedo = { texture = "tiles.png" }
[[shapes]]
type = "sphere"
radius = 1.0
material = "tiles"
[[lights]]
type = "point"
position = [0.0, 2.0, 2.0]
power = 50.0
"#;

/// A folder with `s.toml` (SCENE), its texture `tiles.png` and a sky `sky.exr`.
fn scene_dir(name: &str) -> std::path::PathBuf {
    let dir = temp_dir(name);
    std::fs::write(dir.join("s.toml"), SCENE).expect("write");
    for f in ["tiles.png", "sky.exr"] {
        std::fs::copy(Path::new(ROOT).join("scenes/assets").join(f), dir.join(f)).expect("copy");
    }
    dir
}

/// `photon render s.toml` in `dir`, small, with `extra` flags (progressive ones give
/// `--photons-per-pass 2000`).
fn render(dir: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["render", "s.toml", "--width", "12", "--height", "10", "-q"];
    args.extend_from_slice(extra);
    photon(&args, dir)
}

#[test]
fn renders_with_environment_flags_resume_bit_for_bit() {
    let dir = scene_dir("run-env-resume");
    let env = [
        "--integrator",
        "sppm",
        "--photons-per-pass",
        "2000",
        "--env",
        "sky.exr",
        "--env-rotate",
        "30",
        "--env-intensity",
        "2",
    ];
    let o = render(
        &dir,
        &[&env[..], &["--passes", "3", "-o", "whole.exr"]].concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = render(
        &dir,
        &[
            &env[..],
            &["--passes", "1", "-o", "r.exr", "--keep-checkpoint"],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // From another folder, without the flags: the checkpoint keeps them (the sky's path
    // absolute).
    let elsewhere = temp_dir("run-env-resume-elsewhere");
    let ck = dir.join("r.checkpoint");
    let ck = ck.to_str().expect("utf-8");
    let o = photon(
        &["render", "--resume", ck, "--passes", "2", "-q"],
        &elsewhere,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // Then with the same flags again.
    let o = photon(
        &[
            &["render", "--resume", "r.checkpoint", "--passes", "3", "-q"],
            &env[4..],
        ]
        .concat(),
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        std::fs::read(dir.join("r.exr")).expect("r")
            == std::fs::read(dir.join("whole.exr")).expect("w"),
        "a resumed render with --env differs from an uninterrupted one"
    );
    // Other environment flags are not the render's.
    let o = photon(
        &[
            "render",
            "--resume",
            "r.checkpoint",
            "--passes",
            "4",
            "--env-intensity",
            "3",
        ],
        &dir,
    );
    assert_usage_error(&o, "sky.exr --env-rotate 30 --env-intensity 2;");
}

#[test]
fn outputs_never_replace_the_scenes_inputs() {
    let dir = scene_dir("run-inputs");
    std::os::unix::fs::symlink("sky.exr", dir.join("link.exr")).expect("symlink");
    std::fs::create_dir(dir.join("sub")).expect("mkdir");
    let before = |f: &str| std::fs::read(dir.join(f)).expect("read");
    let (tiles, sky) = (before("tiles.png"), before("sky.exr"));
    let absolute = dir.join("tiles.png").to_string_lossy().into_owned();
    let path = ["--integrator", "path", "--spp", "1"];
    let sppm = [
        "--integrator",
        "sppm",
        "--passes",
        "1",
        "--photons-per-pass",
        "2000",
    ];
    let cases: Vec<Vec<&str>> = vec![
        [&path[..], &["-o", "tiles.png"]].concat(),
        [&path[..], &["-o", "sub/../tiles.png"]].concat(),
        [&path[..], &["--env", "sky.exr", "-o", "sky.exr"]].concat(),
        [&path[..], &["--env", "link.exr", "-o", "sky.exr"]].concat(),
        [&path[..], &["-o", &absolute]].concat(),
        [&path[..], &["--aov", "albedo", "-o", "t.png"]].concat(),
        [&sppm[..], &["--env", "sky.exr", "-o", "sky.exr"]].concat(),
        [
            &sppm[..],
            &["--env", "sky.exr", "-o", "x.png", "--checkpoint", "sky.exr"],
        ]
        .concat(),
        [&sppm[..], &["-o", "t.png", "--snapshots"]].concat(),
    ];
    // Siblings of the output `t`: an AOV, a snapshot.
    for sibling in ["t.albedo.png", "t.pass00001.png"] {
        std::fs::copy(dir.join("tiles.png"), dir.join(sibling)).expect("copy");
    }
    let scene_with = |name: &str| {
        let text = SCENE.replace("tiles.png", name);
        std::fs::write(dir.join("s.toml"), text).expect("write");
    };
    for (i, args) in cases.iter().enumerate() {
        scene_with(match i {
            5 => "t.albedo.png",
            8 => "t.pass00001.png",
            _ => "tiles.png",
        });
        let o = render(&dir, args);
        assert_usage_error(&o, "is a file the scene reads");
        assert_eq!(before("tiles.png"), tiles, "{args:?}");
        assert_eq!(before("sky.exr"), sky, "{args:?}");
    }
    // A resume whose output is one of the scene's files.
    scene_with("tiles.png");
    let o = render(
        &dir,
        &[&sppm[..], &["-o", "ok.exr", "--keep-checkpoint"]].concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = photon(
        &[
            "render",
            "--resume",
            "ok.checkpoint",
            "--passes",
            "2",
            "-o",
            "tiles.png",
        ],
        &dir,
    );
    assert_usage_error(&o, "is a file the scene reads");
    assert_eq!(before("tiles.png"), tiles);
}

#[test]
fn zero_passes_are_refused_and_a_short_time_runs_one_pass() {
    let dir = scene_dir("run-zero");
    let sppm = ["--integrator", "sppm", "--photons-per-pass", "2000"];
    let o = render(
        &dir,
        &[&sppm[..], &["--passes", "0", "-o", "z.exr"]].concat(),
    );
    assert_usage_error(&o, "--passes 0");
    assert!(!dir.join("z.exr").exists());
    let o = render(
        &dir,
        &[
            "--integrator",
            "ppm",
            "--passes",
            "9",
            "--pass-range",
            "5..5",
            "-o",
            "z.part",
        ],
    );
    assert_usage_error(&o, "--pass-range 5..5: the range is empty");
    let o = render(
        &dir,
        &[
            &sppm[..],
            &["--time", "1e-9", "-o", "t.exr", "--keep-checkpoint"],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let state = photon::io::checkpoint::load(&dir.join("t.checkpoint")).expect("checkpoint");
    assert_eq!(
        state.passes, 1,
        "a time budget shorter than a pass runs one"
    );
    let o = photon(
        &["render", "--resume", "t.checkpoint", "--passes", "0"],
        &dir,
    );
    assert_usage_error(&o, "--passes 0");
    // The resume path bounds passes as every other front end does.
    let o = photon(
        &[
            "render",
            "--resume",
            "t.checkpoint",
            "--passes",
            "1099511627777",
        ],
        &dir,
    );
    assert_usage_error(&o, "--passes 1099511627777: must be at most 1099511627776");
    // A scene given beside --resume would be ignored: it is refused.
    let o = photon(&["render", "s.toml", "--resume", "t.checkpoint"], &dir);
    assert_usage_error(&o, "not a scene (the checkpoint names its own)");
}

/// The library refuses what the command line refuses (the Python module renders through it).
#[test]
fn the_library_refuses_zero_passes_and_empty_ranges() {
    let scene = photon::description::load_scene("cornell")
        .expect("cornell")
        .0;
    let spec = Default::default();
    let job = |o: RenderOptions| {
        RenderJob::new(&scene, &spec, o)
            .err()
            .map(|e| e.to_string())
    };
    let ppm = |passes, pass_range| RenderOptions {
        integrator: Some(IntegratorKind::Ppm),
        passes,
        pass_range,
        ..RenderOptions::default()
    };
    let zero = job(ppm(Some(0), None)).expect("passes 0 is refused");
    assert!(zero.contains("passes = 0"), "{zero}");
    let range = job(ppm(None, Some((10, 5).into()))).expect("10..5 is refused");
    assert!(range.contains("10..5"), "{range}");
    assert!(
        job(ppm(None, Some((5, 5).into()))).is_some(),
        "5..5 is refused"
    );
    // A time shorter than any pass still renders one.
    let options = RenderOptions {
        integrator: Some(IntegratorKind::Sppm),
        time: Some(1e-9),
        width: Some(8),
        height: Some(8),
        photons_per_pass: Some(1000),
        ..RenderOptions::default()
    };
    let result = RenderJob::new(&scene, &spec, options)
        .expect("job")
        .render(&|_| {}, &AtomicBool::new(false))
        .expect("render");
    assert_eq!(result.state.expect("state").passes, 1);
}

/// A pass abandoned by its cancel flag leaves the state of the passes completed before, and
/// the next pass gives what it would have.
#[test]
fn an_abandoned_pass_leaves_the_completed_ones() {
    let scene = photon::description::load_scene("cornell")
        .expect("cornell")
        .0;
    for method in [IntegratorKind::Sppm, IntegratorKind::Ppm] {
        let options = RenderOptions {
            integrator: Some(method),
            passes: Some(2),
            width: Some(12),
            height: Some(10),
            photons_per_pass: Some(2000),
            ..RenderOptions::default()
        };
        let job = RenderJob::new(&scene, &Default::default(), options).expect("job");
        let mut straight = job.progressive_state().expect("state");
        straight.run_pass(&scene).expect("pass");
        straight.run_pass(&scene).expect("pass");
        let mut state = job.progressive_state().expect("state");
        state.run_pass(&scene).expect("pass");
        let after_one = state.clone();
        let cancelled = state.run_pass_cancellable(&scene, &AtomicBool::new(true));
        assert!(matches!(cancelled, Err(photon::Error::Cancelled)));
        assert_eq!(state, after_one, "an abandoned pass changed the state");
        state.run_pass(&scene).expect("pass");
        assert_eq!(state, straight);
    }
}
