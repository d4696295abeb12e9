//! Photon benchmark: tracing (1 M photons emitted, maps built) on the built-in scenes, and
//! radius and 50-nearest queries per second on one core in the setting the crates were chosen
//! in (about 1 M photons on box walls, 500k queries of ~50 photons; a hand-written grid
//! reached 1.28–1.36 M/s there, `kiddo`'s immutable kd-tree 0.56–0.61 M/s).
//! `photon::bench::micro`; also part of `photon bench`. Run with `cargo bench --bench
//! photons`. The original project traced 13,000 photons/s and took 180–260 µs per query.

fn main() {
    for name in ["cornell", "seed"] {
        let p = photon::bench::micro::photons(name).expect("built-in scene");
        println!(
            "{name}: {:.2} M photons emitted/s on {} threads, trace and kd-tree builds ({} stored of 1 M)",
            p.emitted_per_s, p.threads, p.stored
        );
    }
    let q = photon::bench::micro::queries().expect("built-in scene");
    println!(
        "queries, 1 thread: {} photons, {} queries, r = {:.4} ({:.0} photons/query)",
        q.photons, q.queries, q.radius, q.photons_per_query
    );
    println!(
        "  radius, random order: grid {:.2} M/s, kd-tree {:.2} M/s; 50-nearest (kd-tree) {:.2} M/s",
        q.grid_radius, q.kd_radius, q.kd_nearest_50
    );
    println!(
        "  radius, spatial order: grid {:.2} M/s, kd-tree {:.2} M/s",
        q.grid_radius_coherent, q.kd_radius_coherent
    );
    println!(
        "  builds: grid {:.0} ms, kd-tree {:.0} ms",
        q.grid_build_ms, q.kd_build_ms
    );
}
