//! Render jobs as untrusted input (issue #25): a job folder's name, its manifest and its parts
//! may be hostile or foreign, and several workers may share one task. Every generated command
//! and script quotes what it names, every path stays inside the job folder, a part proves the
//! job it belongs to, and a task has one writer at a time.

use crate::common;

use common::{assert_usage_error, photon, stderr, temp_dir};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(o))
}

/// A folder name with spaces, both quotes, `$`, a command substitution and a newline
/// followed by a line a shell (or sbatch) would run or obey.
const HOSTILE: &str = "job 'a' \"b\" $HOME $(touch PWNED)\n#SBATCH --wrap=touch PWNED\ntouch PWNED";

/// A tiny job of the built-in Cornell box: 2 tasks of 1 sample per pixel, 8×8 pixels.
fn tiny_job(dir: &Path, name: &str, extra: &[&str]) {
    let mut args = vec![
        "job",
        "create",
        "--tasks",
        "2",
        "-o",
        name,
        "cornell",
        "--integrator",
        "path",
        "--spp",
        "2",
        "--width",
        "8",
        "--height",
        "8",
    ];
    args.extend(extra);
    ok(&photon(&args, dir));
}

/// `sh -c SCRIPT` in `dir` with the photon binary first in PATH, as a user pasting it.
fn shell(script: &str, dir: &Path) -> Output {
    let bin = Path::new(env!("CARGO_BIN_EXE_photon"))
        .parent()
        .expect("bin dir")
        .to_owned();
    let path = std::env::join_paths(std::iter::once(bin).chain(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    )))
    .expect("PATH");
    Command::new("sh")
        .args(["-c", script])
        .env("PATH", path)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX")
        .env_remove("PARALLEL_SEQ")
        .current_dir(dir)
        .output()
        .expect("sh")
}

/// The `#SBATCH` options sbatch reads: the comment lines before the first command.
fn sbatch_options(script: &str) -> Vec<String> {
    script
        .lines()
        .skip(1)
        .take_while(|l| l.trim().is_empty() || l.starts_with('#'))
        .filter_map(|l| l.strip_prefix("#SBATCH "))
        .map(str::to_owned)
        .collect()
}

#[test]
fn slurm_scripts_of_a_hostile_folder_name_run_the_job_and_nothing_else() {
    let dir = temp_dir("jobh-slurm-script");
    tiny_job(&dir, HOSTILE, &[]);
    ok(&photon(
        &[
            "job",
            "submit",
            HOSTILE,
            "--slurm",
            "--dry-run",
            "--time",
            "1:00",
        ],
        &dir,
    ));
    let job = dir.join(HOSTILE);
    let task = std::fs::read_to_string(job.join("slurm/task.sbatch")).expect("task script");
    let merge = std::fs::read_to_string(job.join("slurm/merge.sbatch")).expect("merge script");
    for script in [&task, &merge] {
        for option in sbatch_options(script) {
            let name = option.split('=').next().unwrap_or("");
            assert!(
                [
                    "--job-name",
                    "--time",
                    "--array",
                    "--cpus-per-task",
                    "--output"
                ]
                .contains(&name),
                "unexpected sbatch option '{option}' in:\n{script}"
            );
            assert!(
                !option.contains(|c: char| c.is_whitespace() || "'\"$()".contains(c)),
                "'{option}' is not one token:\n{script}"
            );
        }
    }
    // The scripts as Slurm runs them: in the folder they were submitted from, the job's.
    for i in 0..2 {
        let o = Command::new("sh")
            .arg("slurm/task.sbatch")
            .env("SLURM_ARRAY_TASK_ID", i.to_string())
            .current_dir(&job)
            .output()
            .expect("sh");
        ok(&o);
    }
    ok(&Command::new("sh")
        .arg("slurm/merge.sbatch")
        .current_dir(&job)
        .output()
        .expect("sh"));
    assert!(job.join("merged.exr").is_file());
    assert!(!job.join("PWNED").exists() && !dir.join("PWNED").exists());
    // Values that sbatch reads as tokens are refused when they hold anything else.
    for (flag, value) in [
        ("--time", "1:00\ntouch PWNED"),
        ("--time", "1:00 --wrap=x"),
        ("--partition", "debug\n#SBATCH --wrap=x"),
        ("--partition", "a b"),
    ] {
        assert_usage_error(
            &photon(
                &[
                    "job",
                    "submit",
                    HOSTILE,
                    "--slurm",
                    "--dry-run",
                    flag,
                    value,
                ],
                &dir,
            ),
            flag,
        );
    }
}

