//! `photon validate`: the validation suite's table (scene × integrator).

use anyhow::{Context, Result, bail};
use photon::validate::{Budget, Method, Outcome, find_cases, load_case, run, table};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ValidateArgs {
    /// The suite's folder: sub-folders NAME/ holding NAME.toml and reference.exr.
    #[arg(default_value = "validation")]
    dir: PathBuf,
    /// Only these scenes (comma-separated folder names).
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
    /// Only these integrators (comma-separated: path, photon, sppm, ppm, vcm, bdpt, lighttrace;
    /// default: the first five).
    #[arg(long, value_delimiter = ',', value_parser = parse_method)]
    integrators: Vec<Method>,
    /// The test suite's small budget (32², few samples) instead of the full one (64²).
    #[arg(long)]
    quick: bool,
    /// Spectral transport, against each scene's reference-spectral.exr (Mitsuba's
    /// llvm_ad_spectral) instead of reference.exr; scenes without one are left out.
    #[arg(long)]
    spectral: bool,
    /// Also write the table, with the budget, to this Markdown file (e.g. validation/REPORT.md).
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
}

fn parse_method(s: &str) -> Result<Method, String> {
    Method::from_name(s).ok_or_else(|| {
        format!("'{s}' is not one of path, photon, sppm, ppm, vcm, bdpt, lighttrace")
    })
}

pub fn run_suite(a: &ValidateArgs) -> Result<()> {
    let budget = if a.quick { Budget::QUICK } else { Budget::FULL };
    let budget = if a.spectral {
        budget.spectral()
    } else {
        budget
    };
    let mut cases = find_cases(&a.dir, a.spectral)?;
    if !a.scenes.is_empty() {
        for s in &a.scenes {
            if !cases.iter().any(|c| &c.name == s) {
                bail!("no scene '{s}' in {}", a.dir.display());
            }
        }
        cases.retain(|c| a.scenes.contains(&c.name));
    }
    if cases.is_empty() {
        bail!(
            "{}: no validation scenes (folders NAME/ with NAME.toml and {})",
            a.dir.display(),
            photon::validate::reference_file_name(a.spectral)
        );
    }
    let methods = if a.integrators.is_empty() {
        let mut all = Method::ALL.to_vec();
        all.push(Method::Vcm);
        all
    } else {
        a.integrators.clone()
    };
    let pool = super::thread_pool(a.threads)?;
    let mut outcomes: Vec<Outcome> = Vec::new();
    for case in &cases {
        let loaded = load_case(case, budget.size)?;
        for &m in &methods {
            let o = pool.install(|| run(case, &loaded, m, &budget))?;
            let c = &o.comparison;
            eprintln!(
                "photon: {:<16} {:<6} {:6.2} s  relMSE {:.5}  mean ratios {:.4} {:.4} {:.4}",
                case.name,
                m.name(),
                o.seconds,
                c.overall.rel_mse,
                c.red.mean_ratio,
                c.green.mean_ratio,
                c.blue.mean_ratio
            );
            outcomes.push(o);
        }
    }
    let text = table(&outcomes);
    outln!("{text}");
    if let Some(path) = &a.report {
        let mut command = format!("photon validate {}", a.dir.display());
        if a.quick {
            command += " --quick";
        }
        if a.spectral {
            command += " --spectral";
        }
        if !a.scenes.is_empty() {
            command += &format!(" --scenes {}", a.scenes.join(","));
        }
        if !a.integrators.is_empty() {
            let names: Vec<&str> = a.integrators.iter().map(|m| m.name()).collect();
            command += &format!(" --integrators {}", names.join(","));
        }
        let report = format!(
            "# Validation report\n\nWritten by `{command} --report {}` on {} threads. \
             Budget: {:?}.\n\nReferences: Mitsuba 3 (see README.md). Mean ratios \
             are per channel; relMSE = mean (a − b)² / (b² + 0.01); the worst region is the \
             cell of a 4×4 grid whose mean luminance is furthest from the reference's.\n\n{text}",
            path.display(),
            pool.current_num_threads(),
            budget
        );
        photon::io::atomic::write_file(path, &report)
            .with_context(|| format!("writing {}", path.display()))?;
        eprintln!("photon: wrote {}", path.display());
    }
    Ok(())
}
