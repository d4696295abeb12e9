//! Procedural modelling: Catmull–Clark, NURBS, the pot.

use glam::{DVec2, DVec3, DVec4};
use photon::modeling::PolyMesh;
use photon::modeling::lathe::{lathe, solidify};
use photon::modeling::nurbs::{NurbsCurve, NurbsSurface, weighted};
use photon::modeling::pot::{POT_MAX, POT_MIN, PotParams, pot, pot_body};
use photon::modeling::subdivision::{catmull_clark, limit_position};

fn cube() -> PolyMesh {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    PolyMesh {
        positions: vec![
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(1., 1., 0.),
            p(0., 1., 0.),
            p(0., 0., 1.),
            p(1., 0., 1.),
            p(1., 1., 1.),
            p(0., 1., 1.),
        ],
        faces: vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ],
        ..PolyMesh::default()
    }
}

#[test]
fn creased_edges_stay_sharp() {
    // Every edge of a cube creased: subdivision keeps every point on the cube's surface.
    let mut m = cube();
    let edges: Vec<(u32, u32)> = photon::modeling::mesh::edge_use(&m.faces)
        .keys()
        .copied()
        .collect();
    m.creases.extend(edges);
    let fine = photon::modeling::subdivision::subdivide(&m, 3);
    assert!(fine.is_watertight());
    for p in &fine.positions {
        let d = (*p - DVec3::splat(0.5)).abs().max_element();
        assert!((d - 0.5).abs() < 1e-12, "{p} left the cube's surface");
    }
    // A creased loop (the bottom square) on an otherwise smooth cube: the crease is a closed
    // cubic B-spline of the square, so it stays exactly in the bottom plane, and so does the
    // whole bottom face inside it (a flat (2³ + 1)² grid after three levels).
    let mut m = cube();
    m.creases.extend([(0, 3), (2, 3), (1, 2), (0, 1)]);
    let fine = photon::modeling::subdivision::subdivide(&m, 3);
    let in_plane = fine.positions.iter().filter(|p| p.z.abs() < 1e-12).count();
    assert_eq!(in_plane, 81, "the flat bottom");
    // Without the crease the bottom rounds off: no point stays in the plane.
    let smooth = photon::modeling::subdivision::subdivide(&cube(), 3);
    assert_eq!(
        smooth
            .positions
            .iter()
            .filter(|p| p.z.abs() < 1e-12)
            .count(),
        0
    );
}

#[test]
fn catmull_clark_counts_follow_the_formulas_and_stay_watertight() {
    let mut m = cube();
    assert!(m.is_watertight() && m.signed_volume() > 0.0);
    for level in 1..=4 {
        let (v, e, f) = (m.positions.len(), m.edge_count(), m.faces.len());
        let sides: usize = m.faces.iter().map(Vec::len).sum();
        let next = catmull_clark(&m);
        assert_eq!(
            next.positions.len(),
            v + e + f,
            "level {level}: V' = V + E + F"
        );
        assert_eq!(next.faces.len(), sides, "level {level}: F' = Σ sides");
        assert_eq!(
            next.edge_count(),
            2 * e + sides,
            "level {level}: E' = 2E + Σ sides"
        );
        assert!(
            next.is_watertight(),
            "level {level}: every edge shared by two faces"
        );
        assert!(next.signed_volume() > 0.0, "level {level}: still outward");
        m = next;
    }
    // Converging toward a smooth closed surface: distances from the centre even out, and the
    // shape shrinks inside the cube (convex hull property).
    let c = DVec3::splat(0.5);
    let radii: Vec<f64> = m.positions.iter().map(|p| (*p - c).length()).collect();
    let (lo, hi) = radii
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
    assert!(
        hi < 0.5f64.sqrt() * 1.01 && lo > 0.3 && hi / lo < 1.4,
        "radii {lo}..{hi}"
    );
}

