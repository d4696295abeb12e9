//! How ray casting scales with the triangle count: scene build (BVH included), resident memory
//! and rays/s for the ray benchmark's bumpy sphere at 10k, 100k, 1M and 10M triangles. Run
//! with `cargo bench --bench scale [-- COUNT...]` (Linux: memory from /proc/self/status).

/// Resident memory in MB (0 where /proc is missing).
fn resident_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(0.0, |kb| kb / 1024.0)
}

fn main() {
    let counts: Vec<u64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let counts = if counts.is_empty() {
        vec![10_000, 100_000, 1_000_000, 10_000_000]
    } else {
        counts
    };
    println!(
        "| triangles | build (s) | memory (MB) | bytes/triangle | camera rays/s (1 thread) | bounce rays/s (1 thread) | shadow rays/s (1 thread) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    for n in counts {
        // 2·n_phi·(n_theta − 1) ≈ n with n_phi ≈ 1.25 n_theta, as the 102k mesh (256 × 200).
        let n_theta = ((n as f64 / 2.5).sqrt() as u32).max(4);
        let n_phi = (n as f64 / 2.0 / f64::from(n_theta - 1)) as u32;
        let before = resident_mb();
        let r = photon::bench::micro::rays_on(n_theta, n_phi, photon::accel::RayEngine::Best)
            .expect("the scene builds");
        let memory = resident_mb() - before;
        println!(
            "| {} | {:.2} | {:.0} | {:.0} | {:.2} M | {:.2} M | {:.2} M |",
            r.triangles,
            r.build_ms / 1e3,
            memory,
            memory * 1024.0 * 1024.0 / r.triangles as f64,
            r.camera_one_thread,
            r.bounce_one_thread,
            r.shadow_one_thread
        );
    }
}
