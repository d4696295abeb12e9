//! Ray-casting benchmark: camera and bounce rays per second on a ~100k-triangle mesh inside a
//! closed box, on one thread and on all threads. Run with `cargo bench --bench rays`.
//!
//! Camera rays are coherent (a pinhole grid); bounce rays start at the camera rays' hit points
//! in cosine-distributed directions, as a path tracer's are. Compare with
//! ../shared/design/crates.md (obvhs CwBvh: 5.1 M camera, 1.7 M bounce rays/s on one core).

use glam::Affine3A;
use photon::camera::{Camera, CameraDesc};
use photon::material::{Lambertian, Material};
use photon::math::{Frame, Ray, Rgb, Vec2, Vec3, offset_origin};
use photon::sampling::{Rng, cosine_hemisphere};
use photon::scene::{Scene, SceneBuilder};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::time::Instant;

/// A bumpy sphere of `2·n_phi·(n_theta−1)` triangles.
fn bumpy_sphere(n_theta: u32, n_phi: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = Vec::new();
    for i in 0..=n_theta {
        let theta = PI * i as f32 / n_theta as f32;
        for j in 0..n_phi {
            let phi = 2.0 * PI * j as f32 / n_phi as f32;
            let r = 1.0
                + 0.08 * (7.0 * theta).sin() * (9.0 * phi).cos()
                + 0.03 * (23.0 * phi + 5.0 * theta).sin();
            p.push(
                r * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                ),
            );
        }
    }
    let mut t = Vec::new();
    let idx = |i: u32, j: u32| i * n_phi + (j % n_phi);
    for i in 0..n_theta {
        for j in 0..n_phi {
            let (a, b, c, d) = (idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j));
            if i > 0 {
                t.push([a, b, c]);
            }
            if i + 1 < n_theta {
                t.push([a, c, d]);
            }
        }
    }
    (p, t)
}

fn scene() -> (Scene, usize) {
    let mut b = SceneBuilder::new("bench");
    b.camera(
        CameraDesc {
            position: Vec3::new(0.0, 0.3, -3.5),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
        },
        1024,
        1024,
    );
    let m = b.material(Material::Lambertian(Lambertian {
        albedo: Rgb::splat(0.5),
    }));
    let (p, t) = bumpy_sphere(256, 200);
    let tris = t.len() + 12;
    b.mesh(&p, &t, Affine3A::IDENTITY, m, None).expect("mesh");
    // A closed box around it so every bounce ray hits something.
    let s = 4.0;
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * s;
    for q in [
        [
            v(-1., -1., -1.),
            v(1., -1., -1.),
            v(1., -1., 1.),
            v(-1., -1., 1.),
        ],
        [
            v(-1., 1., -1.),
            v(-1., 1., 1.),
            v(1., 1., 1.),
            v(1., 1., -1.),
        ],
        [
            v(-1., -1., 1.),
            v(1., -1., 1.),
            v(1., 1., 1.),
            v(-1., 1., 1.),
        ],
        [
            v(-1., -1., -1.),
            v(-1., 1., -1.),
            v(1., 1., -1.),
            v(1., -1., -1.),
        ],
        [
            v(-1., -1., -1.),
            v(-1., -1., 1.),
            v(-1., 1., 1.),
            v(-1., 1., -1.),
        ],
        [
            v(1., -1., -1.),
            v(1., 1., -1.),
            v(1., 1., 1.),
            v(1., -1., 1.),
        ],
    ] {
        b.quad(q, m, None);
    }
    (b.build().expect("scene"), tris)
}

fn rate(n: usize, secs: f64) -> f64 {
    n as f64 / secs / 1e6
}

fn main() {
    let t0 = Instant::now();
    let (scene, tris) = scene();
    let build = t0.elapsed().as_secs_f64();
    println!(
        "mesh: {tris} triangles; scene + BVH build {:.0} ms",
        build * 1e3
    );
    let cam = Camera::new(&scene.camera, 1024, 1024).expect("camera");
    let camera_rays: Vec<Ray> = (0..1024u32 * 1024)
        .map(|i| cam.ray(Vec2::new((i % 1024) as f32 + 0.5, (i / 1024) as f32 + 0.5)))
        .collect();
    let mut rng = Rng::keyed(1, &[]);
    let bounce_rays: Vec<Ray> = camera_rays
        .iter()
        .filter_map(|r| scene.intersect(r, f32::INFINITY))
        .map(|h| {
            let n = if h.ng.dot(Vec3::new(0.0, 0.3, -3.5) - h.p) < 0.0 {
                -h.ng
            } else {
                h.ng
            };
            let d = Frame::from_normal(n).to_world(cosine_hemisphere(rng.next_2d()));
            Ray::new(offset_origin(h.p, h.ng, d), d)
        })
        .collect();
    for (name, rays) in [("camera", &camera_rays), ("bounce", &bounce_rays)] {
        for threads in [1, rayon::current_num_threads()] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            let mut best = f64::INFINITY;
            let mut hits = 0;
            for _ in 0..3 {
                let t = Instant::now();
                hits = pool.install(|| {
                    rays.par_chunks(4096)
                        .map(|c| {
                            c.iter()
                                .filter(|r| scene.intersect(r, f32::INFINITY).is_some())
                                .count()
                        })
                        .sum::<usize>()
                });
                best = best.min(t.elapsed().as_secs_f64());
            }
            println!(
                "{name:>6} rays, {threads} thread(s): {:.2} M rays/s closest hit ({} rays, {hits} hits)",
                rate(rays.len(), best),
                rays.len()
            );
        }
    }
    let t = Instant::now();
    let occluded = bounce_rays
        .iter()
        .filter(|r| scene.occluded(r.origin, r.dir, 1.0))
        .count();
    println!(
        "shadow rays (any hit, length 1), 1 thread: {:.2} M rays/s ({occluded} occluded)",
        rate(bounce_rays.len(), t.elapsed().as_secs_f64())
    );
}
