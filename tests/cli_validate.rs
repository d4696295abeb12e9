//! `photon validate`: the table of the validation suite, from the command line.

use crate::common;

use common::{assert_usage_error, photon};
use std::path::Path;

#[test]
fn validate_prints_the_table_and_writes_the_report() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = common::temp_dir("validate-report");
    let report = dir.join("REPORT.md");
    let o = photon(
        &[
            "validate",
            "--quick",
            "--scenes",
            "directional",
            "--integrators",
            "path,photon",
            "--report",
            report.to_str().expect("utf-8"),
        ],
        root,
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", common::stderr(&o));
    for method in ["path", "photon"] {
        let row = out
            .lines()
            .find(|l| l.starts_with(&format!("| directional | {method} |")))
            .unwrap_or_else(|| panic!("no row for {method}: {out}"));
        // The mean ratios (columns 5–7) are near 1.
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        for c in &cells[5..8] {
            let r: f64 = c.parse().expect("a number");
            assert!((r - 1.0).abs() < 0.02, "{row}");
        }
    }
    let written = std::fs::read_to_string(&report).expect("report written");
    assert!(written.contains("| directional | photon |"), "{written}");
}

#[test]
fn validate_refuses_an_unknown_scene_or_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let o = photon(&["validate", "--quick", "--scenes", "no-such-scene"], root);
    assert_usage_error(&o, "no-such-scene");
    let empty = common::temp_dir("validate-empty");
    let o = photon(&["validate", empty.to_str().expect("utf-8")], root);
    assert_usage_error(&o, "no validation scenes");
    let o = photon(&["validate", "--integrators", "bogus"], root);
    assert_eq!(o.status.code(), Some(2));
}