#[test]
fn rerun_commands_are_quoted_for_the_shell() {
    let dir = temp_dir("jobh-rerun");
    tiny_job(&dir, HOSTILE, &[]);
    let status = ok(&photon(&["job", "status", HOSTILE], &dir));
    let here = status
        .split("here:")
        .nth(1)
        .and_then(|rest| rest.split("\n  parallel:").next())
        .expect("a rerun line")
        .trim();
    ok(&shell(here, &dir));
    assert!(!dir.join("PWNED").exists(), "{here}");
    let status = ok(&photon(&["job", "status", HOSTILE], &dir));
    assert!(status.contains("2 of 2 tasks done"), "{status}");
    let merge = status
        .split("all parts present: ")
        .nth(1)
        .expect("a merge line")
        .trim();
    ok(&shell(merge, &dir));
    assert!(dir.join("image.exr").is_file() && !dir.join("PWNED").exists());
}

#[test]
fn the_parallel_rerun_line_runs_the_missing_tasks() {
    if Command::new("parallel").arg("--version").output().is_err() {
        eprintln!("GNU parallel is not installed (apt-get install parallel): skipped");
        return;
    }
    let dir = temp_dir("jobh-parallel");
    tiny_job(&dir, HOSTILE, &[]);
    let status = ok(&photon(&["job", "status", HOSTILE], &dir));
    let line = status
        .split("parallel:")
        .nth(1)
        .and_then(|rest| rest.split("\n  Slurm:").next())
        .expect("a parallel line")
        .trim()
        .replacen("parallel ", "parallel --will-cite ", 1);
    ok(&shell(&line, &dir));
    assert!(!dir.join("PWNED").exists(), "{line}");
    let status = ok(&photon(&["job", "status", HOSTILE], &dir));
    assert!(status.contains("2 of 2 tasks done"), "{line}\n{status}");
}

#[test]
fn printed_commands_do_not_grow_with_the_task_count() {
    let dir = temp_dir("jobh-many-tasks");
    let o = photon(
        &[
            "job",
            "create",
            "--tasks",
            "100000",
            "-o",
            "j",
            "cornell",
            "--integrator",
            "path",
            "--spp",
            "100000",
            "--width",
            "2",
            "--height",
            "2",
        ],
        &dir,
    );
    let created = ok(&o);
    assert!(created.len() < 2000, "{} bytes", created.len());
    let o = photon(&["job", "status", "j"], &dir);
    let status = ok(&o);
    assert!(status.len() < 2000, "{} bytes", status.len());
}

/// A scene in `scenes/a/b/` that names its mesh `../../meshes/cube.obj`.
fn scene_reaching_up(dir: &Path) -> PathBuf {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/assets");
    std::fs::create_dir_all(dir.join("scenes/meshes")).expect("meshes");
    std::fs::create_dir_all(dir.join("scenes/a/b")).expect("a/b");
    for f in ["cube.obj", "cube.mtl", "tiles.png"] {
        std::fs::copy(fixtures.join(f), dir.join("scenes/meshes").join(f)).expect("copy");
    }
    let scene = dir.join("scenes/a/b/s.toml");
    std::fs::write(
        &scene,
        r#"
[camera]
position = [2.0, 2.0, 4.0]
look_at = [0.0, 0.0, 0.0]
[[shapes]]
type = "mesh"
file = "../../meshes/cube.obj"
[[lights]]
type = "point"
position = [1.0, 3.0, 2.0]
power = 200.0
"#,
    )
    .expect("scene");
    scene
}

#[test]
fn scene_files_named_through_dotdot_are_copied_inside_the_job() {
    let dir = temp_dir("jobh-dotdot");
    let scene = scene_reaching_up(&dir);
    // A user's file where `JOB/scene/../../meshes/cube.obj` points.
    std::fs::create_dir_all(dir.join("out/meshes")).expect("out");
    std::fs::write(dir.join("out/meshes/cube.obj"), "the user's file").expect("user file");
    ok(&photon(
        &[
            "job",
            "create",
            "--tasks",
            "2",
            "-o",
            "out/j",
            &scene.to_string_lossy(),
            "--integrator",
            "path",
            "--spp",
            "2",
            "--width",
            "8",
            "--height",
            "8",
        ],
        &dir,
    ));
    assert_eq!(
        std::fs::read_to_string(dir.join("out/meshes/cube.obj")).expect("user file"),
        "the user's file"
    );
    // The job carries the mesh: it renders with the originals gone.
    std::fs::remove_dir_all(dir.join("scenes")).expect("remove originals");
    std::fs::rename(dir.join("out/j"), dir.join("moved")).expect("move");
    ok(&photon(&["job", "run", "moved", "--task", "0"], &dir));
    let manifest = std::fs::read_to_string(dir.join("moved/job.toml")).expect("manifest");
    assert!(!manifest.contains(".."), "{manifest}");
}