/// Uniform cubic B-spline surface on a regular control grid, at integer parameter (i, j):
/// (16 P + 4 Σ edge neighbours + Σ diagonals) / 36.
fn bspline_at_knot(grid: &[Vec<DVec3>], i: usize, j: usize) -> DVec3 {
    let w = [1.0, 4.0, 1.0];
    let mut s = DVec3::ZERO;
    for a in 0..3 {
        for b in 0..3 {
            s += w[a] * w[b] * grid[i + a - 1][j + b - 1];
        }
    }
    s / 36.0
}

#[test]
fn one_level_on_a_regular_grid_gives_the_bicubic_b_spline_limit_points() {
    // A bumpy 7×7 control grid as a quad mesh.
    let n = 7;
    let grid: Vec<Vec<DVec3>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| DVec3::new(i as f64, j as f64, ((i * 7 + j * 3) % 5) as f64 * 0.3))
                .collect()
        })
        .collect();
    let mut mesh = PolyMesh::default();
    for row in &grid {
        mesh.positions.extend(row.iter().copied());
    }
    let idx = |i: usize, j: usize| (i * n + j) as u32;
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            mesh.faces.push(vec![
                idx(i, j),
                idx(i + 1, j),
                idx(i + 1, j + 1),
                idx(i, j + 1),
            ]);
        }
    }
    let fine = catmull_clark(&mesh);
    // Vertex points keep the index of their vertex; find their neighbours in the fine mesh.
    for i in 2..n - 2 {
        for j in 2..n - 2 {
            let v = idx(i, j);
            let mut edge_nb = Vec::new();
            let mut diag_nb = Vec::new();
            for f in fine.faces.iter().filter(|f| f.contains(&v)) {
                let k = f.iter().position(|&x| x == v).expect("in face");
                edge_nb.push(fine.positions[f[(k + 1) % 4] as usize]);
                diag_nb.push(fine.positions[f[(k + 2) % 4] as usize]);
            }
            assert_eq!(edge_nb.len(), 4, "regular vertex");
            let limit = limit_position(fine.positions[v as usize], &edge_nb, &diag_nb);
            let want = bspline_at_knot(&grid, i, j);
            assert!(
                (limit - want).length() < 1e-12,
                "({i},{j}): {limit} vs {want}"
            );
        }
    }
}

fn circle() -> NurbsCurve {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let pts = [
        (1., 0., 1.),
        (1., 1., h),
        (0., 1., 1.),
        (-1., 1., h),
        (-1., 0., 1.),
        (-1., -1., h),
        (0., -1., 1.),
        (1., -1., h),
        (1., 0., 1.),
    ];
    NurbsCurve {
        degree: 2,
        knots: vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.],
        points: pts
            .iter()
            .map(|&(x, y, w)| weighted(DVec3::new(x, y, 0.0), w))
            .collect(),
    }
}

#[test]
fn rational_quadratic_nurbs_reproduce_a_circle_and_a_cylinder_exactly() {
    let c = circle();
    for k in 0..=1000 {
        let u = k as f64 / 1000.0;
        let p = c.point(u);
        assert!(
            (p.length() - 1.0).abs() < 1e-6,
            "u {u}: radius {}",
            p.length()
        );
        let basis = c.basis(u);
        assert!(
            (basis.iter().sum::<f64>() - 1.0).abs() < 1e-12,
            "partition of unity at {u}"
        );
        assert!(basis.iter().all(|&b| b >= 0.0));
    }
    // Cylinder of radius 1 and height 2: the circle swept linearly along z.
    let mut points = Vec::new();
    for p in &c.points {
        for z in [0.0, 2.0] {
            points.push(DVec4::new(p.x, p.y, z * p.w, p.w));
        }
    }
    let cyl = NurbsSurface {
        degree_u: 2,
        degree_v: 1,
        knots_u: c.knots.clone(),
        knots_v: vec![0., 0., 1., 1.],
        count_u: 9,
        count_v: 2,
        points,
    };
    for i in 0..=50 {
        for j in 0..=10 {
            let (u, v) = ((i as f64 / 50.0).clamp(1e-3, 1.0 - 1e-3), j as f64 / 10.0);
            let (p, _, _) = cyl.eval(u, v);
            assert!((DVec2::new(p.x, p.y).length() - 1.0).abs() < 1e-6);
            assert!((p.z - 2.0 * v).abs() < 1e-9);
            // The normal of a cylinder is radial.
            let n = cyl.normal(u, v);
            assert!(
                (n.abs() - DVec3::new(p.x, p.y, 0.0).abs()).length() < 1e-3,
                "normal {n} at {p}"
            );
        }
    }
}

