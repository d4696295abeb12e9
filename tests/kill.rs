//! Kill tests (issue #13): SIGKILL, SIGTERM and SIGINT at random moments of `sppm` and `ppm`
//! renders that continue a checkpoint. After every signal the image and the checkpoint on disk
//! are whole (the last complete pass, or the one before), and resuming to the end gives the
//! bytes of an uninterrupted run.
//!
//! The normal suite sends three signals per integrator; `cargo test --release --test
//! integration kill:: -- --ignored` sends twenty-four.

use crate::common;

use common::{photon, stderr, temp_dir};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

const SCENE: &str = r#"
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
[materials.white]
type = "diffuse"
[materials.glass]
type = "glass"
[[shapes]]
type = "quad"
vertices = [[-2.0, -1.0, -2.0], [2.0, -1.0, -2.0], [2.0, -1.0, 2.0], [-2.0, -1.0, 2.0]]
material = "white"
[[shapes]]
type = "sphere"
radius = 0.6
material = "glass"
[[lights]]
type = "point"
position = [0.0, 2.0, 1.0]
power = 50.0
"#;

/// Passes of a whole render; each takes about 80 ms here (most photons escape the scene).
const PASSES: u64 = 30;

/// The render flags shared by every run of `integrator` (seed and sizes fixed).
fn flags(integrator: &str) -> Vec<String> {
    [
        "--integrator",
        integrator,
        "--photons-per-pass",
        "1000000",
        "--width",
        "24",
        "--height",
        "24",
        "-q",
    ]
    .map(str::to_owned)
    .to_vec()
}

fn render(dir: &Path, integrator: &str, out: &str, passes: u64) -> std::process::Output {
    let passes = passes.to_string();
    // The checkpoint is what the kills are checked against, also once the run finishes.
    let mut args = vec![
        "render",
        "s.toml",
        "--passes",
        &passes,
        "-o",
        out,
        "--keep-checkpoint",
    ];
    let f = flags(integrator);
    args.extend(f.iter().map(String::as_str));
    photon(&args, dir)
}

/// xorshift64*: the same "random" moments on every run, so a failure can be replayed.
struct Moments(u64);

impl Moments {
    fn next(&mut self, below: u64) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) % below
    }
}

/// What the files on disk hold: the checkpoint's passes, and the image's and checkpoint's bytes.
struct OnDisk {
    passes: u64,
    image: Vec<u8>,
    checkpoint: Vec<u8>,
}

/// The image and checkpoint of `out` in `dir`, checked whole: the checkpoint loads and the
/// image decodes.
fn on_disk(dir: &Path, what: &str) -> OnDisk {
    let checkpoint_path = dir.join("out.checkpoint");
    let state = photon::io::checkpoint::load(&checkpoint_path)
        .unwrap_or_else(|e| panic!("{what}: the checkpoint is damaged: {e}"));
    photon::io::image::read_image(&dir.join("out.exr"))
        .unwrap_or_else(|e| panic!("{what}: the image is damaged: {e}"));
    OnDisk {
        passes: state.passes,
        image: std::fs::read(dir.join("out.exr")).expect("image"),
        checkpoint: std::fs::read(&checkpoint_path).expect("checkpoint"),
    }
}

/// `count` signals, cycling SIGKILL, SIGTERM and SIGINT, each at a random moment of a run that
/// resumes `out.checkpoint` towards `PASSES`; then the last resume must equal `reference`.
fn kill_and_resume(integrator: &str, count: usize, seed: u64) {
    let dir = temp_dir(&format!("kill-{integrator}-{count}"));
    std::fs::write(dir.join("s.toml"), SCENE).expect("write");
    let o = render(&dir, integrator, "reference.exr", PASSES);
    assert!(o.status.success(), "{}", stderr(&o));
    let reference = std::fs::read(dir.join("reference.exr")).expect("reference");
    let start = |dir: &Path| {
        let o = render(dir, integrator, "out.exr", 2);
        assert!(o.status.success(), "{}", stderr(&o));
    };
    start(&dir);
    let mut moments = Moments(seed);
    let (mut finished, mut lost_passes) = (0, 0);
    for trial in 0..count {
        let signal = ["KILL", "TERM", "INT"][trial % 3];
        let what = format!("{integrator} trial {trial} (SIG{signal})");
        let before = on_disk(&dir, &what);
        let target = PASSES.to_string();
        let child = Command::new(env!("CARGO_BIN_EXE_photon"))
            .args(["render", "--resume", "out.checkpoint", "--passes", &target])
            .arg("-q")
            .current_dir(&dir)
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        // Start-up (scene load) takes some milliseconds; passes some tens.
        std::thread::sleep(Duration::from_millis(moments.next(700)));
        let _ = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status();
        let out = child.wait_with_output().expect("waits");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{what}: {err}");
        if signal != "KILL" {
            // Interrupted (130), or finished before the signal arrived (0).
            assert!(
                matches!(out.status.code(), Some(0 | 130) | None),
                "{what}: exit {:?}: {err}",
                out.status
            );
        }
        let after = on_disk(&dir, &what);
        assert!(
            after.passes >= before.passes,
            "{what}: the checkpoint went back"
        );
        if after.passes == before.passes {
            assert_eq!(
                after.checkpoint, before.checkpoint,
                "{what}: checkpoint changed"
            );
            assert_eq!(after.image, before.image, "{what}: image changed");
            lost_passes += 1;
        }
        if after.passes == PASSES {
            assert!(
                after.image == reference,
                "{what}: differs from the reference"
            );
            finished += 1;
            for f in ["out.exr", "out.checkpoint"] {
                std::fs::remove_file(dir.join(f)).expect("remove");
            }
            start(&dir);
        }
    }
    let o = photon(
        &[
            "render",
            "--resume",
            "out.checkpoint",
            "--passes",
            &PASSES.to_string(),
            "-q",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let last = on_disk(&dir, "the last resume");
    assert_eq!(last.passes, PASSES);
    assert!(
        last.image == reference,
        "a render resumed after {count} signals differs from an uninterrupted one"
    );
    eprintln!(
        "{integrator}: {count} signals, {finished} runs finished before their signal, {lost_passes} signals arrived before a pass completed; resume identical"
    );
}

#[test]
fn signals_during_ppm_leave_whole_files_and_exact_resumes() {
    kill_and_resume("ppm", 3, 0x9e37_79b9_7f4a_7c15);
}

#[test]
fn signals_during_sppm_leave_whole_files_and_exact_resumes() {
    kill_and_resume("sppm", 3, 0xd1b5_4a32_d192_ed03);
}

#[test]
#[ignore = "long: 24 signals per integrator (about a minute each); run with --ignored"]
fn many_signals_during_ppm_and_sppm() {
    kill_and_resume("ppm", 24, 0x2545_f491_4f6c_dd1d);
    kill_and_resume("sppm", 24, 0x5851_f42d_4c95_7f2d);
}
