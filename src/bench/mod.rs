//! `photon bench`: error against time for each integrator on the standard scenes, and the
//! ray, photon and query micro-benchmarks, as one JSON record and an SVG plot.
//!
//! Each run gets a wall-clock budget. The progressive integrators take it as their time limit;
//! `photon` and `path` meet it by calibration: a 1-sample and a 4-sample render measure the
//! fixed cost (the photon trace) and the cost per sample, and the real run asks for the samples
//! that fill the budget. Every run reports the time it really took.

pub mod micro;
pub mod plot;

use crate::compare::{Crop, compare};
use crate::description::{self, SceneDesc};
use crate::error::{Error, Result};
use crate::film::Image;
use crate::render_job::RenderJob;
use crate::scene::Scene;
use crate::settings::{IntegratorKind, RenderOptions};
use serde::{Deserialize, Serialize};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The error thresholds whose crossing times the record reports.
pub const THRESHOLDS: [f64; 3] = [0.01, 0.003, 0.001];

/// A scene of the standard set, with where its error is measured.
#[derive(Clone, Debug, Serialize)]
pub struct BenchScene {
    pub name: String,
    /// A region reported on its own (the Cornell box's caustic), `[x0, y0, x1, y1)`.
    pub crop: Option<[u32; 4]>,
}

impl BenchScene {
    /// The standard set: the Cornell box (crop: the glass sphere's caustic on the short block)
    /// and the original project's scene.
    pub fn standard() -> Vec<BenchScene> {
        vec![
            BenchScene {
                name: "cornell".into(),
                crop: Some([290, 326, 390, 344]),
            },
            BenchScene {
                name: "seed".into(),
                crop: None,
            },
        ]
    }
}

/// One render of the set.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Run {
    pub scene: String,
    pub integrator: String,
    /// The budget asked for and the seconds the render took (wall clock, scene loaded).
    pub budget: f64,
    pub seconds: f64,
    /// `--spp N` or the passes done.
    pub samples: String,
    pub rel_mse: Option<f64>,
    pub rmse: Option<f64>,
    pub crop_rmse: Option<f64>,
}

/// When an integrator's relMSE first fell to a threshold (interpolated in log–log between runs).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Crossing {
    pub scene: String,
    pub integrator: String,
    pub rel_mse: f64,
    /// `None`: not reached within the largest budget.
    pub seconds: Option<f64>,
}

/// Render `scene` with `integrator` in about `budget` seconds (spectrally if `spectral`).
pub fn run_at_budget(
    scene: &Scene,
    desc: &SceneDesc,
    integrator: IntegratorKind,
    budget: f64,
    spectral: bool,
    threads: &rayon::ThreadPool,
) -> Result<(Image, f64, String)> {
    let render = |options: RenderOptions| -> Result<(Image, f64, u64)> {
        let start = Instant::now();
        let job = RenderJob::new(scene, &desc.render, options)?;
        let cancel = AtomicBool::new(false);
        let result = threads.install(|| job.render(&|_| {}, &cancel))?;
        let passes = result.state.as_ref().map_or(0, |s| s.passes);
        Ok((result.image, start.elapsed().as_secs_f64(), passes))
    };
    let options = |spp: Option<u32>, time: Option<f64>| RenderOptions {
        integrator: Some(integrator),
        spp,
        time,
        spectral: spectral.then_some(true),
        ..RenderOptions::default()
    };
    if integrator.is_progressive() {
        let (image, secs, passes) = render(options(None, Some(budget)))?;
        return Ok((image, secs, format!("{passes} passes")));
    }
    let (_, t1, _) = render(options(Some(1), None))?;
    let (_, t4, _) = render(options(Some(4), None))?;
    let per_spp = ((t4 - t1) / 3.0).max(1e-4);
    let fixed = (t1 - per_spp).max(0.0);
    let spp = ((budget - fixed) / per_spp).clamp(1.0, 1e6) as u32;
    let (image, secs, _) = render(options(Some(spp), None))?;
    Ok((image, secs, format!("{spp} spp")))
}

/// Compare a run's image with the reference, if there is one of its size.
pub fn measure(
    image: &Image,
    reference: Option<&Image>,
    crop: Option<[u32; 4]>,
) -> [Option<f64>; 3] {
    let Some(reference) = reference else {
        return [None; 3];
    };
    let whole = compare(image, reference, None);
    let crop =
        crop.and_then(|[x0, y0, x1, y1]| compare(image, reference, Some(Crop { x0, y0, x1, y1 })));
    [
        whole.as_ref().map(|c| c.overall.rel_mse),
        whole.as_ref().map(|c| c.overall.rmse),
        crop.map(|c| c.overall.rmse),
    ]
}

