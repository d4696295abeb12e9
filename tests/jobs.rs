//! Render jobs (issue #14): a job folder split into tasks, run in any order, merged into the
//! bytes of a single-machine render; idempotent workers, failures reported with the command
//! that reruns them; GNU parallel locally; the Kubernetes manifest's structure. The Slurm
//! test needs a running cluster (`.ci/slurm-up`) and is ignored otherwise:
//! `cargo test --release --test integration jobs:: -- --ignored`.

use crate::common;

use common::{assert_usage_error, photon, stderr, temp_dir};
use std::path::Path;
use std::process::Command;

fn ok(o: &std::process::Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(o))
}

/// The order tasks finish in: a fixed shuffle (a multiplicative permutation of 0..n).
fn shuffled(n: usize) -> Vec<usize> {
    let step = (1..n)
        .rev()
        .find(|s| gcd(*s, n) == 1 && *s * 2 > n)
        .unwrap_or(1);
    (0..n).map(|i| (i * step + n / 2) % n).collect()
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

const PPM: [&str; 10] = [
    "--integrator",
    "ppm",
    "--passes",
    "64",
    "--photons-per-pass",
    "2000",
    "--width",
    "16",
    "--height",
    "16",
];

#[test]
fn ppm_jobs_merge_into_the_single_render_for_any_task_count() {
    let dir = temp_dir("jobs-ppm");
    let mut single = vec!["render", "cornell", "-q", "-o", "single.exr"];
    single.extend(PPM);
    ok(&photon(&single, &dir));
    let single = std::fs::read(dir.join("single.exr")).expect("single");
    for tasks in [1, 3, 8, 64] {
        let job = format!("job{tasks}");
        let n = tasks.to_string();
        let mut create = vec!["job", "create", "--tasks", &n, "-o", &job, "cornell"];
        create.extend(PPM);
        ok(&photon(&create, &dir));
        let order = shuffled(tasks);
        for (k, &i) in order.iter().enumerate() {
            ok(&photon(
                &["job", "run", &job, "--task", &i.to_string()],
                &dir,
            ));
            if k + 1 == tasks / 2 {
                // Merging while tasks are missing gives the passes present, and says so.
                let o = photon(&["job", "merge", &job, "-o", "half.exr"], &dir);
                let text = ok(&o);
                assert!(text.contains(&format!("of {tasks} tasks")), "{text}");
                assert!(text.contains("missing tasks"), "{text}");
            }
        }
        let out = format!("{job}.exr");
        let text = ok(&photon(
            &["job", "merge", &job, "-o", &out, "--require-all"],
            &dir,
        ));
        assert!(text.contains("the image holds 64 of 64 passes"), "{text}");
        assert!(
            std::fs::read(dir.join(&out)).expect("merged") == single,
            "{tasks} tasks merged differ from the single render"
        );
    }
}

/// A scene that reads files beside and below it: the job must carry them all.
fn scene_with_files(dir: &Path) {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/assets");
    std::fs::create_dir_all(dir.join("assets")).expect("assets");
    for f in ["cube.obj", "cube.mtl", "tiles.png"] {
        std::fs::copy(fixtures.join(f), dir.join("assets").join(f)).expect("copy");
    }
    std::fs::write(
        dir.join("s.toml"),
        r#"
[camera]
position = [2.0, 2.0, 4.0]
look_at = [0.0, 0.0, 0.0]
[materials.tiles]
type = "diffuse"
albedo = { texture = "assets/tiles.png" }
[[shapes]]
type = "mesh"
file = "assets/cube.obj"
[[shapes]]
type = "quad"
vertices = [[-3.0, -1.0, -3.0], [3.0, -1.0, -3.0], [3.0, -1.0, 3.0], [-3.0, -1.0, 3.0]]
material = "tiles"
[[lights]]
type = "point"
position = [1.0, 3.0, 2.0]
power = 200.0
"#,
    )
    .expect("scene");
}

#[test]
fn path_and_photon_jobs_merge_bit_for_bit_and_carry_their_files() {
    let dir = temp_dir("jobs-path");
    scene_with_files(&dir);
    for (integrator, extra) in [
        ("path", &["--spp", "12"][..]),
        (
            "photon",
            &[
                "--spp",
                "4",
                "--photons",
                "5000",
                "--caustic-photons",
                "5000",
            ],
        ),
    ] {
        let size = [
            "--width",
            "24",
            "--height",
            "16",
            "--integrator",
            integrator,
        ];
        let mut single = vec!["render", "s.toml", "-q", "-o", "single.exr"];
        single.extend(size);
        single.extend(extra);
        ok(&photon(&single, &dir));
        let job = format!("{integrator}-job");
        let mut create = vec!["job", "create", "--tasks", "3", "-o", &job, "s.toml"];
        create.extend(size);
        create.extend(extra);
        ok(&photon(&create, &dir));
        // The job is self-contained: its copy of every file the scene reads is there, and
        // the originals can go.
        for f in [
            "s.toml",
            "assets/cube.obj",
            "assets/cube.mtl",
            "assets/tiles.png",
        ] {
            assert!(dir.join(&job).join("scene").join(f).is_file(), "{job}: {f}");
        }
        let moved = dir.join(format!("{job}-moved"));
        std::fs::rename(dir.join(&job), &moved).expect("move the job");
        for i in [2, 0, 1] {
            let text = ok(&photon(
                &[
                    "job",
                    "run",
                    &moved.to_string_lossy(),
                    "--task",
                    &i.to_string(),
                ],
                &dir,
            ));
            assert!(text.contains(&format!("task {i}")), "{text}");
        }
        ok(&photon(
            &["job", "merge", &moved.to_string_lossy(), "-o", "merged.exr"],
            &dir,
        ));
        assert!(
            std::fs::read(dir.join("merged.exr")).expect("merged")
                == std::fs::read(dir.join("single.exr")).expect("single"),
            "{integrator}: 3 tasks merged differ from the single render"
        );
    }
}

#[test]
fn workers_are_idempotent_and_failures_are_reported_with_the_rerun() {
    let dir = temp_dir("jobs-status");
    scene_with_files(&dir);
    ok(&photon(
        &[
            "job",
            "create",
            "--tasks",
            "4",
            "-o",
            "j",
            "s.toml",
            "--integrator",
            "path",
            "--spp",
            "4",
            "--width",
            "8",
            "--height",
            "8",
        ],
        &dir,
    ));
    ok(&photon(&["job", "run", "j", "--task", "0"], &dir));
    let before = std::fs::read(dir.join("j/parts/0.part")).expect("part");
    let text = ok(&photon(&["job", "run", "j", "--task", "0"], &dir));
    assert!(text.contains("already done"), "{text}");
    // A truncated part (a worker killed while the file system lost the rename's data) is
    // not done: it is redone.
    std::fs::write(dir.join("j/parts/1.part"), &before[..before.len() / 2]).expect("write");
    // The task index from the scheduler's environment: Slurm's 0-based, parallel's 1-based.
    let run_env = |var: &str, value: &str| {
        Command::new(env!("CARGO_BIN_EXE_photon"))
            .args(["job", "run", "j"])
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("JOB_COMPLETION_INDEX")
            .env_remove("PARALLEL_SEQ")
            .env(var, value)
            .current_dir(&dir)
            .output()
            .expect("run")
    };
    let text = ok(&run_env("SLURM_ARRAY_TASK_ID", "1"));
    assert!(text.contains("task 1 (samples per pixel 1..2)"), "{text}");
    let text = ok(&run_env("PARALLEL_SEQ", "3"));
    assert!(text.contains("task 2 "), "{text}");
    // A damaged copy of the scene: the worker refuses (exit 2, no retry) and says why.
    let mesh = dir.join("j/scene/assets/cube.obj");
    let mut bytes = std::fs::read(&mesh).expect("mesh");
    bytes[0] ^= 0x20;
    std::fs::write(&mesh, bytes).expect("write");
    assert_usage_error(
        &photon(&["job", "run", "j", "--task", "3"], &dir),
        "differs",
    );
    let o = photon(&["job", "status", "j"], &dir);
    let text = ok(&o);
    assert!(text.contains("3 of 4 tasks done"), "{text}");
    assert!(text.contains("task 3 failed"), "{text}");
    assert!(text.contains("sbatch --array=3 "), "{text}");
    assert!(text.contains("photon job run 'j' --task \"$i\""), "{text}");
    assert_usage_error(
        &photon(&["job", "run", "j", "--task", "4"], &dir),
        "tasks 0 to 3",
    );
    let o = photon(&["job", "merge", "j", "-o", "m.exr", "--require-all"], &dir);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
}

#[test]
fn what_cannot_be_split_is_refused_with_the_reason() {
    let dir = temp_dir("jobs-refused");
    for (args, needle) in [
        (
            vec!["cornell", "--integrator", "sppm", "--passes", "8"],
            "passes depend on each other",
        ),
        (
            vec!["cornell", "--integrator", "ppm"],
            "--passes: a ppm job splits its passes into tasks",
        ),
        (
            vec![
                "cornell",
                "--integrator",
                "ppm",
                "--passes",
                "8",
                "--time",
                "5",
            ],
            "--time",
        ),
        (vec!["cornell", "--spp", "4", "--aov", "albedo"], "--aov"),
    ] {
        let mut a = vec!["job", "create", "--tasks", "2", "-o", "j"];
        a.extend(args);
        assert_usage_error(&photon(&a, &dir), needle);
    }
    assert_usage_error(
        &photon(
            &[
                "job", "create", "--tasks", "9", "-o", "j", "cornell", "--spp", "8",
            ],
            &dir,
        ),
        "give 1 to 8 tasks",
    );
}

#[test]
fn the_kubernetes_manifest_is_an_indexed_job_running_the_worker() {
    let dir = temp_dir("jobs-k8s");
    ok(&photon(
        &[
            "job", "create", "--tasks", "5", "-o", "Job_A", "cornell", "--spp", "10",
        ],
        &dir,
    ));
    let o = photon(
        &[
            "job",
            "submit",
            "Job_A",
            "--k8s",
            "--cpus",
            "2",
            "--max-running",
            "3",
        ],
        &dir,
    );
    ok(&o);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["apiVersion"], "batch/v1");
    assert_eq!(v["kind"], "Job");
    // Kubernetes names are lower-case DNS labels.
    assert_eq!(v["metadata"]["name"], "photon-job-a");
    let spec = &v["spec"];
    assert_eq!(spec["completionMode"], "Indexed");
    assert_eq!(spec["completions"], 5);
    assert_eq!(spec["parallelism"], 3);
    let pod = &spec["template"]["spec"];
    assert_eq!(pod["restartPolicy"], "Never");
    let c = &pod["containers"][0];
    assert_eq!(
        c["command"],
        serde_json::json!(["photon", "job", "run", "/jobs/Job_A", "--threads", "2"])
    );
    assert_eq!(c["volumeMounts"][0]["mountPath"], "/jobs");
    assert_eq!(pod["volumes"][0]["name"], c["volumeMounts"][0]["name"]);
    // Exit 2 (bad job) fails the job at once; other failures are retried.
    assert_eq!(
        spec["podFailurePolicy"]["rules"][0]["onExitCodes"]["values"],
        serde_json::json!([2])
    );
}

