//! Photon benchmark: tracing (emitted and stored photons/s), kd-tree build, and k-nearest and
//! radius queries per second on the built-in scenes. Run with `cargo bench --bench photons`.
//! Compare with the original project (../shared/seed/SEED-NOTES.md): 13,000 photons/s,
//! ~1 M photons/s kd-tree build, 180–260 µs per radius query, 137 bytes per photon.

use photon::description::builtin;
use photon::photon::{PhotonConfig, trace_photons};
use photon::sampling::Rng;
use rayon::prelude::*;
use std::time::Instant;

fn main() {
    for name in ["cornell", "seed"] {
        let scene = builtin::load(name).expect("built-in");
        let config = PhotonConfig {
            photons: 1_000_000,
            ..PhotonConfig::default()
        };
        let t = Instant::now();
        let maps = trace_photons(&scene, &config, &|_, _| {}).expect("traces");
        let secs = t.elapsed().as_secs_f64();
        let stored = maps.caustic.len() + maps.global.len();
        println!(
            "{name}: traced 1M photons in {secs:.3} s on {} threads (trace + build): {:.2} M emitted/s, {:.2} M stored/s ({stored} stored)",
            rayon::current_num_threads(),
            1.0 / secs,
            stored as f64 / secs / 1e6
        );
        let photons = maps.global.photons().to_vec();
        let t = Instant::now();
        let map = photon::photon::PhotonMap::build(photon::photon::MapKind::Global, photons, 1.0);
        println!(
            "{name}: kd-tree build of {} photons: {:.1} ms",
            map.len(),
            t.elapsed().as_secs_f64() * 1e3
        );
        // Queries at stored photon positions (where renders ask), radius giving ~50 photons.
        let mut rng = Rng::keyed(1, &[]);
        let queries: Vec<_> = (0..200_000)
            .map(|_| map.photons()[(rng.next_u32() as usize) % map.len()].position())
            .collect();
        let extent = map.bounds().extent().max_element();
        let mut r = extent * 0.01;
        for _ in 0..20 {
            let mean = queries[..2000]
                .iter()
                .map(|&q| map.within(q, r).len())
                .sum::<usize>() as f32
                / 2000.0;
            r *= (50.0 / mean.max(1.0)).sqrt().clamp(0.5, 2.0);
        }
        // Coherent queries (in tree order, as neighbouring pixels ask) against random ones.
        let coherent: Vec<_> = map
            .photons()
            .iter()
            .step_by(map.len() / queries.len())
            .map(|p| p.position())
            .collect();
        let t = Instant::now();
        let n: usize = coherent.iter().map(|&q| map.within(q, r).len()).sum();
        println!(
            "{name}: 1 thread, coherent queries: {:.2} M radius queries/s ({:.0} photons/query)",
            coherent.len() as f64 / t.elapsed().as_secs_f64() / 1e6,
            n as f64 / coherent.len() as f64
        );
        for threads in [1, rayon::current_num_threads()] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            let t = Instant::now();
            let found: usize = pool.install(|| {
                queries
                    .par_iter()
                    .map(|&q| {
                        let mut n = 0;
                        map.for_each_within(q, r, &mut |_, _| n += 1);
                        n
                    })
                    .sum()
            });
            let radius_rate = queries.len() as f64 / t.elapsed().as_secs_f64() / 1e6;
            let t = Instant::now();
            let knn: usize = pool.install(|| {
                queries
                    .par_iter()
                    .map(|&q| map.nearest(q, 50, 2.0 * r).len())
                    .sum()
            });
            let knn_rate = queries.len() as f64 / t.elapsed().as_secs_f64() / 1e6;
            println!(
                "{name}: {threads} thread(s): radius r = {r:.4} ({:.0} photons/query): {radius_rate:.2} M queries/s; 50-nearest: {knn_rate:.2} M queries/s ({:.0} found/query)",
                found as f64 / queries.len() as f64,
                knn as f64 / queries.len() as f64
            );
        }
    }
}