/// `JOB/job.toml` with `from` replaced by `to` (the test fails if `from` is not there).
fn tamper(job: &Path, from: &str, to: &str) {
    let path = job.join("job.toml");
    let text = std::fs::read_to_string(&path).expect("manifest");
    assert!(text.contains(from), "'{from}' not in:\n{text}");
    std::fs::write(&path, text.replacen(from, to, 1)).expect("write");
}

#[test]
fn tampered_manifests_are_refused_before_anything_is_rendered() {
    let dir = temp_dir("jobh-tampered");
    common_scene(&dir.join("other.toml"));
    let outside = dir.join("other.toml").to_string_lossy().into_owned();
    let scene_line = |s: &str| format!("scene = {}", toml_string(s));
    for (what, from, to, needle) in [
        (
            "absolute scene",
            "scene = \"scene/s.toml\"".to_owned(),
            scene_line(&outside),
            "scene",
        ),
        (
            "scene outside scene/",
            "scene = \"scene/s.toml\"".to_owned(),
            scene_line("scene/../../other.toml"),
            "scene",
        ),
        (
            "scene not among the files",
            "scene = \"scene/s.toml\"".to_owned(),
            scene_line("scene/t.toml"),
            "scene",
        ),
        (
            "file outside scene/",
            "path = \"scene/s.toml\"".to_owned(),
            "path = \"parts/../../other.toml\"".to_owned(),
            "path",
        ),
        (
            "endless range",
            "tasks = [[0, 1], [1, 2]]".to_owned(),
            "tasks = [[0, 1], [1, 18446744073709551615]]".to_owned(),
            "total",
        ),
    ] {
        let job = dir.join("j");
        let _ = std::fs::remove_dir_all(&job);
        common_scene(&dir.join("s.toml"));
        ok(&photon(
            &[
                "job",
                "create",
                "--tasks",
                "2",
                "-o",
                "j",
                "s.toml",
                "--integrator",
                "path",
                "--spp",
                "2",
                "--width",
                "8",
                "--height",
                "8",
            ],
            &dir,
        ));
        tamper(&job, &from, &to);
        if what == "endless range" {
            tamper(&job, "total = 2", "total = 18446744073709551615");
        }
        if what == "absolute scene" || what == "scene outside scene/" {
            // The attacker's manifest lists no files, so none is checked.
            let text = std::fs::read_to_string(job.join("job.toml")).expect("manifest");
            let cut = text.find("[[files]]").expect("files");
            std::fs::write(
                job.join("job.toml"),
                format!("files = []\n{}", &text[..cut]),
            )
            .expect("write");
        }
        let o = photon(&["job", "run", "j", "--task", "1"], &dir);
        assert_usage_error(&o, "job.toml");
        assert_usage_error(&o, needle);
        assert!(!job.join("parts/1.part").exists(), "{what}: rendered");
        assert_usage_error(&photon(&["job", "status", "j"], &dir), "job.toml");
    }
}

fn toml_string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

fn common_scene(path: &Path) {
    std::fs::write(
        path,
        r#"
[camera]
position = [2.0, 2.0, 4.0]
look_at = [0.0, 0.0, 0.0]
[materials.white]
type = "diffuse"
albedo = [0.8, 0.8, 0.8]
[[shapes]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "white"
[[lights]]
type = "point"
position = [1.0, 3.0, 2.0]
power = 200.0
"#,
    )
    .expect("scene");
}

#[test]
fn parts_of_another_job_are_not_done() {
    let dir = temp_dir("jobh-foreign");
    tiny_job(&dir, "a", &[]);
    tiny_job(&dir, "b", &["--seed", "7"]);
    let c_args = [
        "job",
        "create",
        "--tasks",
        "2",
        "-o",
        "c",
        "seed",
        "--integrator",
        "path",
        "--spp",
        "2",
        "--width",
        "8",
        "--height",
        "8",
    ];
    ok(&photon(&c_args, &dir));
    for i in ["0", "1"] {
        ok(&photon(&["job", "run", "a", "--task", i], &dir));
    }
    for other in ["b", "c"] {
        for i in ["0", "1"] {
            std::fs::copy(
                dir.join(format!("a/parts/{i}.part")),
                dir.join(format!("{other}/parts/{i}.part")),
            )
            .expect("copy the part");
        }
        let status = ok(&photon(&["job", "status", other], &dir));
        assert!(status.contains("0 of 2 tasks done"), "{other}: {status}");
        let o = photon(
            &["job", "merge", other, "-o", "m.exr", "--require-all"],
            &dir,
        );
        assert!(!o.status.success(), "{other}: merged another job's parts");
        assert!(stderr(&o).contains("another job"), "{}", stderr(&o));
        let text = ok(&photon(&["job", "run", other, "--task", "0"], &dir));
        assert!(!text.contains("already done"), "{text}");
    }
}

/// This machine's host name as the job system records it.
fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .expect("hostname")
        .trim()
        .to_owned()
}

