//! `max_radiance`: each camera sample is scaled down so that no channel exceeds the limit,
//! keeping its colour, for the integrators that render samples per pixel; the others refuse
//! it. The same from the command line, a scene's `[render]` table and the library.

use crate::common;

use common::{assert_usage_error, photon, stderr, temp_dir};
use photon::description::load_scene;
use photon::math::Rgb;
use photon::render_job::RenderJob;
use photon::settings::{IntegratorKind, RenderOptions};
use std::sync::atomic::AtomicBool;

/// A bright orange emitter (black, so it reflects nothing) filling the middle of the view,
/// over a white floor it lights.
const SCENE: &str = r#"
[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 40
resolution = [16, 16]
[materials.white]
type = "diffuse"
[materials.black]
type = "diffuse"
albedo = [0.0, 0.0, 0.0]
[[shapes]]
type = "quad"
vertices = [[-3, -1, -3], [3, -1, -3], [3, -1, 3], [-3, -1, 3]]
material = "white"
[[shapes]]
type = "quad"
vertices = [[-0.6, -0.6, 0], [0.6, -0.6, 0], [0.6, 0.6, 0], [-0.6, 0.6, 0]]
material = "black"
emission = { radiance = [20.0, 10.0, 5.0], two_sided = true }
"#;

const LIMIT: f32 = 2.0;
const SPP: u32 = 4;

fn render(dir: &std::path::Path, options: RenderOptions) -> photon::film::Image {
    let path = dir.join("s.toml");
    std::fs::write(&path, SCENE).expect("write");
    let (scene, loaded) = load_scene(&path.to_string_lossy()).expect("scene");
    RenderJob::new(&scene, &loaded.desc.render, options)
        .expect("job")
        .render(&|_| {}, &AtomicBool::new(false))
        .expect("renders")
        .image
}

fn path_options(max_radiance: Option<f32>) -> RenderOptions {
    RenderOptions {
        integrator: Some(IntegratorKind::Path),
        spp: Some(SPP),
        max_radiance,
        ..RenderOptions::default()
    }
}

#[test]
fn samples_are_scaled_to_the_limit_keeping_their_colour() {
    let dir = temp_dir("max-radiance");
    let free = render(&dir, path_options(None));
    let clamped = render(&dir, path_options(Some(LIMIT)));
    let centre = |image: &photon::film::Image| image.pixels[8 * 16 + 8];
    // Seen directly, the emitter is its own radiance, and clamped, that scaled to the limit.
    assert!(
        (centre(&free) - Rgb::new(20.0, 10.0, 5.0))
            .abs()
            .max_element()
            < 1e-3,
        "{:?}",
        centre(&free)
    );
    assert!(
        (centre(&clamped) - Rgb::new(2.0, 1.0, 0.5))
            .abs()
            .max_element()
            < 1e-4,
        "{:?}",
        centre(&clamped)
    );
    // A pixel whose mean is below limit / spp had no sample at the limit (samples are never
    // negative), so clamping must leave it exactly as it was.
    let below = |f: &Rgb| f.max_element() < LIMIT / SPP as f32;
    let mut untouched = 0;
    for (c, f) in clamped.pixels.iter().zip(&free.pixels) {
        assert!(
            c.max_element() <= LIMIT * (1.0 + 1e-5),
            "{c:?} above the limit"
        );
        assert!(c.max_element() <= f.max_element() * (1.0 + 1e-5));
        if below(f) {
            assert_eq!(c, f);
            // Lit floor, not the black background that no scaling changes.
            if f.max_element() > 0.0 {
                untouched += 1;
            }
        }
    }
    assert!(untouched > 16, "{untouched} lit pixels dim enough to check");
}

#[test]
fn the_command_line_and_a_scene_file_give_the_librarys_image() {
    let dir = temp_dir("max-radiance-cli");
    let library = render(&dir, path_options(Some(LIMIT)));
    let o = photon(
        &[
            "render",
            "s.toml",
            "--integrator",
            "path",
            "--spp",
            "4",
            "--max-radiance",
            "2",
            "-q",
            "-o",
            "cli.pfm",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let cli = photon::io::image::read_image(&dir.join("cli.pfm")).expect("reads");
    assert_eq!(cli.pixels, library.pixels);
    // The same from the scene's [render] table.
    let in_scene = format!("{SCENE}[render]\nmax_radiance = 2.0\n");
    std::fs::write(dir.join("r.toml"), in_scene).expect("write");
    let o = photon(
        &[
            "render",
            "r.toml",
            "--integrator",
            "path",
            "--spp",
            "4",
            "-q",
            "-o",
            "scene.pfm",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let from_scene = photon::io::image::read_image(&dir.join("scene.pfm")).expect("reads");
    assert_eq!(from_scene.pixels, library.pixels);
}

#[test]
fn integrators_without_samples_refuse_it_and_bad_limits_are_refused() {
    let dir = temp_dir("max-radiance-refused");
    std::fs::write(dir.join("s.toml"), SCENE).expect("write");
    let run = |extra: &[&str]| {
        let mut args = vec!["render", "s.toml", "-q", "-o", "x.pfm"];
        args.extend_from_slice(extra);
        photon(&args, &dir)
    };
    assert_usage_error(
        &run(&[
            "--integrator",
            "sppm",
            "--passes",
            "1",
            "--max-radiance",
            "2",
        ]),
        "--max-radiance 2: the sppm integrator does not take it (it is for photon, direct and path)",
    );
    for bad in ["0", "-1", "inf", "nan"] {
        assert_usage_error(
            &run(&["--integrator", "path", &format!("--max-radiance={bad}")]),
            "must be a positive number",
        );
    }
}
