//! Micro-benchmarks: rays/s on a 102k-triangle mesh, photons/s on the built-in scenes, and
//! photon queries/s in the setting the crates were chosen in (1 M photons on the walls of a
//! box, 500k queries of about 50 photons, one core), so figures compare with those
//! measurements (see `benches/photons.rs`).

use crate::accel::RayEngine;
use crate::camera::{Camera, CameraDesc};
use crate::description::builtin;
use crate::error::Result;
use crate::material::{Lambertian, Material};
use crate::math::{Frame, Ray, Rgb, Vec2, Vec3};
use crate::photon::grid::{PhotonGrid, QueryScratch};
use crate::photon::{MapKind, PhotonConfig, PhotonMap, trace_photons};
use crate::sampling::{Rng, cosine_hemisphere};
use crate::scene::{Scene, SceneBuilder};
use glam::Affine3A;
use rayon::prelude::*;
use serde::Serialize;
use std::f32::consts::PI;
use std::time::Instant;

/// Ray casting on the benchmark mesh (M rays/s).
#[derive(Clone, Debug, Serialize)]
pub struct RayRates {
    /// The ray engine measured ([`RayEngine::name`]).
    pub engine: String,
    pub triangles: usize,
    /// Scene build including the BVH, milliseconds.
    pub build_ms: f64,
    pub camera_one_thread: f64,
    pub bounce_one_thread: f64,
    pub shadow_one_thread: f64,
    pub camera_all_threads: f64,
    pub bounce_all_threads: f64,
    pub threads: usize,
}

/// Photon tracing on a built-in scene: 1 M photons emitted, both maps built.
#[derive(Clone, Debug, Serialize)]
pub struct PhotonRates {
    pub scene: String,
    /// M photons emitted per second (trace and kd-tree builds), all threads.
    pub emitted_per_s: f64,
    pub stored: usize,
    pub threads: usize,
}

/// Photon queries, one core (M queries/s).
#[derive(Clone, Debug, Serialize)]
pub struct QueryRates {
    pub photons: usize,
    pub queries: usize,
    pub radius: f32,
    pub photons_per_query: f64,
    pub kd_build_ms: f64,
    pub grid_build_ms: f64,
    /// Queries at random photons.
    pub kd_radius: f64,
    pub grid_radius: f64,
    /// Queries in the photons' spatial order (as neighbouring pixels ask).
    pub kd_radius_coherent: f64,
    pub grid_radius_coherent: f64,
    pub kd_nearest_50: f64,
}

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
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            p.push(r * d);
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

const CAMERA_POSITION: Vec3 = Vec3::new(0.0, 0.3, -3.5);

/// The ray benchmark's scene: a bumpy sphere of 102,000 triangles in a closed box (so every
/// bounce ray hits something), and the triangle count.
pub fn ray_scene(engine: RayEngine) -> Result<(Scene, usize)> {
    ray_scene_of(256, 200, engine)
}

/// [`ray_scene`] with a sphere of `2·n_phi·(n_theta−1)` triangles.
pub fn ray_scene_of(n_theta: u32, n_phi: u32, engine: RayEngine) -> Result<(Scene, usize)> {
    let mut b = SceneBuilder::new("bench");
    b.ray_engine(engine);
    let camera = CameraDesc {
        position: CAMERA_POSITION,
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 45.0,
    };
    b.camera(camera, 1024, 1024);
    let m = b.material(Material::Lambertian(Lambertian {
        albedo: Rgb::splat(0.5),
    }));
    let (p, t) = bumpy_sphere(n_theta, n_phi);
    let triangles = t.len() + 12;
    b.mesh(&p, &t, Affine3A::IDENTITY, m, None)?;
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * 4.0;
    // Each face of the cube [-4, 4]³: a corner and its two edges.
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let mut corner = [0.0f32; 3];
            corner[axis] = side;
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let at = |su: f32, sw: f32| {
                let mut c = corner;
                c[u] = su;
                c[w] = sw;
                v(c[0], c[1], c[2])
            };
            b.quad(
                [at(-1., -1.), at(1., -1.), at(1., 1.), at(-1., 1.)],
                m,
                None,
            );
        }
    }
    Ok((b.build()?, triangles))
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap_or_else(|_| {
            rayon::ThreadPoolBuilder::new()
                .build()
                .expect("a thread pool")
        })
}

