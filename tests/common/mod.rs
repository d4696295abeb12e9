//! Helpers shared by the integration tests.
#![allow(
    dead_code,
    reason = "the Embree build's `bvh` binary uses few of these helpers"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub mod media;

/// Run the `photon` binary with `args` in `dir`.
pub fn photon(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_photon"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run photon")
}

/// The run failed as bad input must: exit code 2, a message mentioning `needle`, no panic.
pub fn assert_usage_error(o: &Output, needle: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "exit code; stderr: {err}");
    assert!(
        err.contains(needle),
        "stderr should mention '{needle}': {err}"
    );
    assert!(!err.contains("panicked"), "must not panic: {err}");
}

/// A run's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The project's own data the tests compare with, committed under `tests/fixtures/shared/`:
/// the original project's image and scene (`seed/`) and the Cornell box's converged
/// reference (`scenes/cornell-box/reference.exr`).
pub fn shared_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/shared")
}

/// A fresh, empty directory for one test's files, under the system temp dir, its own even
/// when two tests give the same name. The first call in a test process also removes the
/// directories left by test processes that have ended.
pub fn temp_dir(name: &str) -> PathBuf {
    static SWEEP: std::sync::Once = std::sync::Once::new();
    static CALLS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    SWEEP.call_once(remove_dead_processes_dirs);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir =
        std::env::temp_dir().join(format!("photon-test-{}-{call}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

/// Remove `photon-test-PID-*` directories whose process is gone (where `/proc` shows which
/// are running; elsewhere nothing is removed).
fn remove_dead_processes_dirs() {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix("photon-test-"))
            .and_then(|rest| rest.split('-').next())
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// Upper-tail check of a chi-square statistic with `dof` degrees of freedom via the
/// Wilson–Hilferty normal approximation: returns the z-score.
pub fn chi2_z(stat: f64, dof: f64) -> f64 {
    let k = dof;
    ((stat / k).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt()
}

/// Chi-square statistic of observed counts against expected probabilities, pooling cells
/// whose expected count is below 5 (Cochran's rule). Returns (statistic, degrees of freedom).
pub fn chi2(observed: &[u64], expected_prob: &[f64], n: u64) -> (f64, f64) {
    assert_eq!(observed.len(), expected_prob.len());
    let total_p: f64 = expected_prob.iter().sum();
    assert!(
        (total_p - 1.0).abs() < 1e-6,
        "expected probabilities sum to {total_p}"
    );
    let mut stat = 0.0;
    let mut cells = 0usize;
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (&o, &p) in observed.iter().zip(expected_prob) {
        let e = p * n as f64;
        if e < 5.0 {
            pool_o += o as f64;
            pool_e += e;
            if p == 0.0 {
                assert_eq!(o, 0, "samples fell where the pdf is zero");
            }
            continue;
        }
        stat += (o as f64 - e).powi(2) / e;
        cells += 1;
    }
    if pool_e > 0.0 {
        stat += (pool_o - pool_e).powi(2) / pool_e;
        cells += 1;
    }
    (stat, (cells - 1) as f64)
}

/// A binary glTF (GLB) from its JSON and binary chunk.
pub fn glb(doc: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(doc).expect("json");
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// `f`'s result on a pool of one thread and on a pool of two: determinism tests compare them.
pub fn on_one_and_two_threads<T: Send>(f: impl Fn() -> T + Sync) -> [T; 2] {
    [1, 2].map(|t| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .expect("pool")
            .install(&f)
    })
}

/// χ² test of a direction sampler against its solid-angle density, as Mitsuba tests its
/// plugins: `n` draws of `sample` (which may fail, `None`) binned over a (cos θ, φ) grid of the
/// sphere, against `pdf` integrated over each cell by the midpoint rule on a finer grid; the
/// failed draws are one more cell, with the probability the pdf leaves over. Returns the
/// z-score of the statistic (Wilson–Hilferty); a correct sampler stays below ~4.
pub fn chi2_directions(
    n: u64,
    seed: u64,
    mut sample: impl FnMut(&mut photon::sampling::Rng) -> Option<photon::math::Vec3>,
    pdf: impl Fn(photon::math::Vec3) -> f64,
) -> f64 {
    use std::f64::consts::PI;
    const Z_BINS: usize = 20;
    const PHI_BINS: usize = 40;
    const SUB: usize = 10;
    let mut counts = vec![0u64; Z_BINS * PHI_BINS + 1];
    let mut rng = photon::sampling::Rng::keyed(seed, &[n]);
    for _ in 0..n {
        let Some(w) = sample(&mut rng) else {
            counts[Z_BINS * PHI_BINS] += 1;
            continue;
        };
        let z = ((f64::from(w.z).clamp(-1.0, 1.0) + 1.0) * 0.5 * Z_BINS as f64) as usize;
        let phi = f64::from(w.y).atan2(f64::from(w.x)).rem_euclid(2.0 * PI);
        let p = (phi / (2.0 * PI) * PHI_BINS as f64) as usize;
        counts[z.min(Z_BINS - 1) * PHI_BINS + p.min(PHI_BINS - 1)] += 1;
    }
    let dz = 2.0 / (Z_BINS * SUB) as f64;
    let dphi = 2.0 * PI / (PHI_BINS * SUB) as f64;
    let mut probs = vec![0f64; Z_BINS * PHI_BINS + 1];
    for (bin, prob) in probs.iter_mut().take(Z_BINS * PHI_BINS).enumerate() {
        let (zb, pb) = (bin / PHI_BINS, bin % PHI_BINS);
        for i in 0..SUB {
            for j in 0..SUB {
                let z = -1.0 + ((zb * SUB + i) as f64 + 0.5) * dz;
                let phi = ((pb * SUB + j) as f64 + 0.5) * dphi;
                let s = (1.0 - z * z).max(0.0).sqrt();
                let w = photon::math::Vec3::new(
                    (s * phi.cos()) as f32,
                    (s * phi.sin()) as f32,
                    z as f32,
                );
                *prob += pdf(w) * dz * dphi;
            }
        }
    }
    // The midpoint rule can miss a sliver of density at a cell's edge: no cell is impossible.
    probs.iter_mut().for_each(|p| *p = p.max(1e-12));
    let covered: f64 = probs.iter().take(Z_BINS * PHI_BINS).sum();
    let failed = counts[Z_BINS * PHI_BINS];
    if covered > 0.998 && failed * 1000 < n {
        // A sampler that (almost) never fails: what the pdf leaves over is the midpoint
        // rule's error, not a probability of failing. Test where the samples went.
        counts.pop();
        probs.pop();
        let kept: u64 = counts.iter().sum();
        probs.iter_mut().for_each(|p| *p /= covered);
        let (stat, dof) = chi2(&counts, &probs, kept);
        return chi2_z(stat, dof);
    }
    probs[Z_BINS * PHI_BINS] = (1.0 - covered).max(1e-12);
    // The midpoint rule's own error: renormalise what it integrated.
    let total: f64 = probs.iter().sum();
    probs.iter_mut().for_each(|p| *p /= total);
    let (stat, dof) = chi2(&counts, &probs, n);
    let z = chi2_z(stat, dof);
    if z > 4.0 {
        // Say where: the cells that differ most.
        let mut worst: Vec<(f64, usize)> = counts
            .iter()
            .zip(&probs)
            .enumerate()
            .map(|(i, (&o, &p))| {
                let e = p * n as f64;
                ((o as f64 - e).powi(2) / e.max(1.0), i)
            })
            .collect();
        worst.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(c, i) in worst.iter().take(5) {
            eprintln!(
                "cell {i} (cos θ bin {}, φ bin {}): observed {}, expected {:.1} (χ² {c:.1})",
                i / PHI_BINS,
                i % PHI_BINS,
                counts[i],
                probs[i] * n as f64
            );
        }
    }
    z
}

/// An octahedron's vertices (±x, ±y, ±z on the unit axes, in that order) and its eight faces,
/// wound outward.
pub const OCTAHEDRON_VERTICES: [[f32; 3]; 6] = [
    [1.0, 0.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, -1.0],
];
pub const OCTAHEDRON_FACES: [[u32; 3]; 8] = [
    [0, 2, 4],
    [2, 1, 4],
    [1, 3, 4],
    [3, 0, 4],
    [2, 0, 5],
    [1, 2, 5],
    [3, 1, 5],
    [0, 3, 5],
];
