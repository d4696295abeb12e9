//! Progressive renders from the command line: resume, merge of partial renders, and a real
//! interruption, each byte-identical to one uninterrupted run.

use crate::common;

use common::{assert_usage_error, photon, stderr};
use std::process::Command;

#[test]
fn progressive_resume_and_merge_are_byte_identical() {
    let dir = common::temp_dir("progressive");
    let base = [
        "--width",
        "16",
        "--height",
        "16",
        "--photons-per-pass",
        "2000",
        "-q",
    ];
    let run = |extra: &[&str]| {
        let args: Vec<&str> = ["render", "cornell"]
            .iter()
            .chain(extra)
            .chain(base.iter())
            .copied()
            .collect();
        photon(&args, &dir)
    };
    for method in ["sppm", "ppm"] {
        let full = format!("{method}-full.pfm");
        let part = format!("{method}-part.pfm");
        let o = run(&["--integrator", method, "--passes", "5", "-o", &full]);
        assert!(o.status.success(), "{}", stderr(&o));
        // A finished render leaves no checkpoint, so the same command runs again.
        assert!(
            !dir.join(format!("{method}-full.checkpoint")).exists(),
            "a finished {method} render left its checkpoint"
        );
        let again = run(&["--integrator", method, "--passes", "5", "-o", &full]);
        assert!(again.status.success(), "{}", stderr(&again));
        let o = run(&[
            "--integrator",
            method,
            "--passes",
            "2",
            "-o",
            &part,
            "--snapshots",
            "--keep-checkpoint",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            dir.join(format!("{method}-part.pass00001.pfm")).exists(),
            "snapshot after pass 1"
        );
        assert!(
            dir.join(format!("{method}-part.pass00002.pfm")).exists(),
            "snapshot after pass 2"
        );
        let checkpoint = format!("{method}-part.checkpoint");
        let o = photon(
            &["render", "--resume", &checkpoint, "--passes", "5", "-q"],
            &dir,
        );
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            std::fs::read(dir.join(&part)).expect("resumed"),
            std::fs::read(dir.join(&full)).expect("full"),
            "{method}: interrupted at 2 and resumed to 5 equals 5 straight"
        );
    }
    // ppm partial renders merge into the single run's image.
    for (range, name) in [("0..2", "a.part"), ("2..4", "b.part"), ("4..5", "c.part")] {
        let o = run(&["--integrator", "ppm", "--pass-range", range, "-o", name]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = photon(
        &["merge", "c.part", "a.part", "b.part", "-o", "merged.pfm"],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(dir.join("merged.pfm")).expect("merged"),
        std::fs::read(dir.join("ppm-full.pfm")).expect("full")
    );
    // A gap is a merge of the passes present (a job merged before all tasks finished);
    // a part given twice is refused.
    let o = photon(&["merge", "a.part", "c.part", "-o", "gap.pfm"], &dir);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("(3 passes or samples per pixel)"),
        "{}",
        stderr(&o)
    );
    assert_usage_error(
        &photon(&["merge", "a.part", "a.part", "-o", "twice.pfm"], &dir),
        "overlap",
    );
    let mut bytes = std::fs::read(dir.join("sppm-part.checkpoint")).expect("checkpoint");
    let k = bytes.len() / 2;
    bytes[k] ^= 1;
    std::fs::write(dir.join("bad.checkpoint"), &bytes).expect("write");
    assert_usage_error(
        &photon(&["render", "--resume", "bad.checkpoint", "-q"], &dir),
        "corrupted",
    );
    assert_usage_error(
        &run(&[
            "--integrator",
            "sppm",
            "--pass-range",
            "0..2",
            "-o",
            "s.part",
        ]),
        "--pass-range 0..2: the sppm integrator does not take it (it is for ppm, vcm, bdpt and lighttrace)",
    );
    assert_usage_error(
        &run(&["--integrator", "ppm", "-o", "p.png"]),
        "needs a number of passes or a time",
    );
    assert_usage_error(
        &run(&[
            "--integrator",
            "ppm",
            "--passes",
            "2",
            "--alpha",
            "1.5",
            "-o",
            "p.png",
        ]),
        "alpha",
    );
}

#[test]
fn an_interrupted_progressive_render_resumes_to_the_same_image() {
    let dir = common::temp_dir("interrupt");
    let base = [
        "render",
        "cornell",
        "--integrator",
        "sppm",
        "--width",
        "24",
        "--height",
        "24",
        "--photons-per-pass",
        "20000",
        "-q",
    ];
    let child = Command::new(env!("CARGO_BIN_EXE_photon"))
        .args(base)
        .args(["--passes", "100000", "-o", "i.pfm"])
        .current_dir(&dir)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let _ = Command::new("kill").arg(child.id().to_string()).status();
    let out = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    let done: u64 = err
        .split("interrupted after pass ")
        .nth(1)
        .and_then(|t| t.split(';').next())
        .and_then(|n| n.trim().parse().ok())
        .expect("pass count in the message");
    let target = (done + 2).to_string();
    let o = photon(
        &[
            "render",
            "--resume",
            "i.checkpoint",
            "--passes",
            &target,
            "-q",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let mut args: Vec<&str> = base.to_vec();
    args.extend(["--passes", &target, "-o", "straight.pfm"]);
    let o = photon(&args, &dir);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(dir.join("i.pfm")).expect("resumed"),
        std::fs::read(dir.join("straight.pfm")).expect("straight")
    );
}