#[test]
fn nurbs_normals_and_derivatives_agree_with_finite_differences() {
    // A general rational patch: check ∂S/∂u, ∂S/∂v against central differences.
    let mut points = Vec::new();
    for i in 0..5 {
        for j in 0..4 {
            let p = DVec3::new(i as f64, j as f64, ((i * 3 + j * 5) % 4) as f64 * 0.4);
            points.push(weighted(p, 0.6 + 0.2 * ((i + j) % 3) as f64));
        }
    }
    let s = NurbsSurface {
        degree_u: 3,
        degree_v: 2,
        knots_u: vec![0., 0., 0., 0., 0.3, 1., 1., 1., 1.],
        knots_v: vec![0., 0., 0., 0.6, 1., 1., 1.],
        count_u: 5,
        count_v: 4,
        points,
    };
    let h = 1e-6;
    for &(u, v) in &[(0.1, 0.2), (0.45, 0.7), (0.8, 0.35), (0.29, 0.61)] {
        let (_, su, sv) = s.eval(u, v);
        let fu = (s.eval(u + h, v).0 - s.eval(u - h, v).0) / (2.0 * h);
        let fv = (s.eval(u, v + h).0 - s.eval(u, v - h).0) / (2.0 * h);
        assert!(
            (su - fu).length() < 1e-5 * fu.length().max(1.0),
            "∂u at ({u},{v}): {su} vs {fu}"
        );
        assert!(
            (sv - fv).length() < 1e-5 * fv.length().max(1.0),
            "∂v at ({u},{v}): {sv} vs {fv}"
        );
        assert!((s.normal(u, v) - fu.cross(fv).normalize()).length() < 1e-5);
    }
}

