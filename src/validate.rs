//! The validation suite: small scenes with converged references made by another renderer
//! (Mitsuba 3, `validation/make_references.py`), rendered by every integrator and compared.
//!
//! A case is a folder `NAME/` holding `NAME.toml` (the scene) and `reference.exr`. Each
//! integrator renders the scene at a square size that divides the reference's, and the
//! reference is averaged down to it (exact for box-filtered pixels). The figures are per-channel
//! mean ratios, relMSE, and the worst of a 4×4 grid of regions (largest error of its mean), so
//! that a bias confined to one corner of a scene is not averaged away.

use crate::compare::{Comparison, compare};
use crate::description::load_scene;
use crate::error::{Error, Result};
use crate::film::{Image, PixelFilter};
use crate::integrator::{Integrator, PathConfig, PhotonIntegrator, PhotonSettings};
use crate::io::image::read_image;
use crate::math::luminance;
use crate::photon::{PhotonConfig, trace_photons};
use crate::progressive::{Method as ProgressiveMethod, ProgressiveConfig, ProgressiveState};
use crate::render::{RenderSettings, render};
use crate::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// The integrators the suite runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Path,
    Photon,
    Sppm,
    Ppm,
    Vcm,
    Bdpt,
    LightTrace,
}

impl Method {
    /// The path tracer and the photon-mapping integrators.
    pub const ALL: [Method; 4] = [Method::Path, Method::Photon, Method::Sppm, Method::Ppm];
    /// Vertex connection and merging and its modes.
    pub const VCM_FAMILY: [Method; 3] = [Method::Vcm, Method::Bdpt, Method::LightTrace];

    pub fn name(self) -> &'static str {
        match self {
            Method::Path => "path",
            Method::Photon => "photon",
            Method::Sppm => "sppm",
            Method::Ppm => "ppm",
            Method::Vcm => "vcm",
            Method::Bdpt => "bdpt",
            Method::LightTrace => "lighttrace",
        }
    }

    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL
            .into_iter()
            .chain(Method::VCM_FAMILY)
            .find(|m| m.name() == name)
    }
}

/// How much work each integrator gets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// Rendered image size (square); must divide the reference's size.
    pub size: u32,
    pub path_spp: u32,
    /// `path`'s samples in scenes with media: light sampled from points in a medium near a
    /// point or spot light varies as 1/r² (equiangular sampling, which would bound it, is not
    /// implemented), and at `path_spp` the rare bright samples left `fog-spot` 1.2% dark
    /// (0.2% at 16384).
    pub media_path_spp: u32,
    pub photon_spp: u32,
    pub global_photons: u64,
    pub caustic_photons: u64,
    pub passes: u32,
    pub photons_per_pass: u64,
    /// Passes of the vcm family (a camera path per pixel each, and a light path per four pixels,
    /// or per pixel for `lighttrace`).
    pub vcm_passes: u32,
    /// Initial radius of `sppm` and `ppm` as a fraction of the scene's diagonal (the vcm family
    /// merges within its own default for the scene file's resolution). The
    /// command line's default (4 or 6 pixel footprints) is made for full-size images: at 32² it is
    /// a fifth of a room, and its bias takes thousands of passes to fade.
    pub radius_fraction: f32,
    /// Render with spectral transport (against `reference-spectral.exr`).
    pub spectral: bool,
}

impl Budget {
    /// The budget for spectral rendering: the progressive methods' passes share their
    /// wavelengths, three per pass, so the colour of an image of few passes is a coarse
    /// sample of the spectrum; the same photons in four times the passes (a quarter each)
    /// sample it four times as finely. (At `QUICK`'s 64 passes the blue of `spot-light` read
    /// 2.4% low, at 256 passes 0.1%.)
    pub fn spectral(self) -> Budget {
        Budget {
            spectral: true,
            passes: self.passes * 4,
            photons_per_pass: self.photons_per_pass / 4,
            ..self
        }
    }

    /// What the test suite runs: every scene and integrator in well under a minute in all.
    pub const QUICK: Budget = Budget {
        size: 32,
        path_spp: 1024,
        media_path_spp: 4096,
        // At 16 the mean of the beam-lit `door-ajar` moved by 2% when rounding changed which
        // paths the same seed drew (1.012 to 1.0205): as wide as the suite's bound.
        photon_spp: 32,
        global_photons: 250_000,
        caustic_photons: 500_000,
        passes: 64,
        photons_per_pass: 20_000,
        vcm_passes: 1024,
        radius_fraction: 0.005,
        spectral: false,
    };

