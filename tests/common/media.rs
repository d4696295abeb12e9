//! Scenes with media built from TOML text and rendered by each integrator, for the media
//! tests.

use photon::math::Rgb;
use photon::settings::IntegratorKind;
use std::path::Path;

/// The scene `toml` describes, reading the files it names from `base_dir`.
pub fn scene_in(toml: &str, base_dir: &Path) -> photon::scene::Scene {
    let desc =
        photon::description::toml_read::read_str(toml, &base_dir.join("scene.toml"), base_dir)
            .unwrap_or_else(|e| panic!("{e}"));
    photon::description::build::build(&desc).unwrap_or_else(|e| panic!("{e}"))
}

pub fn scene(toml: &str) -> photon::scene::Scene {
    scene_in(toml, Path::new("."))
}

/// The image's mean, rendered by `integrator` with `samples` samples per pixel or passes.
pub fn image_mean(scene: &photon::scene::Scene, integrator: &str, samples: u32) -> Rgb {
    let image = render(scene, integrator, samples, None);
    image.pixels.iter().sum::<Rgb>() / image.pixels.len() as f32
}

/// The scene rendered by `integrator` with `samples` samples per pixel or passes, at `size`
/// (default: the scene's).
pub fn render(
    scene: &photon::scene::Scene,
    integrator: &str,
    samples: u32,
    size: Option<(u32, u32)>,
) -> photon::film::Image {
    let kind = match integrator {
        "path" => IntegratorKind::Path,
        "direct" => IntegratorKind::Direct,
        "sppm" => IntegratorKind::Sppm,
        "ppm" => IntegratorKind::Ppm,
        "photon" => IntegratorKind::Photon,
        _ => unreachable!("no integrator {integrator}"),
    };
    let options = if kind.is_progressive() {
        photon::settings::RenderOptions {
            integrator: Some(kind),
            passes: Some(u64::from(samples)),
            photons_per_pass: Some(20_000),
            // Balls of radius 0.1 (four times this), well inside the sphere: near the wall a
            // ball reaches past it and finds fewer photons, the boundary bias every density
            // estimate has.
            radius: Some(0.025),
            ..Default::default()
        }
    } else {
        photon::settings::RenderOptions {
            integrator: Some(kind),
            spp: Some(samples),
            // Volume photons in spheres of a fixed radius: the media tests' furnaces have the
            // same light everywhere, where large spheres average noise away without bias.
            photons: (kind == IntegratorKind::Photon).then_some(400_000),
            caustic_photons: (kind == IntegratorKind::Photon).then_some(400_000),
            k: (kind == IntegratorKind::Photon).then_some(0),
            radius: (kind == IntegratorKind::Photon).then_some(0.3),
            ..Default::default()
        }
    };
    let options = photon::settings::RenderOptions {
        width: size.map(|s| s.0),
        height: size.map(|s| s.1),
        ..options
    };
    let job = photon::render_job::RenderJob::new(scene, &Default::default(), options)
        .unwrap_or_else(|e| panic!("{e}"));
    job.render(&|_| {}, &std::sync::atomic::AtomicBool::new(false))
        .expect("renders")
        .image
}

/// Every integrator renders `scene` (at `size`, or its own) to the same bits on one thread
/// and on two.
pub fn assert_every_integrator_renders_alike_on_one_and_two_threads(
    scene: &photon::scene::Scene,
    size: Option<(u32, u32)>,
) {
    for integrator in ["path", "direct", "photon", "sppm", "ppm"] {
        let images = super::on_one_and_two_threads(|| {
            let image = render(scene, integrator, 2, size);
            image
                .pixels
                .iter()
                .map(|p| p.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        });
        assert_eq!(images[0], images[1], "{integrator}");
    }
}

/// The text of a furnace: a closed sphere whose wall emits radiance 1 and reflects nothing,
/// filled with media that scatter but do not absorb (a coloured mist, and a ball of a
/// backward-scattering cloud behind an invisible boundary), with the camera at z =
/// `camera_z` and the cloud's centre at z = `cloud_z`. Radiance 1 everywhere solves the
/// transport equation there, so every pixel of every integrator reads 1.
pub fn furnace_toml(camera_z: f32, cloud_z: f32, resolution: u32) -> String {
    format!(
        r#"
medium = "mist"
[camera]
position = [0.0, 0.0, {camera_z}]
look_at = [0.0, 0.0, -1.0]
fov = 60.0
resolution = [{resolution}, {resolution}]

[media.mist]
sigma_s = [1.0, 2.0, 4.0]
g = 0.5

[media.cloud]
sigma_s = 5.0
g = -0.3

[[shapes]]
type = "sphere"
center = [0.0, 0.0, {cloud_z}]
radius = 0.3
interior = "cloud"

[[lights]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
radiance = 1.0
two_sided = true
"#
    )
}
