//! Ray-casting benchmark: camera, bounce and shadow rays per second on a 102k-triangle mesh
//! inside a closed box, on one thread and on all threads (`photon::bench::micro::rays`; also
//! part of `photon bench`). Run with `cargo bench --bench rays`. For scale: Embree 3 cast
//! 10 M camera and 4.0 M bounce rays/s on one core of a 2-core laptop-class machine, on a
//! 115k-triangle mesh.

//! Every engine compiled in is measured: our BVH, and Embree with `--features embree`.

use photon::accel::RayEngine;

fn main() {
    for engine in RayEngine::compiled() {
        let r = photon::bench::micro::rays(engine).expect("the benchmark scene builds");
        println!(
            "{}: mesh of {} triangles; scene + acceleration build {:.0} ms",
            r.engine, r.triangles, r.build_ms
        );
        println!(
            "  1 thread:  camera {:.2} M rays/s, bounce {:.2} M rays/s, shadow (any hit) {:.2} M rays/s",
            r.camera_one_thread, r.bounce_one_thread, r.shadow_one_thread
        );
        println!(
            "  {} threads: camera {:.2} M rays/s, bounce {:.2} M rays/s",
            r.threads, r.camera_all_threads, r.bounce_all_threads
        );
    }
}
