//! Heterogeneous media on voxel grids against closed forms: Beer–Lambert through a grid of
//! known integral, a furnace filled with a lumpy cloud, determinism, and errors for bad grids.

use crate::common;

use common::media::{
    assert_every_integrator_renders_alike_on_one_and_two_threads, image_mean, render, scene_in,
};
use photon::math::Rgb;
use photon::medium::grid_file::write_vol;
use std::path::Path;

/// A grid of n³ voxels whose density rises along z from 0 to 2 (at voxel centres
/// 2 (k + ½)/n): its trilinear interpolation, held flat in the half voxels at the faces,
/// integrates to exactly 1 across the unit cube, the two flat halves' errors cancelling.
fn z_ramp(dir: &Path, n: usize) {
    let values: Vec<f32> = (0..n * n * n)
        .map(|i| 2.0 * ((i / (n * n)) as f32 + 0.5) / n as f32)
        .collect();
    std::fs::write(dir.join("ramp.vol"), write_vol([n, n, n], &values)).expect("writes");
}

/// A camera looking down −z through an invisible box holding an absorbing grid medium (the
/// ramp, placed as the box [−1, 1]² × [−0.5, 0.5]) at a two-sided emitter of radiance 1:
/// exp(−σa ∫ density) = exp(−σa) per channel. Ratio tracking estimates it, so it is noisy.
#[test]
fn light_through_an_absorbing_grid_is_beer_lambert_of_its_integrated_density() {
    let dir = common::temp_dir("grid-beer-lambert");
    z_ramp(&dir, 6);
    let s = scene_in(
        r#"
[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 1.0
resolution = [4, 4]

[media.ink]
sigma_a = [0.5, 1.0, 2.0]
grid = "ramp.vol"
transform = [{ scale = [2.0, 2.0, 1.0] }, { translate = [-1.0, -1.0, -0.5] }]

[[shapes]]
type = "box"
min = [-1.0, -1.0, -0.5]
max = [1.0, 1.0, 0.5]
interior = "ink"

[[shapes]]
type = "quad"
vertices = [[-2.0, -2.0, -2.0], [2.0, -2.0, -2.0], [2.0, 2.0, -2.0], [-2.0, 2.0, -2.0]]
emission = { radiance = 1.0, two_sided = true }
"#,
        &dir,
    );
    // Ratio tracking's estimates have a standard deviation below 0.3 per sample in every
    // channel here; the bound is four of the mean's.
    for (integrator, samples, size) in [
        ("path", 2048, 8),
        ("direct", 2048, 8),
        ("photon", 256, 8),
        ("sppm", 32, 24),
        ("ppm", 32, 24),
    ] {
        let image = render(&s, integrator, samples, Some((size, size)));
        let mean = image.pixels.iter().sum::<Rgb>() / image.pixels.len() as f32;
        let bound = 4.0 * 0.3 / f64::from(samples * size * size).sqrt() as f32;
        for (c, sigma) in [0.5f32, 1.0, 2.0].into_iter().enumerate() {
            let exact = (-sigma).exp();
            let got = mean.to_array()[c];
            eprintln!(
                "grid Beer–Lambert, {integrator}, channel {c}: {got:.5}, exact {exact:.5} (bound {bound:.4})"
            );
            assert!(
                (got - exact).abs() < bound,
                "{integrator}, channel {c}: {got} vs exp(−{sigma}) = {exact}"
            );
        }
    }
}

/// A lumpy cloud (density from 0.5 to 6.5 in blobs, coloured σs, no absorption) filling a
/// closed sphere whose wall has radiance 1 everywhere (the grid's cube holds the sphere; the
/// cloud is the scene's medium): the radiance is 1 everywhere, whatever the density does. A
/// wrong null-collision weight, a scattering point's σs taken at the wrong place or a
/// majorant below the density shows as a channel off 1. (Where the density is zero no
/// photon scatters, and where the medium ends none is found, so a photon estimate whose
/// sphere or ball reaches there reads too little: the density stays above zero and the
/// cloud reaches the wall.) The cloud is a few mean free paths thick at most, so that the
/// progressive methods' 16 bounces hold nearly all of its light.
fn lumpy_furnace(dir: &Path, camera_z: f32, resolution: u32) -> photon::scene::Scene {
    let n = 12;
    let values: Vec<f32> = (0..n * n * n)
        .map(|i| {
            let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
            let lump = ((x * 7 + y * 3 + z * 5) % 4) as f32;
            if (x + y + z) % 3 == 0 {
                0.5
            } else {
                0.5 + 2.0 * lump
            }
        })
        .collect();
    std::fs::write(dir.join("lumps.vol"), write_vol([n, n, n], &values)).expect("writes");
    scene_in(
        &format!(
            r#"
medium = "cloud"
[camera]
position = [0.0, 0.0, {camera_z}]
look_at = [0.0, 0.0, -1.0]
fov = 60.0
resolution = [{resolution}, {resolution}]

[media.cloud]
sigma_s = [0.2, 0.4, 0.8]
g = 0.4
grid = "lumps.vol"
transform = [{{ scale = 2.0 }}, {{ translate = [-1.0, -1.0, -1.0] }}]

[[lights]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
radiance = 1.0
two_sided = true
"#
        ),
        dir,
    )
}

#[test]
fn a_furnace_holding_a_lumpy_grid_cloud_reads_its_wall_radiance() {
    let dir = common::temp_dir("grid-furnace");
    let s = lumpy_furnace(&dir, 0.8, 4);
    for (integrator, samples) in [("path", 2048), ("photon", 8), ("sppm", 160), ("ppm", 160)] {
        let mean = image_mean(&s, integrator, samples);
        for c in 0..3 {
            let got = mean.to_array()[c];
            eprintln!("grid furnace, channel {c}: {integrator} {got:.4}, exact 1");
            let bound = if integrator == "path" { 0.02 } else { 0.05 };
            assert!(
                (got - 1.0).abs() < bound,
                "{integrator}, channel {c}: {got}, not 1"
            );
        }
    }
}

#[test]
fn grid_media_render_identically_on_one_and_two_threads() {
    let dir = common::temp_dir("grid-threads");
    let s = lumpy_furnace(&dir, 0.3, 6);
    assert_every_integrator_renders_alike_on_one_and_two_threads(&s, None);
}

/// Grids that cannot be read are errors naming the file and what was expected; mistakes in
/// the scene are errors at their line and column.
#[test]
fn bad_grids_are_clear_errors() {
    let dir = common::temp_dir("grid-errors");
    std::fs::write(
        dir.join("short.vol"),
        &write_vol([2, 2, 2], &[1.0; 8])[..40],
    )
    .expect("writes");
    std::fs::write(dir.join("smoke.vdb"), b"not a vdb").expect("writes");
    std::fs::write(dir.join("ok.vol"), write_vol([1, 1, 1], &[1.0])).expect("writes");
    let head = "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n[media.smoke]\nsigma_s = 1.0\n";
    let cases = [
        ("grid = \"missing.vol\"\n", "scene.toml:6:8", "not found"),
        (
            "grid_name = \"density\"\n",
            "scene.toml:6:13",
            "give 'grid' too",
        ),
        (
            "grid = \"short.vol\"\n",
            "short.vol",
            "not a Mitsuba volume",
        ),
        ("grid = \"smoke.vdb\"\n", "smoke.vdb", "byte"),
        (
            "grid = \"ok.vol\"\ntransform = { scale = [1.0, 0.0, 1.0] }\n",
            "smoke",
            "not invertible",
        ),
    ];
    for (tail, at, needle) in cases {
        let text = format!("{head}{tail}");
        let e = photon::description::toml_read::read_str(&text, &dir.join("scene.toml"), &dir)
            .and_then(|d| photon::description::build::build(&d).map(|_| ()))
            .expect_err(&text)
            .to_string();
        assert!(e.contains(at), "{e}\n--- for ---\n{text}");
        assert!(e.contains(needle), "{e}\n--- for ---\n{text}");
    }
}

/// A job folder carries the grid file its scene reads, and its tasks merge into the single
/// render bit for bit (ratio and delta tracking draw from each sample's own numbers).
#[test]
fn jobs_carry_the_grid_and_merge_bit_for_bit() {
    let dir = common::temp_dir("grid-job");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for f in ["smoke.toml", "smoke.vdb"] {
        std::fs::copy(scenes.join(f), dir.join(f)).expect("copy");
    }
    let render = [
        "smoke.toml",
        "--integrator",
        "ppm",
        "--passes",
        "4",
        "--photons-per-pass",
        "2000",
        "--width",
        "16",
        "--height",
        "16",
    ];
    let single = common::photon(
        &[&["render", "-q", "-o", "single.exr"][..], &render].concat(),
        &dir,
    );
    assert!(single.status.success(), "{}", common::stderr(&single));
    let create = common::photon(
        &[&["job", "create", "--tasks", "2", "-o", "job"][..], &render].concat(),
        &dir,
    );
    assert!(create.status.success(), "{}", common::stderr(&create));
    assert!(dir.join("job/scene/smoke.vdb").is_file());
    for task in ["1", "0"] {
        let o = common::photon(&["job", "run", "job", "--task", task], &dir);
        assert!(o.status.success(), "{}", common::stderr(&o));
    }
    let o = common::photon(&["job", "merge", "job", "-o", "merged.exr"], &dir);
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(
        std::fs::read(dir.join("merged.exr")).expect("merged")
            == std::fs::read(dir.join("single.exr")).expect("single"),
        "2 tasks merged differ from the single render"
    );
}
