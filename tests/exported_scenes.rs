//! What exporters really write, rendered by every integrator against the path tracer: meshes
//! shaded smooth (corner-averaged vertex normals, as Blender writes a box shaded smooth) and a
//! two-sided emitter with a material mounted 1 cm below a ceiling. The path tracer is checked
//! against Mitsuba 3 on such scenes by the validation suite; here the photon-mapping
//! integrators must agree with it.

use photon::description::{build::build, toml_read::read_str};
use photon::render_job::RenderJob;
use photon::scene::Scene;
use photon::settings::{IntegratorKind, RenderOptions};
use std::path::Path;
use std::sync::atomic::AtomicBool;

const MATERIALS: &str = r#"
[camera]
position = [0.5, 0.5, -0.9]
look_at = [0.5, 0.55, 0.5]
up = [0.0, 1.0, 0.0]
fov = 50.0
resolution = [32, 32]
[render]
filter = "box"
[materials.white]
type = "diffuse"
albedo = [0.75, 0.75, 0.75]
[materials.red]
type = "diffuse"
albedo = [0.7, 0.1, 0.1]
[materials.green]
type = "diffuse"
albedo = [0.1, 0.7, 0.1]
"#;

/// A closed box [0, 1] × [0, 1] × [−1, 1], each wall two triangles. `smooth`: every vertex
/// normal points from its corner to the box's centre, as a box shaded smooth gets them (a
/// ceiling corner's normal is tilted 35° to 55° from the wall's).
fn box_walls(smooth: bool) -> String {
    let walls: [([[f32; 3]; 4], &str); 6] = [
        (
            [[0., 0., -1.], [1., 0., -1.], [1., 0., 1.], [0., 0., 1.]],
            "white",
        ),
        (
            [[0., 1., -1.], [0., 1., 1.], [1., 1., 1.], [1., 1., -1.]],
            "white",
        ),
        (
            [[0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]],
            "white",
        ),
        (
            [[0., 0., -1.], [0., 0., 1.], [0., 1., 1.], [0., 1., -1.]],
            "red",
        ),
        (
            [[1., 0., -1.], [1., 1., -1.], [1., 1., 1.], [1., 0., 1.]],
            "green",
        ),
        (
            [[0., 0., -1.], [0., 1., -1.], [1., 1., -1.], [1., 0., -1.]],
            "white",
        ),
    ];
    let mut text = String::new();
    for (corners, material) in walls {
        let normals: Vec<String> = corners
            .iter()
            .map(|c| {
                let v = [0.5 - c[0], 0.5 - c[1], -c[2]];
                let l = v.iter().map(|x| x * x).sum::<f32>().sqrt();
                format!("[{}, {}, {}]", v[0] / l, v[1] / l, v[2] / l)
            })
            .collect();
        let positions: Vec<String> = corners.iter().map(|c| format!("{c:?}")).collect();
        text += &format!(
            "[[shapes]]\ntype = \"triangles\"\npositions = [{}]\nindices = [[0, 1, 2], [0, 2, 3]]\nmaterial = \"{material}\"\n",
            positions.join(", ")
        );
        if smooth {
            text += &format!("normals = [{}]\n", normals.join(", "));
        }
    }
    text
}

fn scene(text: &str) -> Scene {
    let desc = read_str(text, Path::new("box.toml"), Path::new(".")).expect("reads");
    build(&desc).expect("builds")
}

/// The image's mean per channel with `integrator`.
fn mean(scene: &Scene, integrator: IntegratorKind, options: RenderOptions) -> [f64; 3] {
    let options = RenderOptions {
        integrator: Some(integrator),
        seed: Some(5),
        ..options
    };
    let job = RenderJob::new(scene, &Default::default(), options).expect("job");
    let image = job
        .render(&|_| {}, &AtomicBool::new(false))
        .expect("renders")
        .image;
    let m = image.mean();
    [f64::from(m.x), f64::from(m.y), f64::from(m.z)]
}

/// Every photon-mapping integrator's mean against the path tracer's, per channel.
fn ratios_to_path(scene: &Scene) -> Vec<(&'static str, [f64; 3])> {
    let reference = mean(
        scene,
        IntegratorKind::Path,
        RenderOptions {
            spp: Some(1024),
            ..Default::default()
        },
    );
    let progressive = RenderOptions {
        passes: Some(48),
        photons_per_pass: Some(40_000),
        ..Default::default()
    };
    let runs = [
        (
            "photon",
            IntegratorKind::Photon,
            RenderOptions {
                spp: Some(16),
                ..Default::default()
            },
        ),
        ("sppm", IntegratorKind::Sppm, progressive.clone()),
        ("ppm", IntegratorKind::Ppm, progressive),
    ];
    runs.into_iter()
        .map(|(name, kind, options)| {
            let m = mean(scene, kind, options);
            let r = [0, 1, 2].map(|c| m[c] / reference[c]);
            eprintln!("{name}: mean / path = {r:.4?}");
            (name, r)
        })
        .collect()
}

fn assert_within(ratios: &[(&str, [f64; 3])], tolerance: f64) {
    for (name, r) in ratios {
        // Written so that a NaN fails too.
        assert!(
            r.iter().all(|x| (x - 1.0).abs() <= tolerance),
            "{name}: mean / path = {r:?}, outside ±{tolerance}"
        );
    }
}

/// Photons are transported with the adjoint BSDF under shading normals (Veach 1997, §5.3),
/// estimates compare geometric normals, and the final gather's irradiance reflects only
/// toward directions above the shading plane. Without these, the photon methods read this box
/// 5–7% dark (10–16% in a Blender-exported Cornell box) and the final gather 3% bright.
#[test]
fn a_box_shaded_smooth_renders_as_the_path_tracer_sees_it() {
    let light = r#"
[[shapes]]
type = "quad"
vertices = [[0.4, 0.95, 0.1], [0.6, 0.95, 0.1], [0.6, 0.95, 0.3], [0.4, 0.95, 0.3]]
material = "white"
emission = { radiance = 20.0 }
"#;
    let smooth = scene(&format!("{MATERIALS}{}{light}", box_walls(true)));
    assert_within(&ratios_to_path(&smooth), 0.025);
}

/// A two-sided emitter with a material 1 cm below a white ceiling, seen by the camera, as
/// Blender exports a light panel. The ceiling's photons lie on a parallel plane within the
/// gather disc of the light's own surface; counting them read the light's pixels twice as
/// bright and the image 25–30% bright in `sppm` and `ppm`. What remains at this small budget
/// is the blur of the ceiling's bright patch above the panel onto the ceiling beside it, which
/// shrinks with the radius (+0.7% at 256 passes of a 64² image), plus the noise of the slit
/// that camera paths find rarely: `sppm` read +4.5% to +8.6% in blue (which white surfaces
/// dominate) between changes of its random streams, hence ±10%, far from the bug's +25%.
#[test]
fn a_light_flush_with_a_ceiling_gathers_only_its_own_photons() {
    let light = r#"
[[shapes]]
type = "quad"
vertices = [[0.3, 0.99, 0.3], [0.7, 0.99, 0.3], [0.7, 0.99, 0.7], [0.3, 0.99, 0.7]]
material = "white"
emission = { radiance = 5.0, two_sided = true }
"#;
    let text = format!("{MATERIALS}{}{light}", box_walls(false))
        .replace("look_at = [0.5, 0.55, 0.5]", "look_at = [0.5, 0.7, 0.5]");
    assert_within(&ratios_to_path(&scene(&text)), 0.10);
}
