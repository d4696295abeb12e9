//! `photon bench`: the standard set (error against time per integrator on `cornell` and
//! `seed`, and the micro-benchmarks) as `OUT/bench.json` and `OUT/bench.svg`.

use anyhow::{Context, Result, bail};
use photon::accel::RayEngine;
use photon::bench::{self, BenchScene, Crossing, Run, micro, plot};
use photon::io::atomic::write_file;
use photon::io::image::read_image;
use photon::settings::IntegratorKind;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct BenchArgs {
    /// Scenes (comma-separated built-in names or scene files).
    #[arg(long, value_delimiter = ',', default_value = "cornell,seed")]
    scenes: Vec<String>,
    /// Integrators (comma-separated: photon, sppm, ppm, vcm, bdpt, lighttrace, path, direct).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "photon,sppm,ppm,vcm,path"
    )]
    integrators: Vec<String>,
    /// Wall-clock budgets in seconds (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "1,4,12,40")]
    budgets: Vec<f64>,
    /// Folder of references, NAME.exr for scene NAME (the repository's bench/references).
    #[arg(long, default_value = "bench/references")]
    references: PathBuf,
    /// Render spectrally, against NAME-spectral.exr in the references' folder.
    #[arg(long)]
    spectral: bool,
    /// Output folder: bench.json and bench.svg.
    #[arg(short, long, default_value = "bench-results")]
    output: PathBuf,
    /// A previous bench.json, drawn dashed in the plot ("before").
    #[arg(long, value_name = "JSON")]
    before: Option<PathBuf>,
    /// Skip the ray, photon and query micro-benchmarks.
    #[arg(long)]
    no_micro: bool,
    /// Only the micro-benchmarks.
    #[arg(long, conflicts_with = "no_micro")]
    micro_only: bool,
    /// Render nothing: draw the plot of this bench.json (with --before) into OUT/bench.svg.
    #[arg(long, value_name = "JSON", conflicts_with_all = ["no_micro", "micro_only"])]
    replot: Option<PathBuf>,
    /// A label for this record (e.g. a commit), shown in the plot's title.
    #[arg(long, default_value = "")]
    label: String,
    /// Worker threads for the renders (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
}

/// The record `bench.json` holds.
#[derive(Serialize, Deserialize)]
struct Record {
    photon_version: String,
    label: String,
    threads: usize,
    runs: Vec<Run>,
    #[serde(default)]
    crossings: Vec<Crossing>,
    #[serde(default)]
    micro: Option<serde_json::Value>,
}

fn parse_integrators(names: &[String]) -> Result<Vec<IntegratorKind>> {
    names
        .iter()
        .map(|n| {
            IntegratorKind::from_name(n).with_context(|| {
                let names: Vec<&str> = IntegratorKind::ALL.iter().map(|k| k.name()).collect();
                format!("--integrators: '{n}' is not one of {}", names.join(", "))
            })
        })
        .collect()
}

pub fn run(a: &BenchArgs) -> Result<()> {
    let integrators = parse_integrators(&a.integrators)?;
    if let Some(b) = a.budgets.iter().find(|b| !(**b > 0.0 && **b <= 86_400.0)) {
        bail!("--budgets: {b} is not a number of seconds in (0, 86400]");
    }
    let before: Vec<Run> = match &a.before {
        Some(path) => read_record(path)?.runs,
        None => Vec::new(),
    };
    if let Some(path) = &a.replot {
        let record = read_record(path)?;
        std::fs::create_dir_all(&a.output)
            .with_context(|| format!("creating {}", a.output.display()))?;
        let title = plot_title(&record, !before.is_empty());
        write_text(
            &a.output.join("bench.svg"),
            &plot::svg(&title, &record.runs, &before),
        )?;
        eprintln!("photon: wrote {}/bench.svg", a.output.display());
        return Ok(());
    }
    let pool = super::thread_pool(a.threads)?;
    let mut runs = Vec::new();
    if !a.micro_only {
        for name in &a.scenes {
            runs.extend(bench_scene(a, name, &integrators, &pool)?);
        }
    }
    let micro = if a.no_micro {
        None
    } else {
        Some(micro_benchmarks()?)
    };
    let crossings = bench::crossings(&runs);
    print_crossings(&crossings);
    let record = Record {
        photon_version: env!("CARGO_PKG_VERSION").into(),
        label: a.label.clone(),
        threads: pool.current_num_threads(),
        runs,
        crossings,
        micro,
    };
    std::fs::create_dir_all(&a.output)
        .with_context(|| format!("creating {}", a.output.display()))?;
    let json = serde_json::to_string_pretty(&record)? + "\n";
    write_text(&a.output.join("bench.json"), &json)?;
    if !record.runs.is_empty() {
        let title = plot_title(&record, !before.is_empty());
        write_text(
            &a.output.join("bench.svg"),
            &plot::svg(&title, &record.runs, &before),
        )?;
    }
    eprintln!(
        "photon: wrote {}/bench.json and bench.svg",
        a.output.display()
    );
    Ok(())
}