#[test]
fn gnu_parallel_runs_the_tasks_locally() {
    if Command::new("parallel").arg("--version").output().is_err() {
        eprintln!("GNU parallel is not installed (apt-get install parallel): skipped");
        return;
    }
    let dir = temp_dir("jobs-parallel");
    let mut create = vec!["job", "create", "--tasks", "6", "-o", "j", "cornell"];
    create.extend(PPM);
    ok(&photon(&create, &dir));
    // The README's one-liner, with each task's index in place of {}.
    let bin = env!("CARGO_BIN_EXE_photon");
    let o = Command::new("parallel")
        .args([
            "--will-cite",
            "-j",
            "2",
            &format!("{bin} job run j --threads 1 --task {{}}"),
            ":::",
        ])
        .args((0..6).map(|i| i.to_string()))
        .current_dir(&dir)
        .output()
        .expect("parallel");
    ok(&o);
    let mut single = vec!["render", "cornell", "-q", "-o", "single.exr"];
    single.extend(PPM);
    ok(&photon(&single, &dir));
    ok(&photon(
        &["job", "merge", "j", "-o", "m.exr", "--require-all"],
        &dir,
    ));
    assert!(
        std::fs::read(dir.join("m.exr")).expect("merged")
            == std::fs::read(dir.join("single.exr")).expect("single")
    );
}

