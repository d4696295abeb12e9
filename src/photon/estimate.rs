//! Radiance and irradiance estimates from photon maps (Jensen 2001, ch. 7):
//! L(x, ωo) ≈ Σ f(x, ωi, ωo) ΔΦi w(di), with a kernel w normalised over the gather disc.
//!
//! Photons are gathered by k-nearest within a maximum radius (the radius then is the k-th
//! distance, or the maximum if fewer are found) or by a fixed radius. Only photons whose stored
//! normal agrees with the query's (the same side of the same surface: the original project's
//! "above the surface and going toward it", done right) are used, and distance is measured in
//! a disc flattened along the normal, so photons on a nearby wall or the other face of a thin
//! object do not leak in.

use super::kdtree::{KdIndex, KdPoint};
use super::map::PhotonMap;
use super::record::{decode_octahedral, encode_octahedral};
use crate::material::Material;
use crate::math::{Frame, Rgb, Vec3};
use rayon::prelude::*;
use std::f32::consts::PI;

/// Density-estimation kernels, each normalised to integrate to 1 over its disc.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// Constant: 1 / (π r²).
    Box,
    /// Jensen's cone filter (k = 1): weight ∝ 1 − d/r.
    Cone,
    /// Pavicic's Gaussian (α = 0.918, β = 1.953), here normalised exactly.
    Gaussian,
    /// Epanechnikov: weight ∝ 1 − d²/r², the kernel of least asymptotic error.
    Epanechnikov,
}

const PAVICIC_BETA: f32 = 1.953;

impl Kernel {
    pub const ALL: [Kernel; 4] = [
        Kernel::Box,
        Kernel::Cone,
        Kernel::Gaussian,
        Kernel::Epanechnikov,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Kernel::Box => "box",
            Kernel::Cone => "cone",
            Kernel::Gaussian => "gaussian",
            Kernel::Epanechnikov => "epanechnikov",
        }
    }

    /// Unnormalised profile g(s²) for s = d/r in [0, 1].
    fn profile(self, s2: f32) -> f32 {
        match self {
            Kernel::Box => 1.0,
            Kernel::Cone => 1.0 - s2.sqrt(),
            Kernel::Gaussian => {
                1.0 - (1.0 - (-PAVICIC_BETA * s2 / 2.0).exp()) / (1.0 - (-PAVICIC_BETA).exp())
            }
            Kernel::Epanechnikov => 1.0 - s2,
        }
    }

    /// ∫ over the unit disc of g = 2π ∫₀¹ g(s) s ds, in closed form.
    fn norm(self) -> f32 {
        match self {
            Kernel::Box => PI,
            Kernel::Cone => PI / 3.0,
            Kernel::Gaussian => {
                let b = PAVICIC_BETA;
                let inner = 0.5 - (0.5 - (1.0 - (-b / 2.0).exp()) / b) / (1.0 - (-b).exp());
                2.0 * PI * inner
            }
            Kernel::Epanechnikov => PI / 2.0,
        }
    }

    /// Weight of a photon at distance² `d2` in a disc of radius² `r2`; ∫_disc w dA = 1.
    #[inline]
    pub fn weight(self, d2: f32, r2: f32) -> f32 {
        if d2 > r2 {
            return 0.0;
        }
        self.profile(d2 / r2) / (self.norm() * r2)
    }
}

/// How photons are gathered around a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GatherParams {
    /// Photons per estimate; 0 for a fixed-radius gather at `max_radius`.
    pub k: usize,
    pub max_radius: f32,
    pub kernel: Kernel,
}

/// Cosine below which a photon's normal disagrees with the query's (about 25°).
const NORMAL_AGREEMENT: f32 = 0.9;
/// Distance along the normal counts this many times more than distance in the plane: the
/// search sphere is flattened into a disc of thickness 2r/DISC.
const DISC: f32 = 3.0;

/// Distance² in the flattened metric, or `None` if the photon is on another surface.
#[inline]
fn disc_distance2(d: Vec3, d2: f32, n: Vec3, photon_normal: Vec3) -> Option<f32> {
    if photon_normal.dot(n) < NORMAL_AGREEMENT {
        return None;
    }
    let h = d.dot(n);
    Some(d2 + (DISC * DISC - 1.0) * h * h)
}

