//! `--env FILE|R,G,B`, `--env-rotate` and `--env-intensity` from the command line: they add or
//! replace a scene's sky, and bad values are located errors (exit code 2), never panics.

use crate::common;

use std::path::{Path, PathBuf};

fn repo(path: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(path)
        .to_string_lossy()
        .into_owned()
}

/// A white floor under the sky, seen from above at an angle (the sky is in view too).
const FLOOR: &str = r#"
[camera]
position = [0.0, 1.0, 3.0]
look_at = [0.0, 0.0, 0.0]
[materials.white]
type = "diffuse"
albedo = 0.8
[[shapes]]
type = "quad"
vertices = [[-2.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0], [-2.0, 0.0, -2.0]]
material = "white"
"#;

fn render(dir: &Path, extra: &[&str], out: &str) -> std::process::Output {
    let mut args = vec![
        "render",
        "floor.toml",
        "--integrator",
        "path",
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "16",
        "-q",
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    common::photon(&args, dir)
}

fn mean(dir: &Path, file: &str) -> f32 {
    photon::io::image::read_image(&dir.join(file))
        .expect("reads")
        .mean()
        .x
}

#[test]
fn env_lights_a_scene_that_has_no_light() {
    let dir = common::temp_dir("cli-env");
    std::fs::write(dir.join("floor.toml"), FLOOR).expect("write");
    // Without a light, photon mapping has nothing to trace: the message says what to add.
    let o = common::photon(
        &[
            "render",
            "floor.toml",
            "--width",
            "8",
            "--height",
            "8",
            "-q",
            "-o",
            "x.png",
        ],
        &dir,
    );
    common::assert_usage_error(&o, "--env");
    // A uniform sky of 1: the floor (albedo 0.8) and the sky around it.
    let o = render(&dir, &["--env", "1"], "one.exr");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = render(&dir, &["--env", "0.5,0.5,0.5"], "half.exr");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let ratio = mean(&dir, "half.exr") / mean(&dir, "one.exr");
    assert!(
        (ratio - 0.5).abs() < 0.01,
        "half the sky, half the light: {ratio}"
    );
    // An image sky, turned: the sun moves, and so does the light on the floor.
    let sky = repo("scenes/assets/sky.exr");
    let o = render(&dir, &["--env", &sky], "sky0.exr");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = render(&dir, &["--env", &sky, "--env-rotate", "120"], "sky120.exr");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = render(&dir, &["--env", &sky, "--env-intensity", "2"], "sky2.exr");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let (a, b, c) = (
        photon::io::image::read_image(&dir.join("sky0.exr")).expect("reads"),
        photon::io::image::read_image(&dir.join("sky120.exr")).expect("reads"),
        mean(&dir, "sky2.exr"),
    );
    assert_ne!(a.pixels, b.pixels, "rotating the sky changes the image");
    assert!((c / a.mean().x - 2.0).abs() < 0.02, "twice the intensity");
}

#[test]
fn bad_env_values_are_usage_errors() {
    let dir = common::temp_dir("cli-env-errors");
    std::fs::write(dir.join("floor.toml"), FLOOR).expect("write");
    for (args, needle) in [
        (vec!["--env", "1,2"], "R,G,B"),
        (vec!["--env", "-1"], "not negative"),
        (vec!["--env", "nan"], "finite"),
        (vec!["--env", "nowhere.exr"], "no such file"),
        (vec!["--env", "sky.png"], ".exr, .hdr or .pfm"),
        (vec!["--env-rotate", "30"], "has none"),
        (
            vec!["--env", "1", "--env-intensity", "-2"],
            "--env-intensity",
        ),
    ] {
        let o = render(&dir, &args, "x.exr");
        common::assert_usage_error(&o, needle);
    }
    // A sky in the scene file that is not an image it can read.
    std::fs::write(dir.join("bad.hdr"), b"not an image").expect("write");
    let text = format!("{FLOOR}\n[[lights]]\ntype = \"environment\"\nfile = \"bad.hdr\"\n");
    std::fs::write(dir.join("badsky.toml"), text).expect("write");
    let o = common::photon(&["render", "badsky.toml", "-q", "-o", "x.exr"], &dir);
    common::assert_usage_error(&o, "bad.hdr");
}