/// Wait until Slurm has none of `ids` queued or running (up to ten minutes).
fn wait_for_slurm(ids: &[&str]) {
    let start = std::time::Instant::now();
    loop {
        let o = Command::new("squeue")
            .args(["-h", "-o", "%i", "-j", &ids.join(",")])
            .output()
            .expect("squeue");
        if String::from_utf8_lossy(&o.stdout).trim().is_empty() {
            return;
        }
        assert!(
            start.elapsed().as_secs() < 600,
            "Slurm jobs {ids:?} did not finish"
        );
        std::thread::sleep(std::time::Duration::from_millis(500));
    }
}

/// On a real one-node Slurm cluster (`.ci/slurm-up`): 8 tasks as an array and a merge job
/// after it, in a job folder whose name holds spaces, quotes, `$`, a command substitution and
/// a newline followed by lines sbatch or a shell would obey; one task cancelled on purpose,
/// found by `job status`, rerun with the command it prints; the merged image equals a local
/// single render byte for byte, and nothing but the job ran.
#[test]
#[ignore = "needs a running Slurm cluster: .ci/slurm-up, then --ignored"]
fn slurm_array_jobs_merge_bit_for_bit_and_rerun_a_cancelled_task() {
    let dir = temp_dir("jobs-slurm");
    let name = "j 'a' \"b\" $HOME $(touch PWNED)\n#SBATCH --wrap=touch PWNED\ntouch PWNED";
    let job = dir.join(name);
    let render = [
        "--integrator",
        "ppm",
        "--passes",
        "16",
        "--photons-per-pass",
        "50000",
        "--width",
        "64",
        "--height",
        "64",
    ];
    let mut create = vec!["job", "create", "--tasks", "8", "-o", name, "cornell"];
    create.extend(render);
    ok(&photon(&create, &dir));
    let start = std::time::Instant::now();
    let o = photon(&["job", "submit", name, "--slurm", "--cpus", "1"], &dir);
    let text = ok(&o);
    let ids: Vec<String> = String::from_utf8_lossy(&o.stdout)
        .split_whitespace()
        .map(str::to_owned)
        .collect();
    assert_eq!(ids.len(), 2, "{text}");
    let (tasks, merge) = (&ids[0], &ids[1]);
    // Task 5 is cancelled before it runs (it waits for a CPU behind tasks 0 to 3).
    let cancelled = Command::new("scancel")
        .arg(format!("{tasks}_5"))
        .status()
        .expect("scancel");
    assert!(cancelled.success());
    wait_for_slurm(&[tasks, merge]);
    let first_wall = start.elapsed().as_secs_f64();
    let log = std::fs::read_to_string(job.join("slurm/merge.log")).expect("merge log");
    assert!(log.contains("merged 7 of 8 tasks"), "{log}");
    assert!(log.contains("missing tasks: 5"), "{log}");
    let status = ok(&photon(&["job", "status", name], &dir));
    // The last line, which holds the quoted folder name and so its newlines.
    let rerun = status
        .split("Slurm:")
        .nth(1)
        .expect("a Slurm rerun line")
        .trim()
        .to_owned();
    assert!(rerun.contains(" && sbatch --array=5 "), "{status}");
    let o = Command::new("sh")
        .args(["-c", &rerun.replacen("sbatch ", "sbatch --parsable ", 1)])
        .current_dir(&dir)
        .output()
        .expect("sbatch");
    let rerun_id = String::from_utf8_lossy(&o.stdout).trim().to_owned();
    assert!(o.status.success(), "{}", stderr(&o));
    wait_for_slurm(&[&rerun_id]);
    ok(&photon(
        &["job", "merge", name, "-o", "merged.exr", "--require-all"],
        &dir,
    ));
    let mut single = vec!["render", "cornell", "-q", "-o", "single.exr"];
    single.extend(render);
    ok(&photon(&single, &dir));
    let same = std::fs::read(dir.join("merged.exr")).expect("merged")
        == std::fs::read(dir.join("single.exr")).expect("single");
    let pwned: Vec<_> = [dir.join("PWNED"), job.join("PWNED")]
        .into_iter()
        .filter(|p| p.exists())
        .collect();
    let home_pwned = std::env::var_os("HOME").map(|h| Path::new(&h).join("PWNED"));
    eprintln!(
        "slurm: array job {tasks} (8 tasks, task 5 cancelled), merge job {merge}, rerun job {rerun_id}; first pass {first_wall:.1} s, total {:.1} s; merged == single: {same}; files the folder name tried to create: {pwned:?}",
        start.elapsed().as_secs_f64()
    );
    assert!(same, "the Slurm job's image differs from the single render");
    assert!(pwned.is_empty(), "the folder name ran a command");
    assert!(
        !home_pwned.is_some_and(|p| p.exists()),
        "the folder name ran a command"
    );
}