    /// What `photon validate` runs by default and `validation/REPORT.md` records.
    pub const FULL: Budget = Budget {
        size: 64,
        path_spp: 1024,
        media_path_spp: 4096,
        photon_spp: 16,
        global_photons: 250_000,
        caustic_photons: 1_000_000,
        passes: 256,
        photons_per_pass: 50_000,
        vcm_passes: 1024,
        radius_fraction: 0.005,
        spectral: false,
    };
}

/// One validation scene.
#[derive(Clone, Debug)]
pub struct Case {
    pub name: String,
    pub scene_file: PathBuf,
    pub reference_file: PathBuf,
}

/// The reference file of a case: Mitsuba's RGB render, or its spectral one.
pub fn reference_file_name(spectral: bool) -> &'static str {
    if spectral {
        "reference-spectral.exr"
    } else {
        "reference.exr"
    }
}

/// Every case in `dir`: sub-folders `NAME/` with `NAME.toml` and the reference
/// ([`reference_file_name`]), by name.
pub fn find_cases(dir: &Path, spectral: bool) -> Result<Vec<Case>> {
    let entries = std::fs::read_dir(dir).map_err(|source| Error::Read {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut cases = Vec::new();
    for entry in entries.flatten() {
        let folder = entry.path();
        let Some(name) = folder.file_name().and_then(|n| n.to_str()) else {
            continue;
        };
        let scene_file = folder.join(format!("{name}.toml"));
        let reference_file = folder.join(reference_file_name(spectral));
        if scene_file.is_file() && reference_file.is_file() {
            cases.push(Case {
                name: name.to_string(),
                scene_file,
                reference_file,
            });
        }
    }
    cases.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(cases)
}

/// The region of a 4×4 grid whose mean luminance is furthest from the reference's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub row: u32,
    pub column: u32,
    /// Mean luminance over the reference's, in that region.
    pub ratio: f64,
    /// |difference of the means| / the whole reference's mean luminance.
    pub share: f64,
}

/// One scene rendered by one integrator, against its reference.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub case: String,
    pub method: Method,
    pub seconds: f64,
    pub comparison: Comparison,
    pub worst: Region,
}

/// A loaded case: the scene and its reference at `size`.
pub struct Loaded {
    pub scene: Scene,
    pub reference: Image,
}

/// Load a case's scene and its reference averaged down to `size`².
pub fn load_case(case: &Case, size: u32) -> Result<Loaded> {
    let (scene, _) = load_scene(&case.scene_file.to_string_lossy())?;
    let full = read_image(&case.reference_file)?;
    let bad = |m: String| Error::InvalidSetting(format!("{}: {m}", case.name));
    if full.width != full.height || size == 0 || full.width % size != 0 {
        return Err(bad(format!(
            "the reference is {}×{}; the size {size} must divide it and it must be square",
            full.width, full.height
        )));
    }
    let reference = full
        .downsample(full.width / size)
        .ok_or_else(|| bad("cannot average the reference down".into()))?;
    Ok(Loaded { scene, reference })
}

/// Render a loaded case with `method` and compare it with the reference.
pub fn run(case: &Case, loaded: &Loaded, method: Method, budget: &Budget) -> Result<Outcome> {
    let start = Instant::now();
    let image = render_with(&loaded.scene, method, budget)?;
    let seconds = start.elapsed().as_secs_f64();
    let comparison = compare(&image, &loaded.reference, None).ok_or_else(|| {
        Error::InvalidSetting(format!("{}: image and reference differ in size", case.name))
    })?;
    Ok(Outcome {
        case: case.name.clone(),
        method,
        seconds,
        comparison,
        worst: worst_region(&image, &loaded.reference),
    })
}

