//! The original project's succulent in a pot, modelled the way it was in Blender: a profile
//! revolved (lathe), given thickness (solidify), smoothed by Catmull–Clark subdivision; a soil
//! disk; leaves from NURBS patches. Placed where the original's Blender file put it.

use super::lathe::{lathe, solidify};
use super::mesh::PolyMesh;
use super::nurbs::{NurbsSurface, clamped_uniform_knots, weighted};
use super::subdivision::subdivide;
use crate::sampling::Rng;
use glam::{DAffine3, DVec2, DVec3};
use std::f64::consts::TAU;

/// Where SEED-SCENE.md puts the pot: bounding box, base centre, soil height and radius.
pub const POT_MIN: DVec3 = DVec3::new(-4.687, -0.587, 0.012);
pub const POT_MAX: DVec3 = DVec3::new(-3.313, 0.787, 0.985);
pub const SOIL_HEIGHT: f64 = 0.7453;
pub const SOIL_RADIUS: f64 = 0.64;
const LEAF_COUNT: usize = 8;

/// Parameters of the procedural pot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PotParams {
    /// Catmull–Clark levels applied to the body (the original used 2).
    pub subdivisions: u32,
    /// Varies the leaves.
    pub seed: u64,
}

impl Default for PotParams {
    fn default() -> Self {
        Self {
            subdivisions: 2,
            seed: 0,
        }
    }
}

/// The assembled model, in world space (Z up).
#[derive(Clone, Debug)]
pub struct PotModel {
    pub body: PolyMesh,
    pub soil_center: DVec3,
    pub soil_radius: f64,
    pub leaves: Vec<PolyMesh>,
}

/// The 9-point profile (radius, height) of the outer surface, from the centre of the base up to
/// the rim, in model units; revolved in 16 steps and solidified 0.195 inward as in the original.
const PROFILE: [[f64; 2]; 9] = [
    [0.0, 0.0],
    [1.30, 0.0],
    [1.45, 0.10],
    [1.55, 0.60],
    [1.70, 1.40],
    [1.85, 2.05],
    [1.95, 2.40],
    [2.15, 2.50],
    [2.15, 2.85],
];
const LATHE_STEPS: u32 = 16;
const THICKNESS: f64 = 0.195;
const HEIGHT_STRETCH: f64 = 1.045;

/// The pot body: lathe → solidify → Catmull–Clark, then scaled and moved onto its spot.
pub fn pot_body(subdivisions: u32) -> PolyMesh {
    // Heights stretched so that, after subdivision rounds the rim, the height-to-width ratio is
    // SEED-SCENE.md's (0.973 / 1.374).
    let profile: Vec<DVec2> = PROFILE
        .iter()
        .map(|p| DVec2::new(p[0], p[1] * HEIGHT_STRETCH))
        .collect();
    let shell = solidify(&lathe(&profile, LATHE_STEPS), THICKNESS);
    let mut body = subdivide(&shell, subdivisions);
    let (lo, hi) = body.bounds();
    let scale = (POT_MAX.x - POT_MIN.x) / (hi.x - lo.x);
    let target_base = DVec3::new(
        0.5 * (POT_MIN.x + POT_MAX.x),
        0.5 * (POT_MIN.y + POT_MAX.y),
        POT_MIN.z,
    );
    let model_base = DVec3::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z);
    let m = DAffine3::from_translation(target_base)
        * DAffine3::from_scale(DVec3::splat(scale))
        * DAffine3::from_translation(-model_base);
    body.transform(&m);
    body
}

/// One leaf as a NURBS patch (cubic along, quadratic across, a raised midrib), rising from
/// `base` toward azimuth `phi`: `reach` outward; its midline height follows the quadratic
/// Bézier 2t(1 − t)·`arch` + t²·`tip` (a drooping leaf has a negative tip).
fn leaf(base: DVec3, phi: f64, reach: f64, arch: f64, tip: f64, width: f64) -> NurbsSurface {
    let along = DVec3::new(phi.cos(), phi.sin(), 0.0);
    let across = DVec3::new(-phi.sin(), phi.cos(), 0.0);
    let widths = [0.15, 0.45, 0.5, 0.35, 0.02];
    let mut points = Vec::new();
    for (i, w) in widths.iter().enumerate() {
        let t = i as f64 / 4.0;
        let height = 2.0 * t * (1.0 - t) * arch + t * t * tip;
        let centre = base + along * (reach * t) + DVec3::Z * height;
        for j in 0..3 {
            let s = j as f64 - 1.0;
            let midrib = if j == 1 { 0.06 * width } else { 0.0 };
            let p = centre + across * (s * w * width) + DVec3::Z * midrib;
            points.push(weighted(p, if j == 1 { 1.2 } else { 1.0 }));
        }
    }
    NurbsSurface {
        degree_u: 3,
        degree_v: 2,
        knots_u: clamped_uniform_knots(5, 3),
        knots_v: clamped_uniform_knots(3, 2),
        count_u: 5,
        count_v: 3,
        points,
    }
}

impl PotModel {
    /// The soil as a polygon mesh (a 32-sided disc), for export.
    pub fn soil_mesh(&self) -> PolyMesh {
        let n = 32;
        let mut m = PolyMesh::default();
        for k in 0..n {
            let a = TAU * f64::from(k) / f64::from(n);
            m.positions
                .push(self.soil_center + self.soil_radius * DVec3::new(a.cos(), a.sin(), 0.0));
        }
        m.faces.push((0..n).collect());
        m
    }

    /// All leaves as one mesh.
    pub fn leaves_mesh(&self) -> PolyMesh {
        let mut m = PolyMesh::default();
        for l in &self.leaves {
            m.append(l);
        }
        m
    }
}

/// The whole pot: body, soil and eight leaves (their shapes varied by `seed`).
pub fn pot(params: &PotParams) -> PotModel {
    let body = pot_body(params.subdivisions);
    let centre = DVec3::new(
        0.5 * (POT_MIN.x + POT_MAX.x),
        0.5 * (POT_MIN.y + POT_MAX.y),
        SOIL_HEIGHT,
    );
    let mut rng = Rng::keyed(params.seed, &[0x1eaf]);
    // From upright to drooping over the rim: together they fill SEED-SCENE.md's leaf box.
    let upright = [1.0, 0.25, 0.8, 0.1, 0.6, 0.35, 0.9, 0.2];
    let leaves = (0..LEAF_COUNT)
        .map(|k| {
            let a = (upright[k] + 0.15 * (f64::from(rng.next_f32()) - 0.5)).clamp(0.0, 1.0);
            let phi = TAU * k as f64 / LEAF_COUNT as f64 + 0.35 * (f64::from(rng.next_f32()) - 0.5);
            let start = centre + 0.12 * DVec3::new(phi.cos(), phi.sin(), 0.0);
            let surface = leaf(
                start,
                phi,
                1.6 - 1.0 * a,
                0.9 + 1.2 * a,
                -0.55 + 2.45 * a,
                0.55 - 0.15 * a,
            );
            surface.tessellate(16, 6)
        })
        .collect();
    PotModel {
        body,
        soil_center: centre,
        soil_radius: SOIL_RADIUS,
        leaves,
    }
}
