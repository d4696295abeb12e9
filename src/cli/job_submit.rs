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
    let job_dir = std::path::absolute(&a.job).context("job folder")?;
    let photon = match &a.photon {
        Some(p) => p.clone(),
        None => std::env::current_exe().context("cannot find this executable")?,
    };
    if a.k8s {
        outln!("{}", kubernetes(a, &manifest, &job_dir)?);
        return Ok(());
    }
    let (task, merge) = slurm_scripts(a, &manifest, &job_dir, &photon);
    for (name, text) in [(TASK_SCRIPT, &task), (MERGE_SCRIPT, &merge)] {
        let path = job_dir.join(name);
        std::fs::create_dir_all(path.parent().expect("a folder"))?;
        photon::io::image::write_atomically(&path, |tmp| {
            std::fs::write(tmp, text).map_err(|source| photon::Error::Write {
                path: path.clone(),
                source,
            })
        })?;
    }
    let task_script = job_dir.join(TASK_SCRIPT);
    let merge_script = job_dir.join(MERGE_SCRIPT);
    if a.dry_run {
        outln!(
            "sbatch --parsable {}\nsbatch --parsable --dependency=afterany:TASKS {}",
            task_script.display(),
            merge_script.display()
        );
        return Ok(());
    }
    let tasks_id = sbatch(&[task_script.as_os_str().to_owned()])?;
    let merge_id = sbatch(&[
        format!("--dependency=afterany:{tasks_id}").into(),
        merge_script.as_os_str().to_owned(),
    ])?;
    eprintln!(
        "photon: submitted {} tasks as Slurm job {tasks_id}, and the merge as job {merge_id} (after them; it writes {} and lists failures in {})",
        manifest.tasks.len(),
        job_dir.join("merged.exr").display(),
        job_dir.join("slurm/merge.log").display()
    );
    outln!("{tasks_id} {merge_id}");
    Ok(())
}

/// `sbatch --parsable ARGS…`: the job id it prints.
fn sbatch(args: &[std::ffi::OsString]) -> Result<String> {
    let out = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
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

/// Quote `s` for a POSIX shell.
fn sh(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn slurm_scripts(
    a: &SubmitArgs,
    manifest: &Manifest,
    job_dir: &Path,
    photon: &Path,
) -> (String, String) {
    let name = job_dir
        .file_name()
        .map_or_else(|| "job".into(), |n| n.to_string_lossy().into_owned());
    let mut common = format!("#SBATCH --job-name=photon-{name}\n");
    if let Some(p) = &a.partition {
        common += &format!("#SBATCH --partition={p}\n");
    }
    if let Some(t) = &a.time {
        common += &format!("#SBATCH --time={t}\n");
    }
    let throttle = a.max_running.map_or_else(String::new, |m| format!("%{m}"));
    let (job, photon) = (
        sh(&job_dir.to_string_lossy()),
        sh(&photon.to_string_lossy()),
    );
    let logs = job_dir.join("slurm");
    let task = format!(
        "#!/bin/sh\n{common}#SBATCH --array=0-{}{throttle}\n#SBATCH --cpus-per-task={}\n#SBATCH --output={}/task-%a.log\n# Each array task renders one part; exit 75 asks for a retry, 2 will fail again.\nexec {photon} job run {job} --threads {}\n",
        manifest.tasks.len() - 1,
        a.cpus,
        logs.display(),
        a.cpus,
    );
    let merge = format!(
        "#!/bin/sh\n{common}#SBATCH --cpus-per-task=1\n#SBATCH --output={}/merge.log\n# Runs after every task (afterany): merges the parts present and reports the rest.\n{photon} job merge {job} -o {}\n{photon} job status {job}\n",
        logs.display(),
        sh(&job_dir.join("merged.exr").to_string_lossy()),
    );
    (task, merge)
}

/// An Indexed Job: `completions` tasks, each pod given its index in JOB_COMPLETION_INDEX,
/// the job folder on a shared volume.
fn kubernetes(a: &SubmitArgs, manifest: &Manifest, job_dir: &Path) -> Result<String> {
    let name = job_dir
        .file_name()
        .map_or_else(|| "job".into(), |n| n.to_string_lossy().into_owned())
        .to_ascii_lowercase()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect::<String>();
    let mount = PathBuf::from("/jobs").join(job_dir.file_name().unwrap_or_default());
    let tasks = manifest.tasks.len();
    let value = serde_json::json!({
        "apiVersion": "batch/v1",
        "kind": "Job",
        "metadata": { "name": format!("photon-{}", name.trim_matches('-')) },
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