#[test]
fn pot_body_is_watertight_outward_and_where_the_spec_puts_it() {
    let shell = solidify(
        &lathe(
            &[
                DVec2::new(0.0, 0.0),
                DVec2::new(1.0, 0.0),
                DVec2::new(1.0, 1.0),
            ],
            16,
        ),
        0.1,
    );
    assert!(shell.is_watertight() && shell.signed_volume() > 0.0);
    for levels in 0..=2 {
        let body = pot_body(levels);
        assert!(body.is_watertight(), "level {levels}");
        assert!(
            body.signed_volume() > 0.0,
            "level {levels}: normals face outward"
        );
    }
    let body = pot_body(2);
    let (lo, hi) = body.bounds();
    let size = POT_MAX - POT_MIN;
    for (a, b) in [(lo, POT_MIN), (hi, POT_MAX)] {
        let err = ((a - b).abs() / size).max_element();
        assert!(err < 0.05, "bounds {lo}..{hi} vs {POT_MIN}..{POT_MAX}");
    }
    // 16 steps × 8 profile segments per side (16 triangles at the axis, 112 quads), doubled,
    // plus 16 rim quads; each n-gon becomes n quads, then each quad 4.
    assert_eq!(body.faces.len(), ((16 * 3 + 112 * 4) * 2 + 16 * 4) * 4);
    let model = pot(&PotParams::default());
    assert_eq!(model.leaves.len(), 8);
    let other = pot(&PotParams {
        seed: 1,
        ..PotParams::default()
    });
    assert_ne!(
        model.leaves[0].positions, other.leaves[0].positions,
        "the seed varies the leaves"
    );
    // Leaves rise from the soil and fill roughly SEED-SCENE.md's leaf box.
    let (mut llo, mut lhi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
    for l in &model.leaves {
        let (a, b) = l.bounds();
        llo = llo.min(a);
        lhi = lhi.max(b);
    }
    let want_lo = DVec3::new(-5.19, -0.89, 0.37);
    let want_hi = DVec3::new(-2.80, 1.21, 2.55);
    let span = want_hi - want_lo;
    assert!(
        ((llo - want_lo).abs() / span).max_element() < 0.15,
        "leaves {llo}..{lhi}"
    );
    assert!(
        ((lhi - want_hi).abs() / span).max_element() < 0.15,
        "leaves {llo}..{lhi}"
    );
}

#[test]
fn the_default_scene_shows_the_pot_lit_with_photon_mapped_indirect_light() {
    use photon::camera::Camera;
    use photon::description::builtin;
    use photon::film::PixelFilter;
    use photon::integrator::{Integrator, PhotonIntegrator, PhotonSettings};
    use photon::math::Vec3;
    use photon::photon::{PhotonConfig, trace_photons};
    use photon::render::{RenderSettings, render};
    use std::sync::Arc;

    let scene = builtin::load("seed").expect("builds");
    let (w, h) = (48u32, 48u32);
    let camera = Camera::new(&scene.camera, w, h).expect("camera");
    // Find the pixel looking at the pot's belly (world (−4, 0.1, 0.4) is its front-facing side).
    let target = Vec3::new(-4.0, -0.5, 0.4);
    let mut best = (0u32, 0u32, f32::MAX);
    for y in 0..h {
        for x in 0..w {
            let r = camera.ray(glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            let d = r.dir.cross(target - r.origin).length() / (target - r.origin).length();
            if d < best.2 {
                best = (x, y, d);
            }
        }
    }
    let (px, py, _) = best;
    let hit = scene
        .intersect(
            &camera.ray(glam::Vec2::new(px as f32 + 0.5, py as f32 + 0.5)),
            f32::INFINITY,
        )
        .expect("sees something");
    let m = scene.material(hit.material);
    let albedo = m.albedo(Vec3::Z);
    assert!(
        albedo.x > albedo.y && albedo.y > albedo.z,
        "the pot is terracotta, got {albedo} at pixel ({px},{py})"
    );
    // Bottom-left quarter: the pot sits in the front-left corner of the image.
    assert!(px < w / 2 && py > h / 2, "pot at pixel ({px},{py})");

    let config = PhotonConfig {
        photons: 200_000,
        global_photons: Some(50_000),
        ..PhotonConfig::default()
    };
    let maps = trace_photons(&scene, &config, &|_, _| {}).expect("traces");
    let settings = PhotonSettings::for_scene(&scene);
    let integrator = Integrator::Photon(Box::new(PhotonIntegrator::new(settings, Arc::new(maps))));
    let s = RenderSettings {
        seed: 1,
        filter: PixelFilter::Box,
        ..RenderSettings::new(w, h, 4)
    };
    let out = render(&scene, &integrator, &s, &|_, _| {}).expect("renders");
    // Pot pixels (terracotta albedo): directly lit on the side facing the light, and receiving
    // photon-mapped indirect light (the side facing the camera is in shadow).
    let pot_pixels: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let a = out.aovs.albedo.get(x, y);
            (a - glam::Vec3::new(0.62, 0.33, 0.22)).abs().max_element() < 0.02
        })
        .collect();
    assert!(pot_pixels.len() > 20, "{} pot pixels", pot_pixels.len());
    assert!(pot_pixels.contains(&(px, py)));
    assert!(
        pot_pixels
            .iter()
            .any(|&(x, y)| out.aovs.direct.get(x, y).x > 0.0),
        "no direct light on the pot"
    );
    // (A few pixels facing the open front may send all their gather rays out of the box.)
    let lit = pot_pixels
        .iter()
        .filter(|&&(x, y)| out.aovs.indirect.get(x, y).x > 0.0)
        .count();
    assert!(
        lit * 10 >= pot_pixels.len() * 9,
        "{lit} of {} pot pixels get indirect light",
        pot_pixels.len()
    );
    // Leaves are green where they are seen: some pixel above the pot shows leaf albedo.
    let leaf_seen = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .any(|(x, y)| {
            let a = out.aovs.albedo.get(x, y);
            a.y > 2.0 * a.x && a.y > 2.0 * a.z && a.y < 0.45
        });
    assert!(leaf_seen, "no leaf visible");
}