/// The image `method` makes of `scene` with `budget` (seed 0, box filter).
pub fn render_with(scene: &Scene, method: Method, budget: &Budget) -> Result<Image> {
    let settings = |spp| RenderSettings {
        seed: 0,
        filter: PixelFilter::Box,
        spectral: budget.spectral,
        ..RenderSettings::new(budget.size, budget.size, spp)
    };
    let none = |_, _| {};
    match method {
        Method::Path => {
            let integrator = Integrator::Path(PathConfig::default());
            let spp = if scene.has_media() {
                budget.media_path_spp
            } else {
                budget.path_spp
            };
            Ok(render(scene, &integrator, &settings(spp), &none)?.image)
        }
        Method::Photon => {
            let config = PhotonConfig {
                photons: budget.caustic_photons.max(budget.global_photons),
                global_photons: Some(budget.global_photons),
                spectral: budget.spectral,
                ..PhotonConfig::default()
            };
            let maps = trace_photons(scene, &config, &none)?;
            let s = PhotonSettings::for_scene(scene);
            let integrator = Integrator::Photon(Box::new(PhotonIntegrator::new(s, Arc::new(maps))));
            Ok(render(scene, &integrator, &settings(budget.photon_spp), &none)?.image)
        }
        Method::Sppm | Method::Ppm | Method::Vcm | Method::Bdpt | Method::LightTrace => {
            let progressive = ProgressiveMethod::from_name(method.name()).expect("a method");
            // The vcm family merges within the radius `photon render` gives it for the scene
            // file's own resolution (the same in the scene at any budget's size); the suite's
            // radius fraction is for the photon-mapping methods' gathers.
            let (passes, max_depth, initial_radius) = match progressive.vcm_mode() {
                Some(_) => {
                    let (width, height) = scene.default_resolution;
                    let radius = crate::progressive::default_vcm_radius(scene, width, height)
                        .ok_or_else(|| Error::InvalidScene("degenerate camera".into()))?;
                    (budget.vcm_passes, 64, Some(radius))
                }
                None => (
                    budget.passes,
                    16,
                    Some(budget.radius_fraction * scene.view_diagonal()),
                ),
            };
            let config = ProgressiveConfig {
                method: progressive,
                width: budget.size,
                height: budget.size,
                seed: 0,
                alpha: 2.0 / 3.0,
                photons_per_pass: budget.photons_per_pass,
                initial_radius,
                max_depth,
                light_samples: 1,
                spectral: budget.spectral,
            };
            let mut state = ProgressiveState::new(scene, config, 0)?;
            for _ in 0..passes {
                state.run_pass(scene)?;
            }
            Ok(state.image())
        }
    }
}

/// The 4×4-grid region with the largest error of its mean luminance.
pub fn worst_region(image: &Image, reference: &Image) -> Region {
    const GRID: u32 = 4;
    let lum = |img: &Image, x0: u32, x1: u32, y0: u32, y1: u32| {
        let mut sum = 0.0f64;
        for y in y0..y1 {
            for x in x0..x1 {
                sum += f64::from(luminance(img.get(x, y)));
            }
        }
        sum / f64::from((x1 - x0) * (y1 - y0)).max(1.0)
    };
    let (w, h) = (reference.width, reference.height);
    let whole = lum(reference, 0, w, 0, h).max(1e-12);
    let mut worst = Region {
        row: 0,
        column: 0,
        ratio: 1.0,
        share: -1.0,
    };
    for row in 0..GRID {
        for column in 0..GRID {
            let (x0, x1) = (column * w / GRID, (column + 1) * w / GRID);
            let (y0, y1) = (row * h / GRID, (row + 1) * h / GRID);
            let (a, b) = (lum(image, x0, x1, y0, y1), lum(reference, x0, x1, y0, y1));
            let share = (a - b).abs() / whole;
            if share > worst.share {
                worst = Region {
                    row,
                    column,
                    ratio: if b > 0.0 { a / b } else { f64::INFINITY },
                    share,
                };
            }
        }
    }
    worst
}

/// The outcomes as a Markdown table.
pub fn table(outcomes: &[Outcome]) -> String {
    let mut s = String::from(
        "| scene | integrator | time (s) | relMSE | mean ratio R | G | B | worst region (row, col): ratio, share of mean |\n\
         |---|---|---:|---:|---:|---:|---:|---|\n",
    );
    for o in outcomes {
        let c = &o.comparison;
        s += &format!(
            "| {} | {} | {:.2} | {:.5} | {:.4} | {:.4} | {:.4} | ({}, {}): {:.3}, {:.1}% |\n",
            o.case,
            o.method.name(),
            o.seconds,
            c.overall.rel_mse,
            c.red.mean_ratio,
            c.green.mean_ratio,
            c.blue.mean_ratio,
            o.worst.row,
            o.worst.column,
            o.worst.ratio,
            100.0 * o.worst.share,
        );
    }
    s
}