/// Visit the photons gathered at `p` (normal `n`): `f(photon index, kernel weight)`.
fn gather(
    map: &PhotonMap,
    p: Vec3,
    n: Vec3,
    g: &GatherParams,
    skip_direct: bool,
    f: &mut impl FnMut(usize, f32),
) {
    let photons = map.photons();
    let metric = |ph: &super::Photon, d2: f32| {
        if skip_direct && ph.is_direct() {
            return None;
        }
        disc_distance2(ph.position() - p, d2, n, ph.normal())
    };
    let max_r2 = g.max_radius * g.max_radius;
    if g.k == 0 {
        map.for_each_within(p, g.max_radius, &mut |i, d2| {
            if let Some(m) = metric(&photons[i], d2)
                && m <= max_r2
            {
                f(i, g.kernel.weight(m, max_r2));
            }
        });
        return;
    }
    let best = map.index().nearest_by(photons, p, g.k, max_r2, &metric);
    let r2 = best.r2();
    for &(m, i) in best.found() {
        f(i, g.kernel.weight(m, r2));
    }
}

/// Reflected radiance at `p` toward `wo` from the photons of `map`: Σ f ΔΦ w. `frame.n` is the
/// normal on the side of `wo`. With `skip_direct`, photons straight from a light are left out
/// (direct light is computed by next-event estimation instead).
pub fn radiance(
    map: &PhotonMap,
    p: Vec3,
    frame: &Frame,
    wo_local: Vec3,
    material: &Material,
    g: &GatherParams,
    skip_direct: bool,
) -> Rgb {
    let mut l = Rgb::ZERO;
    let photons = map.photons();
    gather(map, p, frame.n, g, skip_direct, &mut |i, w| {
        let wi = frame.to_local(photons[i].incoming());
        l += material.eval(wo_local, wi) * photons[i].relative_power() * w;
    });
    l * map.power_scale
}

/// Reflected radiance at a point from every photon of `map` within the fixed radius `r`
/// (box kernel, 1/(π r²)) that passes the surface filter: Σ f ΔΦ / (π r²), and how many
/// photons contributed. The progressive integrators' estimate.
pub fn radiance_fixed_radius(
    map: &PhotonMap,
    p: Vec3,
    frame: &Frame,
    wo_local: Vec3,
    material: &Material,
    r: f32,
    skip_direct: bool,
) -> (Rgb, u32) {
    let photons = map.photons();
    let mut sum = Rgb::ZERO;
    let mut count = 0;
    let r2 = r * r;
    map.for_each_within(p, r, &mut |i, d2| {
        let ph = &photons[i];
        if skip_direct && ph.is_direct() {
            return;
        }
        if let Some(m) = disc_distance2(ph.position() - p, d2, frame.n, ph.normal())
            && m <= r2
        {
            sum += material.eval(wo_local, frame.to_local(ph.incoming())) * ph.relative_power();
            count += 1;
        }
    });
    (sum * (map.power_scale / (PI * r2)), count)
}

/// Irradiance E at `p` on the side of normal `n`: Σ ΔΦ w (watts per m²).
pub fn irradiance(map: &PhotonMap, p: Vec3, n: Vec3, g: &GatherParams) -> Rgb {
    let mut e = Rgb::ZERO;
    let photons = map.photons();
    gather(map, p, n, g, false, &mut |i, w| {
        e += photons[i].relative_power() * w;
    });
    e * map.power_scale
}

/// Irradiance precomputed at a subset of the global map's photons (Christensen, "Faster
/// Photon Map Global Illumination", JGT 1999), so that a final-gather ray costs one nearest
/// lookup instead of a full density estimate.
#[derive(Clone, Debug)]
pub struct IrradianceCache {
    points: Vec<CachePoint>,
    index: KdIndex,
}

#[derive(Clone, Copy, Debug)]
struct CachePoint {
    position: Vec3,
    normal: [u8; 2],
    irradiance: Rgb,
}

impl KdPoint for CachePoint {
    fn position(&self) -> Vec3 {
        self.position
    }
}

impl IrradianceCache {
    /// Irradiance from `maps` (all of them added) at every `stride`-th photon of `at`.
    pub fn build(at: &PhotonMap, maps: &[&PhotonMap], stride: usize, g: &GatherParams) -> Self {
        let mut points: Vec<CachePoint> = at
            .photons()
            .par_iter()
            .step_by(stride.max(1))
            .map(|ph| {
                let (p, n) = (ph.position(), ph.normal());
                CachePoint {
                    position: p,
                    normal: encode_octahedral(n),
                    irradiance: maps.iter().map(|m| irradiance(m, p, n, g)).sum(),
                }
            })
            .collect();
        let index = super::kdtree::build(&mut points);
        Self { points, index }
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Irradiance of the nearest cache point on the same surface within `max_radius`.
    pub fn lookup(&self, p: Vec3, n: Vec3, max_radius: f32) -> Option<Rgb> {
        let metric = |c: &CachePoint, d2: f32| {
            disc_distance2(c.position - p, d2, n, decode_octahedral(c.normal))
        };
        let best = self
            .index
            .nearest_by(&self.points, p, 1, max_radius * max_radius, &metric);
        best.found()
            .first()
            .map(|&(_, i)| self.points[i].irradiance)
    }
}
