//! `photon job submit`: the job's tasks as a Slurm array with a merge job after it, or as a
//! Kubernetes Indexed Job. Both run the same worker command, `photon job run JOB`, which
//! finds its task in the scheduler's environment.

use super::job::SubmitArgs;
use anyhow::{Context, Result, bail};
use photon::job::Manifest;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The Slurm scripts, relative to the job folder.
pub const TASK_SCRIPT: &str = "slurm/task.sbatch";
pub const MERGE_SCRIPT: &str = "slurm/merge.sbatch";

pub fn submit(a: &SubmitArgs) -> Result<()> {
    let manifest = Manifest::load(&a.job)?;
    let job_dir = std::fs::canonicalize(&a.job)
        .with_context(|| format!("cannot find '{}'", a.job.display()))?;
    let photon = match &a.photon {
        Some(p) => p.clone(),
        None => std::env::current_exe().context("cannot find this executable")?,
    };
    if a.k8s {
        outln!("{}", kubernetes(a, &manifest, &job_dir)?);
        return Ok(());
    }
    let (task, merge) = slurm_scripts(a, &manifest, &job_dir, &photon)?;
    for (name, text) in [(TASK_SCRIPT, &task), (MERGE_SCRIPT, &merge)] {
        let path = job_dir.join(name);
        std::fs::create_dir_all(path.parent().expect("a folder"))?;
        photon::io::atomic::write_file(&path, text)?;
    }
    if a.dry_run {
        let cd = format!("cd {}", sh_quote(&job_dir.to_string_lossy()));
        outln!(
            "{cd} && sbatch --parsable {TASK_SCRIPT}\n{cd} && sbatch --parsable --dependency=afterany:TASKS {MERGE_SCRIPT}"
        );
        return Ok(());
    }
    let tasks_id = sbatch(&job_dir, &[TASK_SCRIPT.to_owned()])?;
    let merge_id = sbatch(
        &job_dir,
        &[
            format!("--dependency=afterany:{tasks_id}"),
            MERGE_SCRIPT.to_owned(),
        ],
    )?;
    eprintln!(
        "photon: submitted {} tasks as Slurm job {tasks_id}, and the merge as job {merge_id} (after them; it writes {} and lists failures in {})",
        manifest.tasks.len(),
        job_dir.join("merged.exr").display(),
        job_dir.join("slurm/merge.log").display()
    );
    outln!("{tasks_id} {merge_id}");
    Ok(())
}

