//! `photon bench` from the command line, on a tiny budget: the record holds real comparisons
//! with the shipped reference, the plot draws them (and a previous record, dashed), and bad
//! input is a usage error.

use crate::common;

use common::{assert_usage_error, photon};
use std::path::PathBuf;

fn references() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("bench/references")
        .to_string_lossy()
        .into_owned()
}

#[test]
fn bench_records_errors_against_the_reference_and_plots_them() {
    let dir = common::temp_dir("bench");
    let refs = references();
    let args = [
        "bench",
        "--scenes",
        "cornell",
        "--integrators",
        "ppm",
        "--budgets",
        "0.2,0.8",
        "--no-micro",
        "--references",
        &refs,
        "-o",
        "first",
    ];
    let o = photon(&args, &dir);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("| cornell | ppm |"), "{stdout}");
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("first/bench.json")).expect("json"))
            .expect("valid JSON");
    let runs = record["runs"].as_array().expect("runs");
    assert_eq!(runs.len(), 2);
    for run in runs {
        // A real comparison with the Mitsuba reference: a few passes of ppm are within a few
        // per cent, and nowhere near zero (which a self-comparison would give).
        let e = run["rel_mse"].as_f64().expect("relMSE");
        assert!(e > 1e-4 && e < 0.2, "relMSE {e}");
        assert!(run["crop_rmse"].as_f64().expect("crop") > 0.0);
        let seconds = run["seconds"].as_f64().expect("seconds");
        assert!(seconds >= run["budget"].as_f64().expect("budget"));
    }
    // How many passes a budget buys depends on the machine's load, so the record is checked
    // for its shape and its comparisons, never for which budget did better.
    for run in runs {
        let s = run["samples"].as_str().expect("samples");
        let passes: u64 = s
            .split(' ')
            .next()
            .and_then(|n| n.parse().ok())
            .expect("N passes");
        assert!(passes >= 1, "{s}");
    }
    assert_eq!(record["crossings"].as_array().expect("crossings").len(), 3);
    let svg = std::fs::read_to_string(dir.join("first/bench.svg")).expect("svg");
    assert_eq!(svg.matches("<polyline").count(), 1);

    // The same again with the first record as "before": two lines, one dashed.
    let mut again = args.to_vec();
    again.splice(8..8, ["--before", "first/bench.json"]);
    let last = again.len() - 1;
    again[last] = "second";
    let o = photon(&again, &dir);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let svg = std::fs::read_to_string(dir.join("second/bench.svg")).expect("svg");
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert!(svg.contains("ppm (before)"));

    // A stored record replotted renders nothing and draws the same lines.
    let o = photon(
        &[
            "bench",
            "--replot",
            "second/bench.json",
            "--before",
            "first/bench.json",
            "-o",
            "third",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(!dir.join("third/bench.json").exists());
    let replotted = std::fs::read_to_string(dir.join("third/bench.svg")).expect("svg");
    assert_eq!(replotted, svg);
}

#[test]
fn bench_refuses_bad_input() {
    let dir = common::temp_dir("bench-bad");
    let o = photon(&["bench", "--integrators", "nope", "--no-micro"], &dir);
    assert_usage_error(&o, "not one of");
    let o = photon(&["bench", "--budgets=0", "--no-micro"], &dir);
    assert_usage_error(&o, "--budgets");
    let o = photon(&["bench", "--before", "missing.json", "--no-micro"], &dir);
    assert_usage_error(&o, "missing.json");
    // A reference of another size than the scene's is refused before any render.
    std::fs::create_dir_all(dir.join("refs")).expect("dir");
    let o = photon(
        &[
            "render",
            "cornell",
            "--integrator",
            "direct",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
            "-q",
            "-o",
            "refs/cornell.exr",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = photon(
        &[
            "bench",
            "--scenes",
            "cornell",
            "--references",
            "refs",
            "--no-micro",
        ],
        &dir,
    );
    assert_usage_error(&o, "8×8");
}
