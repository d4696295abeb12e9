//! Large but valid numbers: an emitter as big as the coordinate limit allows has its area, and
//! a light whose power overflows single precision is refused by name, the same way for every
//! integrator (not "the scene emits no light" for the photon methods and a silent render for
//! the others).

use crate::common;

use std::path::Path;

/// A triangle emitter of edge `size` seen from far enough away, and a white sphere.
fn emitter_scene(dir: &Path, size: f32) {
    let far = size * 3.0;
    let toml = format!(
        "[camera]\nposition = [0, 0, {far:e}]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\
         [materials.white]\ntype = \"diffuse\"\nalbedo = 0.8\n\
         [[shapes]]\ntype = \"triangles\"\n\
         positions = [[0, 0, 0], [{size:e}, 0, 0], [0, {size:e}, 0]]\nindices = [[0, 1, 2]]\n\
         material = \"white\"\nemission = {{ radiance = 1.0 }}\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, {:e}]\nradius = {:e}\nmaterial = \"white\"\n",
        size * 0.5,
        size * 0.1,
    );
    std::fs::write(dir.join("scene.toml"), toml).expect("write scene");
}

fn render(dir: &Path, integrator: &str, extra: &[&str]) -> std::process::Output {
    let out = format!("{integrator}{}.pfm", extra.join(""));
    let mut args = vec![
        "render",
        "scene.toml",
        "--integrator",
        integrator,
        "-o",
        &out,
    ];
    match integrator {
        "sppm" | "ppm" => args.extend(["--passes", "1", "--photons-per-pass", "1000"]),
        "photon" => args.extend([
            "--spp",
            "1",
            "--photons",
            "1000",
            "--caustic-photons",
            "1000",
        ]),
        _ => args.extend(["--spp", "1"]),
    }
    args.extend(extra);
    common::photon(&args, dir)
}

#[test]
fn an_emitter_of_edge_1e10_has_an_area() {
    // Its edges' cross product has components of 1e20, whose squares overflow f32.
    let dir = common::temp_dir("big-emitter");
    emitter_scene(&dir, 1e10);
    let o = render(&dir, "direct", &[]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let area = photon::geometry::Triangle::new(
        photon::math::Vec3::ZERO,
        photon::math::Vec3::new(1e10, 0.0, 0.0),
        photon::math::Vec3::new(0.0, 1e10, 0.0),
    )
    .area();
    assert_eq!(area, 5e19);
}

#[test]
fn a_light_whose_power_overflows_is_refused_by_every_integrator() {
    let dir = common::temp_dir("huge-sky");
    emitter_scene(&dir, 1.0);
    for integrator in ["direct", "path", "photon", "sppm", "ppm"] {
        let o = render(&dir, integrator, &["--env", "1e38"]);
        common::assert_usage_error(&o, "(the environment light) has a power of");
        assert!(
            !common::stderr(&o).contains("emits no light"),
            "{integrator}"
        );
        // Large but finite powers still render.
        let o = render(&dir, integrator, &["--env", "1e30"]);
        assert!(o.status.success(), "{integrator}: {}", common::stderr(&o));
    }
}
