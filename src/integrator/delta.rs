//! How a camera path leaves a surface through the smooth part of its material: along every
//! branch of its delta lobes near the camera, along one sampled direction beyond.

use super::ShadingPoint;
use crate::material::{Material, Part, TransportMode};
use crate::math::{Rgb, Vec3};
use crate::sampling::Sampler;

/// One direction a camera path leaves a surface in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SmoothBranch {
    /// The direction, in the shading frame.
    pub wi: Vec3,
    /// The path throughput's factor: a delta branch's whole weight where every branch is
    /// followed, f·|cos|/pdf where one direction was sampled.
    pub weight: Rgb,
    /// The density of a direction sampled from a lobe with one (what emission found along it
    /// is weighted with); `None` along a delta lobe.
    pub glossy_pdf: Option<f32>,
}

/// The directions a camera path leaves a surface in (see [`smooth_branches`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SmoothBranches {
    /// Whether these are every delta branch, each counted with its whole weight (no choice was
    /// made, so no probability divides them).
    pub split: bool,
    pub branches: [Option<SmoothBranch>; 2],
}

/// Where a camera path at `depth` bounces goes from `sp` through the lobes of `part`.
///
/// While `depth < split_depth`, along every branch of the material's delta lobes (glass: its
/// reflection with weight F and its refraction with weight 1 − F): choosing one at random
/// makes the light seen in mirrors and glass, and the caustics seen through them, flicker
/// between samples, while both together cost little near the camera. Beyond that depth, or
/// where the material has no delta branch toward `wo`, along one direction sampled from
/// `part` (which draws two numbers from `rng`, the lobe's then the direction's).
pub(crate) fn smooth_branches<R: Sampler + ?Sized>(
    sp: &ShadingPoint,
    part: Part,
    depth: u32,
    split_depth: u32,
    rng: &mut R,
) -> SmoothBranches {
    let m = &sp.material;
    let split = m.specular_branches(sp.wo_local, TransportMode::Radiance);
    if depth < split_depth && split[0].is_some() {
        return SmoothBranches {
            split: true,
            branches: split.map(|b| {
                b.map(|b| SmoothBranch {
                    wi: b.wi,
                    weight: b.weight,
                    glossy_pdf: None,
                })
            }),
        };
    }
    let u_lobe = rng.next_f32();
    let u = rng.next_2d();
    let sampled = m
        .sample_part(sp.wo_local, u_lobe, u, TransportMode::Radiance, part)
        .map(|s| SmoothBranch {
            wi: s.wi,
            weight: s.weight,
            glossy_pdf: (!s.is_specular()).then_some(s.pdf),
        });
    SmoothBranches {
        split: false,
        branches: [sampled, None],
    }
}

/// Probability that a camera path stops at a material rather than going on through its
/// smooth part: 1 with only a rough part (or when it may go no further), 0 with only a smooth
/// part, else the rough part's share of the albedo seen from `wo`, kept within [0.1, 0.9] so
/// neither choice is starved. The one rule for a coat over a rough base: the progressive
/// methods' camera paths stop there with this probability (their visible point), and the
/// photon integrator's, which take the rough part at every point, go on along the coat with
/// the rest (Russian roulette).
pub(crate) fn stop_probability(m: &Material, wo: Vec3, may_go_on: bool) -> f32 {
    match (m.has(Part::Rough), m.has(Part::Smooth) && may_go_on) {
        (true, false) => 1.0,
        (false, _) => 0.0,
        (true, true) => {
            let rough = m.part_weight(wo, Part::Rough);
            let smooth = m.part_weight(wo, Part::Smooth);
            if rough + smooth > 0.0 {
                (rough / (rough + smooth)).clamp(0.1, 0.9)
            } else {
                0.5
            }
        }
    }
}