/// A process id no process has (above Linux's largest `pid_max`).
const DEAD_PID: u32 = 99_999_999;

#[test]
fn a_task_has_one_worker_at_a_time() {
    let dir = temp_dir("jobh-lock");
    tiny_job(&dir, "j", &[]);
    // Another host's worker holds task 0: a second worker leaves it alone (exit 75, retry).
    std::fs::write(
        dir.join("j/parts/0.lock"),
        format!("host = \"elsewhere\"\npid = {DEAD_PID}\n"),
    )
    .expect("lock");
    let o = photon(&["job", "run", "j", "--task", "0"], &dir);
    assert_eq!(o.status.code(), Some(75), "{}", stderr(&o));
    assert!(stderr(&o).contains("elsewhere"), "{}", stderr(&o));
    assert!(!dir.join("j/parts/0.part").exists());
    let status = ok(&photon(&["job", "status", "j"], &dir));
    assert!(status.contains("1 running"), "{status}");
    // A lock this host's dead worker left is taken over.
    std::fs::write(
        dir.join("j/parts/1.lock"),
        format!("host = \"{}\"\npid = {DEAD_PID}\n", host_name()),
    )
    .expect("lock");
    ok(&photon(&["job", "run", "j", "--task", "1"], &dir));
    assert!(dir.join("j/parts/1.part").is_file());
    assert!(!dir.join("j/parts/1.lock").exists());
}

#[test]
fn temporaries_of_other_hosts_are_left_alone() {
    let dir = temp_dir("jobh-temporaries");
    tiny_job(&dir, "j", &[]);
    let parts = dir.join("j/parts");
    let legacy = parts.join(format!(".0.part.{DEAD_PID}.partial"));
    let foreign = parts.join(format!(".0.part.elsewhere.{DEAD_PID}.partial"));
    let own_dead = parts.join(format!(".0.part.{}.{DEAD_PID}.partial", host_name()));
    for f in [&legacy, &foreign, &own_dead] {
        std::fs::write(f, "being written").expect("temporary");
    }
    ok(&photon(&["job", "run", "j", "--task", "0"], &dir));
    assert!(legacy.exists(), "a temporary of unknown host was removed");
    assert!(foreign.exists(), "another host's temporary was removed");
    assert!(!own_dead.exists(), "this host's dead temporary was kept");
}

#[test]
fn job_errors_have_the_right_exit_codes() {
    let dir = temp_dir("jobh-exit-codes");
    tiny_job(&dir, "j", &[]);
    // A job copied without its empty parts/ folder still runs.
    std::fs::remove_dir(dir.join("j/parts")).expect("remove parts");
    ok(&photon(&["job", "run", "j", "--task", "0"], &dir));
    assert!(dir.join("j/parts/0.part").is_file());
    // Another Photon version: exit 2, and the failure is recorded for `job status`.
    tamper(
        &dir.join("j"),
        &format!("photon_version = \"{}\"", env!("CARGO_PKG_VERSION")),
        "photon_version = \"0.0.1\"",
    );
    assert_usage_error(&photon(&["job", "run", "j", "--task", "1"], &dir), "0.0.1");
    assert!(dir.join("j/parts/1.failed").is_file());
    let status = ok(&photon(&["job", "status", "j"], &dir));
    assert!(status.contains("1 failed"), "{status}");
    for exposure in ["nan", "inf", "-1000"] {
        assert_usage_error(
            &photon(
                &["job", "merge", "j", "-o", "m.png", "--exposure", exposure],
                &dir,
            ),
            "--exposure",
        );
    }
}

/// An RFC 1123 label, as Kubernetes requires of a Job's name.
fn is_dns_label(s: &str) -> bool {
    (1..=63).contains(&s.len())
        && s.bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-')
        && !s.starts_with('-')
        && !s.ends_with('-')
}

#[test]
fn kubernetes_jobs_have_valid_names_and_parallelism() {
    let dir = temp_dir("jobh-k8s");
    let long = "A".repeat(87);
    for name in ["___", long.as_str(), "Ünï code", HOSTILE] {
        tiny_job(&dir, name, &[]);
        let o = photon(&["job", "submit", name, "--k8s"], &dir);
        ok(&o);
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        let job_name = v["metadata"]["name"].as_str().expect("name");
        assert!(is_dns_label(job_name), "'{job_name}' for '{name}'");
    }
    for flags in [["--cpus", "0"], ["--max-running", "0"]] {
        for scheduler in ["--k8s", "--slurm"] {
            let mut args = vec!["job", "submit", "___", scheduler, "--dry-run"];
            args.extend(flags);
            if scheduler == "--k8s" {
                args.retain(|a| *a != "--dry-run");
            }
            assert_usage_error(&photon(&args, &dir), flags[0]);
        }
    }
}