/// Load a standard scene for the bench.
pub fn load(name: &str) -> Result<(Scene, SceneDesc)> {
    let (scene, loaded) = description::load_scene(name)?;
    Ok((scene, loaded.desc))
}

/// The times at which each (scene, integrator)'s relMSE crossed each threshold: the first
/// budget at or below it, interpolated in log–log from the budget before.
pub fn crossings(runs: &[Run]) -> Vec<Crossing> {
    let mut out = Vec::new();
    let mut keys: Vec<(String, String)> = Vec::new();
    for r in runs {
        let k = (r.scene.clone(), r.integrator.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    for (scene, integrator) in keys {
        let mut points: Vec<(f64, f64)> = runs
            .iter()
            .filter(|r| r.scene == scene && r.integrator == integrator)
            .filter_map(|r| Some((r.seconds, r.rel_mse?)))
            .collect();
        if points.is_empty() {
            continue;
        }
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &threshold in &THRESHOLDS {
            out.push(Crossing {
                scene: scene.clone(),
                integrator: integrator.clone(),
                rel_mse: threshold,
                seconds: crossing_time(&points, threshold),
            });
        }
    }
    out
}

/// First time the curve `(seconds, error)` reaches `threshold`, interpolating log error
/// against log time between the runs on either side.
pub fn crossing_time(points: &[(f64, f64)], threshold: f64) -> Option<f64> {
    let i = points.iter().position(|&(_, e)| e <= threshold)?;
    if i == 0 {
        return Some(points[0].0);
    }
    let ((t0, e0), (t1, e1)) = (points[i - 1], points[i]);
    if !(e0 > 0.0 && e1 > 0.0 && t0 > 0.0 && t1 > 0.0) || e0 == e1 {
        return Some(t1);
    }
    let f = (threshold.ln() - e0.ln()) / (e1.ln() - e0.ln());
    Some((t0.ln() + f * (t1.ln() - t0.ln())).exp())
}

/// Check a reference against the scene's resolution.
pub fn check_reference(reference: &Image, desc: &SceneDesc, name: &str) -> Result<()> {
    let (w, h) = (desc.camera.width, desc.camera.height);
    if reference.width != w || reference.height != h {
        return Err(Error::InvalidSetting(format!(
            "the reference for {name} is {}×{}, the scene renders {w}×{h}",
            reference.width, reference.height
        )));
    }
    Ok(())
}

/// A run with only its error and time, for tests.
#[cfg(test)]
pub(crate) fn test_run(scene: &str, integrator: &str, seconds: f64, rel_mse: f64) -> Run {
    Run {
        scene: scene.into(),
        integrator: integrator.into(),
        budget: seconds,
        seconds,
        samples: String::new(),
        rel_mse: Some(rel_mse),
        rmse: None,
        crop_rmse: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_interpolates_in_log_log() {
        // Error ∝ 1/t: 0.01 at 1 s, 0.001 at 10 s; 0.003 is crossed at 10/3 s.
        let points = [(1.0, 0.01), (10.0, 0.001)];
        let t = crossing_time(&points, 0.003).expect("reached");
        assert!((t - 10.0 / 3.0).abs() < 1e-9, "{t}");
        assert_eq!(crossing_time(&points, 0.02), Some(1.0));
        assert_eq!(crossing_time(&points, 0.0005), None);
    }

    #[test]
    fn crossings_cover_each_scene_and_integrator_once_per_threshold() {
        let run = |integrator: &str, seconds: f64, e: f64| test_run("s", integrator, seconds, e);
        let runs = [
            run("ppm", 4.0, 0.002),
            run("ppm", 1.0, 0.02),
            run("path", 1.0, 0.5),
        ];
        let c = crossings(&runs);
        assert_eq!(c.len(), 6);
        let ppm_01 = c
            .iter()
            .find(|c| c.integrator == "ppm" && c.rel_mse == 0.01)
            .expect("ppm");
        // Between (1 s, 0.02) and (4 s, 0.002): one third of the way in log error.
        let expected = (4.0f64.ln() * (0.5f64.ln() / 0.1f64.ln())).exp();
        assert!((ppm_01.seconds.expect("reached") - expected).abs() < 1e-9);
        assert!(
            c.iter()
                .filter(|c| c.integrator == "path")
                .all(|c| c.seconds.is_none())
        );
    }
}