/// Best of three timings of `f`, in seconds.
fn best_of_three(mut f: impl FnMut()) -> f64 {
    (0..3)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Camera rays (a pinhole grid, coherent), bounce rays (from the camera rays' hits in
/// cosine-distributed directions, as a path tracer's) and shadow rays (any hit, length 1).
pub fn rays(engine: RayEngine) -> Result<RayRates> {
    rays_on(256, 200, engine)
}

/// [`rays`] on a sphere of `2·n_phi·(n_theta−1)` triangles.
pub fn rays_on(n_theta: u32, n_phi: u32, engine: RayEngine) -> Result<RayRates> {
    let start = Instant::now();
    let (scene, triangles) = ray_scene_of(n_theta, n_phi, engine)?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let camera = Camera::new(&scene.camera, 1024, 1024).expect("the bench camera is valid");
    let camera_rays: Vec<Ray> = (0..1024u32 * 1024)
        .map(|i| camera.ray(Vec2::new((i % 1024) as f32 + 0.5, (i / 1024) as f32 + 0.5)))
        .collect();
    let mut rng = Rng::keyed(1, &[]);
    let bounce_rays: Vec<Ray> = camera_rays
        .iter()
        .filter_map(|r| scene.intersect(r, f32::INFINITY))
        .map(|h| {
            let facing = h.ng.dot(CAMERA_POSITION - h.p) >= 0.0;
            let n = if facing { h.ng } else { -h.ng };
            let d = Frame::from_normal(n).to_world(cosine_hemisphere(rng.next_2d()));
            Ray::new(h.offset_origin(d), d)
        })
        .collect();
    let closest = |rays: &[Ray], threads: usize| {
        let pool = pool(threads);
        let secs = best_of_three(|| {
            let hits: usize = pool.install(|| {
                rays.par_chunks(4096)
                    .map(|c| {
                        c.iter()
                            .filter(|r| scene.intersect(r, f32::INFINITY).is_some())
                            .count()
                    })
                    .sum()
            });
            std::hint::black_box(hits);
        });
        rays.len() as f64 / secs / 1e6
    };
    let shadow_secs = best_of_three(|| {
        let n = bounce_rays
            .iter()
            .filter(|r| scene.occluded(r.origin, r.dir, 1.0))
            .count();
        std::hint::black_box(n);
    });
    let threads = rayon::current_num_threads();
    Ok(RayRates {
        engine: scene.ray_engine().name().to_string(),
        triangles,
        build_ms,
        camera_one_thread: closest(&camera_rays, 1),
        bounce_one_thread: closest(&bounce_rays, 1),
        shadow_one_thread: bounce_rays.len() as f64 / shadow_secs / 1e6,
        camera_all_threads: closest(&camera_rays, threads),
        bounce_all_threads: closest(&bounce_rays, threads),
        threads,
    })
}

/// 1 M photons traced on the built-in scene `name`, both maps built, on every thread.
pub fn photons(name: &str) -> Result<PhotonRates> {
    let scene = builtin::load(name)?;
    let config = PhotonConfig {
        photons: 1_000_000,
        ..PhotonConfig::default()
    };
    let t = Instant::now();
    let maps = trace_photons(&scene, &config, &|_, _| {})?;
    let secs = t.elapsed().as_secs_f64();
    Ok(PhotonRates {
        scene: name.into(),
        emitted_per_s: 1.0 / secs,
        stored: maps.caustic.len() + maps.global.len(),
        threads: rayon::current_num_threads(),
    })
}

/// Radius and 50-nearest queries on one core: the Cornell box's global photons (about 1 M),
/// 500k queries at photon positions (where renders ask), radius set for about 50 photons.
pub fn queries() -> Result<QueryRates> {
    let scene = builtin::load("cornell")?;
    let config = PhotonConfig {
        photons: 1_300_000,
        ..PhotonConfig::default()
    };
    let maps = trace_photons(&scene, &config, &|_, _| {})?;
    let photons = maps.global.photons().to_vec();
    let pool = pool(1);
    let t = Instant::now();
    let map = pool.install(|| PhotonMap::build(MapKind::Global, photons, 1.0));
    let kd_build_ms = t.elapsed().as_secs_f64() * 1e3;
    let mut rng = Rng::keyed(1, &[]);
    let queries: Vec<Vec3> = (0..500_000)
        .map(|_| map.photons()[(rng.next_u32() as usize) % map.len()].position())
        .collect();
    let extent = map.bounds().extent().max_element();
    let mut r = extent * 0.01;
    for _ in 0..20 {
        let sample = &queries[..2000];
        let found: usize = sample.iter().map(|&q| map.within(q, r).len()).sum();
        let mean = found as f32 / sample.len() as f32;
        r *= (50.0 / mean.max(1.0)).sqrt().clamp(0.5, 2.0);
    }
    let t = Instant::now();
    let grid = PhotonGrid::build(map.photons().to_vec(), 2.0 * r);
    let grid_build_ms = t.elapsed().as_secs_f64() * 1e3;
    let rate = |secs: f64| queries.len() as f64 / secs / 1e6;
    // Radius queries/s of the kd-tree and the grid over `set`, and the photons found (the
    // two must agree; using the count also keeps the loops from being optimised away).
    let radius_rates = |set: &[Vec3]| -> Result<(f64, f64, usize)> {
        let mut found = 0usize;
        let kd = best_of_three(|| {
            found = 0;
            for &q in set {
                map.for_each_within(q, r, &mut |_, _| found += 1);
            }
            std::hint::black_box(found);
        });
        let mut scratch = QueryScratch::default();
        let mut grid_found = 0usize;
        let on_grid = best_of_three(|| {
            grid_found = 0;
            for &q in set {
                grid.for_each_within(q, r, &mut scratch, &mut |_, _| grid_found += 1);
            }
            std::hint::black_box(grid_found);
        });
        if grid_found != found {
            return Err(crate::error::Error::InvalidSetting(format!(
                "the grid found {grid_found} photons where the kd-tree found {found}"
            )));
        }
        let per_s = |secs: f64| set.len() as f64 / secs / 1e6;
        Ok((per_s(kd), per_s(on_grid), found))
    };
    let (kd_radius, grid_radius, found) = radius_rates(&queries)?;
    // In the photons' own (kd-tree) order, as neighbouring pixels ask.
    let step = (map.len() / queries.len()).max(1);
    let coherent: Vec<Vec3> = map
        .photons()
        .iter()
        .step_by(step)
        .map(|p| p.position())
        .collect();
    let (kd_radius_coherent, grid_radius_coherent, _) = radius_rates(&coherent)?;
    let kd_nearest_50 = rate(best_of_three(|| {
        let n: usize = queries
            .iter()
            .map(|&q| map.nearest(q, 50, 2.0 * r).len())
            .sum();
        std::hint::black_box(n);
    }));
    Ok(QueryRates {
        photons: map.len(),
        queries: queries.len(),
        radius: r,
        photons_per_query: found as f64 / queries.len() as f64,
        kd_build_ms,
        grid_build_ms,
        kd_radius,
        grid_radius,
        kd_radius_coherent,
        grid_radius_coherent,
        kd_nearest_50,
    })
}
