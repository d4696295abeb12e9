//! Scene build time (BVH included) for triangles laid out in a row, on a grid, in a random
//! cloud and all coincident: the cost must grow linearly with the count for every layout
//! (issue #13). Run with `cargo bench --bench layouts [-- COUNT...]`; the default counts are
//! 40k and 400k.

use photon::camera::CameraDesc;
use photon::material::{Lambertian, Material};
use photon::math::{Rgb, Vec3};
use photon::sampling::Rng;
use photon::scene::{SceneBuilder, TriangleMesh};
use std::time::Instant;

/// The corners of triangle `i` of `n` in `layout`.
fn triangle(layout: &str, i: usize, n: usize, rng: &mut Rng) -> [Vec3; 3] {
    let origin = match layout {
        "row" => Vec3::new(i as f32 * 0.1, 0.0, 0.0),
        "grid" => {
            let side = (n as f32).sqrt().ceil() as usize;
            Vec3::new((i % side) as f32 * 0.1, (i / side) as f32 * 0.1, 0.0)
        }
        "cloud" => Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 100.0,
        _ => Vec3::ZERO,
    };
    [
        origin,
        origin + Vec3::new(0.05, 0.0, 0.0),
        origin + Vec3::new(0.0, 0.05, 0.0),
    ]
}

fn main() {
    let counts: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let counts = if counts.is_empty() {
        vec![40_000, 400_000]
    } else {
        counts
    };
    println!("layout      triangles   build s   µs/triangle");
    for layout in ["row", "grid", "cloud", "coincident"] {
        for &n in &counts {
            let mut rng = Rng::keyed(7, &[]);
            let mut mesh = TriangleMesh::default();
            for i in 0..n {
                let base = mesh.positions.len() as u32;
                mesh.positions.extend(triangle(layout, i, n, &mut rng));
                mesh.triangles.push([base, base + 1, base + 2]);
            }
            let mut b = SceneBuilder::new(layout);
            b.camera(
                CameraDesc {
                    position: Vec3::new(0.0, 0.0, -5.0),
                    look_at: Vec3::ZERO,
                    up: Vec3::Y,
                    fov_y_deg: 40.0,
                },
                8,
                8,
            );
            let m = b.material(Material::Lambertian(Lambertian {
                albedo: Rgb::splat(0.5),
            }));
            let t = Instant::now();
            b.triangle_mesh(&mesh, glam::Affine3A::IDENTITY, m, None)
                .expect("mesh");
            let scene = b.build().expect("scene");
            let s = t.elapsed().as_secs_f64();
            std::hint::black_box(&scene);
            println!(
                "{layout:<11} {n:>9}   {s:>7.3}   {:>8.2}",
                s * 1e6 / n as f64
            );
        }
    }
}
