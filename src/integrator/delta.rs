//! How a camera path leaves a surface through the smooth part of its material: along every
//! branch of its delta lobes near the camera, along one sampled direction beyond.

use super::ShadingPoint;
use crate::material::{Part, TransportMode};
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