fn bench_scene(
    a: &BenchArgs,
    name: &str,
    integrators: &[IntegratorKind],
    pool: &rayon::ThreadPool,
) -> Result<Vec<Run>> {
    let (scene, desc) = bench::load(name).with_context(|| format!("loading {name}"))?;
    let crop = BenchScene::standard()
        .into_iter()
        .find(|s| s.name == name)
        .and_then(|s| s.crop);
    let stem = Path::new(name)
        .file_stem()
        .map_or(name.to_string(), |s| s.to_string_lossy().into_owned());
    let suffix = if a.spectral { "-spectral" } else { "" };
    let reference_path = a.references.join(format!("{stem}{suffix}.exr"));
    let reference = if reference_path.exists() {
        let r = read_image(&reference_path)
            .with_context(|| format!("reading {}", reference_path.display()))?;
        bench::check_reference(&r, &desc, name)?;
        Some(r)
    } else {
        eprintln!(
            "photon: no reference {} for {name}: times only",
            reference_path.display()
        );
        None
    };
    let mut runs = Vec::new();
    for &integrator in integrators {
        for &budget in &a.budgets {
            let (image, seconds, samples) =
                bench::run_at_budget(&scene, &desc, integrator, budget, a.spectral, pool)?;
            let [rel_mse, rmse, crop_rmse] = bench::measure(&image, reference.as_ref(), crop);
            let show = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.5}"));
            eprintln!(
                "photon: {name:<8} {:<6} budget {budget:>5} s: {seconds:6.2} s {samples:<12} relMSE {}  RMSE {}  crop RMSE {}",
                integrator.name(),
                show(rel_mse),
                show(rmse),
                show(crop_rmse)
            );
            runs.push(Run {
                scene: name.to_string(),
                integrator: integrator.name().to_string(),
                budget,
                seconds,
                samples,
                rel_mse,
                rmse,
                crop_rmse,
            });
        }
    }
    Ok(runs)
}

fn micro_benchmarks() -> Result<serde_json::Value> {
    let mut rays = Vec::new();
    for engine in RayEngine::compiled() {
        let r = micro::rays(engine)?;
        eprintln!(
            "photon: rays ({}), 1 thread: camera {:.2}, bounce {:.2}, shadow {:.2} M/s; {} threads: camera {:.2}, bounce {:.2} M/s ({} triangles, build {:.0} ms)",
            r.engine,
            r.camera_one_thread,
            r.bounce_one_thread,
            r.shadow_one_thread,
            r.threads,
            r.camera_all_threads,
            r.bounce_all_threads,
            r.triangles,
            r.build_ms
        );
        rays.push(r);
    }
    let mut photons = Vec::new();
    for name in ["cornell", "seed"] {
        let p = micro::photons(name)?;
        eprintln!(
            "photon: photons, {name}: {:.2} M emitted/s on {} threads ({} stored of 1 M)",
            p.emitted_per_s, p.threads, p.stored
        );
        photons.push(p);
    }
    let q = micro::queries()?;
    eprintln!(
        "photon: queries, 1 thread, {} photons, r {:.4} ({:.0} photons/query): random order: grid {:.2} M/s, kd-tree {:.2} M/s; spatial order: grid {:.2} M/s, kd-tree {:.2} M/s; kd 50-nearest {:.2} M/s (builds: grid {:.0} ms, kd {:.0} ms)",
        q.photons,
        q.radius,
        q.photons_per_query,
        q.grid_radius,
        q.kd_radius,
        q.grid_radius_coherent,
        q.kd_radius_coherent,
        q.kd_nearest_50,
        q.grid_build_ms,
        q.kd_build_ms
    );
    Ok(serde_json::json!({ "rays": rays, "photons": photons, "queries": q }))
}

fn print_crossings(crossings: &[Crossing]) {
    if crossings.is_empty() {
        return;
    }
    outln!("| scene | integrator | relMSE 0.01 | relMSE 0.003 | relMSE 0.001 |");
    outln!("|---|---|---:|---:|---:|");
    for chunk in crossings.chunks(bench::THRESHOLDS.len()) {
        let cells: Vec<String> = chunk
            .iter()
            .map(|c| {
                c.seconds
                    .map_or("not reached".into(), |s| format!("{s:.2} s"))
            })
            .collect();
        outln!(
            "| {} | {} | {} |",
            chunk[0].scene,
            chunk[0].integrator,
            cells.join(" | ")
        );
    }
}

fn plot_title(record: &Record, with_before: bool) -> String {
    format!(
        "photon bench {}{}: relMSE against wall-clock seconds, {} threads{}",
        record.photon_version,
        if record.label.is_empty() {
            String::new()
        } else {
            format!(" ({})", record.label)
        },
        record.threads,
        if with_before { "; dashed: before" } else { "" }
    )
}

fn read_record(path: &Path) -> Result<Record> {
    let text = photon::io::input::read_text(path)
        .with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a bench.json record", path.display()))
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    write_file(path, text).with_context(|| format!("writing {}", path.display()))
}