/// `sbatch --parsable ARGS…` started in the job folder, which becomes the jobs' working
/// folder: the scripts name everything relative to it. Returns the job id it prints.
fn sbatch(job_dir: &Path, args: &[String]) -> Result<String> {
    let out = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .current_dir(job_dir)
        .output()
        .context("cannot run sbatch: is Slurm installed here?")?;
    if !out.status.success() {
        bail!(
            "sbatch failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    // --parsable prints "id" or "id;cluster".
    Ok(text.trim().split(';').next().unwrap_or("").to_owned())
}

/// `s` quoted for a POSIX shell: in single quotes, each `'` written `'\''`.
pub fn sh_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// `--time` as Slurm reads it: minutes, `M:S`, `H:M:S`, `D-H`, `D-H:M`, `D-H:M:S`, or
/// UNLIMITED/INFINITE.
fn check_time(t: &str) -> Result<()> {
    let digits_and_separators = t.len() <= 32
        && t.starts_with(|c: char| c.is_ascii_digit())
        && t.chars()
            .all(|c| c.is_ascii_digit() || c == ':' || c == '-');
    if !(digits_and_separators
        || ["UNLIMITED", "INFINITE"].contains(&t.to_ascii_uppercase().as_str()))
    {
        bail!(
            "--time '{}': expected a Slurm time limit such as 90 (minutes), 1:30:00 or 2-00:00:00",
            t.escape_debug()
        );
    }
    Ok(())
}

/// `--partition`: one or more partition names, comma-separated.
fn check_partition(p: &str) -> Result<()> {
    if p.is_empty()
        || p.len() > 128
        || !p
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-.,".contains(c))
    {
        bail!(
            "--partition '{}': expected a partition name (letters, digits, '_', '-', '.'; ',' between several)",
            p.escape_debug()
        );
    }
    Ok(())
}

/// The Slurm job name: `photon-` and the job folder's name, with anything but ASCII letters,
/// digits, `_`, `-` and `.` replaced by `_`.
fn slurm_job_name(job_dir: &Path) -> String {
    let folder = job_dir
        .file_name()
        .map_or_else(|| "job".into(), |n| n.to_string_lossy().into_owned());
    let name: String = folder
        .chars()
        .take(64)
        .map(|c| {
            if c.is_ascii_alphanumeric() || "_-.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("photon-{name}")
}

/// The array script and the merge script. They name no path but the photon executable's
/// (quoted in the shell body): sbatch starts them in the job folder, and `#SBATCH` lines,
/// which sbatch reads itself without any quoting, hold only checked tokens.
fn slurm_scripts(
    a: &SubmitArgs,
    manifest: &Manifest,
    job_dir: &Path,
    photon: &Path,
) -> Result<(String, String)> {
    let mut common = format!("#SBATCH --job-name={}\n", slurm_job_name(job_dir));
    if let Some(p) = &a.partition {
        check_partition(p)?;
        common += &format!("#SBATCH --partition={p}\n");
    }
    if let Some(t) = &a.time {
        check_time(t)?;
        common += &format!("#SBATCH --time={t}\n");
    }
    let throttle = a.max_running.map_or_else(String::new, |m| format!("%{m}"));
    let photon = sh_quote(&photon.to_string_lossy());
    // Slurm sets SLURM_SUBMIT_DIR to the folder sbatch ran in: the job folder.
    let job = r#""${SLURM_SUBMIT_DIR:-.}""#;
    let task = format!(
        "#!/bin/sh\n{common}#SBATCH --array=0-{}{throttle}\n#SBATCH --cpus-per-task={}\n#SBATCH --output=slurm/task-%a.log\n# Submit from the job folder. Each array task renders one part; exit 75 asks for a retry, 2 will fail again.\nexec {photon} job run {job} --threads {}\n",
        manifest.tasks.len() - 1,
        a.cpus,
        a.cpus,
    );
    let merge = format!(
        "#!/bin/sh\n{common}#SBATCH --cpus-per-task=1\n#SBATCH --output=slurm/merge.log\n# Submit from the job folder. Runs after every task (afterany): merges the parts present and reports the rest.\n{photon} job merge {job} -o {job}/merged.exr\n{photon} job status {job}\n",
    );
    Ok((task, merge))
}

/// A Kubernetes object name (an RFC 1123 label: at most 63 lower-case letters, digits and
/// `-`, starting and ending with a letter or digit) for the job folder `folder`: `photon-`
/// and the folder's name, shortened with a hash of the whole name when it is too long.
fn kubernetes_name(folder: &str) -> String {
    const MAX: usize = 63;
    let mut name = String::from("photon-");
    for c in folder.to_ascii_lowercase().chars() {
        let c = if c.is_ascii_alphanumeric() { c } else { '-' };
        if !(c == '-' && name.ends_with('-')) {
            name.push(c);
        }
    }
    let mut name = name.trim_end_matches('-').to_owned();
    if name == "photon" {
        name += "-job";
    }
    if name.len() > MAX {
        let hash = &photon::job::fnv64_hex(folder.as_bytes())[..8];
        name.truncate(MAX - hash.len() - 1);
        name = format!("{}-{hash}", name.trim_end_matches('-'));
    }
    name
}

/// An Indexed Job: `completions` tasks, each pod given its index in JOB_COMPLETION_INDEX,
/// the job folder on a shared volume.
fn kubernetes(a: &SubmitArgs, manifest: &Manifest, job_dir: &Path) -> Result<String> {
    let folder = job_dir
        .file_name()
        .map_or_else(|| "job".into(), |n| n.to_string_lossy().into_owned());
    let mount = PathBuf::from("/jobs").join(job_dir.file_name().unwrap_or_default());
    let tasks = manifest.tasks.len();
    let value = serde_json::json!({
        "apiVersion": "batch/v1",
        "kind": "Job",
        "metadata": { "name": kubernetes_name(&folder) },
        "spec": {
            "completionMode": "Indexed",
            "completions": tasks,
            "parallelism": a.max_running.map_or(tasks, |m| m as usize),
            // Exit 75 is worth a retry; exit 2 is not (Kubernetes ≥ 1.26 pod failure policy).
            "backoffLimit": 3 * tasks,
            "podFailurePolicy": {
                "rules": [{
                    "action": "FailJob",
                    "onExitCodes": { "containerName": "photon", "operator": "In", "values": [2] }
                }]
            },
            "template": {
                "spec": {
                    "restartPolicy": "Never",
                    "containers": [{
                        "name": "photon",
                        "image": a.image,
                        "command": ["photon", "job", "run", mount.to_string_lossy(), "--threads", a.cpus.to_string()],
                        "resources": { "requests": { "cpu": a.cpus.to_string() } },
                        "volumeMounts": [{ "name": "jobs", "mountPath": "/jobs" }]
                    }],
                    "volumes": [{
                        "name": "jobs",
                        "persistentVolumeClaim": { "claimName": a.volume_claim }
                    }]
                }
            }
        }
    });
    Ok(serde_json::to_string_pretty(&value)?)
}
