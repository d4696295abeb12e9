//! Radiance and irradiance estimates from photon maps (Jensen 2001, ch. 7):
//! L(x, ωo) ≈ Σ f(x, ωi, ωo) ΔΦi w(di), with a kernel w normalised over the gather disc.
//!
//! Photons are gathered by k-nearest within a maximum radius (the radius then is the k-th
//! distance, or the maximum if fewer are found) or by a fixed radius. Only photons whose stored
//! normal agrees with the query's (the same side of the same surface: the original project's
//! "above the surface and going toward it", done right) are used, and distance is measured in
//! a disc flattened along the normal, so photons on a nearby wall or the other face of a thin
//! object do not leak in.

use super::map::PhotonMap;
use crate::material::{Material, Part, TransportMode};
use crate::math::{Frame, Rgb, Vec3, plane_tolerance};
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

/// How far the normals of one plane may differ when the photon's is stored in a map: each is
/// within 1° of the true normal (octahedral 2 × u8, see [`super::record`]), so together
/// within 2° (0.035 rad).
pub(crate) const STORED_NORMAL_ERROR: f32 = 0.04;
/// The same for a progressive pass's photons, whose normals are exact (f32).
pub(crate) const EXACT_NORMAL_ERROR: f32 = 1e-3;

/// Distance² in the flattened metric, or `None` if the photon is on another surface.
///
/// `d` is the photon's offset from the query point, `d2` its length², `n` and `photon_normal`
/// the geometric normals of the two points on the sides their light came from. A photon is on
/// the query's surface when
/// - the normals agree (cos > 0.9): not a wall meeting this one in a corner, nor the other
///   face of a thin object;
/// - its offset from the query's tangent plane is explained by the surface's bending. On a
///   smooth surface a chord between points with normals n and n′ leaves the tangent plane by
///   |d·n| = |d| |n − n′| / 2 (exactly on a circle), and across the facets of a tessellated
///   one by at most |d| |n − n′|. `normal_error` |d| covers the normals' own error
///   ([`STORED_NORMAL_ERROR`] or [`EXACT_NORMAL_ERROR`]) and `plane_tolerance` (a few ulps of
///   the coordinates) rounding. A photon further off the plane lies on a parallel surface
///   nearby: a ceiling above a light mounted just below it, a shelf above a shelf. Such
///   photons are left out once the disc is under their offset / `normal_error` (a light 1 cm
///   below a ceiling: 25 cm for a photon map, 10 m for a progressive pass).
#[inline]
pub(crate) fn disc_distance2(
    d: Vec3,
    d2: f32,
    n: Vec3,
    photon_normal: Vec3,
    plane_tolerance: f32,
    normal_error: f32,
) -> Option<f32> {
    if photon_normal.dot(n) < NORMAL_AGREEMENT {
        return None;
    }
    let h = d.dot(n);
    let off_plane = h.abs() - plane_tolerance;
    let bend = (n - photon_normal).length() + normal_error;
    if off_plane > 0.0 && off_plane * off_plane > d2 * bend * bend {
        return None;
    }
    Some(d2 + (DISC * DISC - 1.0) * h * h)
}

/// Which photons of a map a gather may use.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Filter {
    /// Leave out photons straight from a light (direct light comes from next-event estimation).
    pub(super) skip_direct: bool,
    /// Leave out the irradiance cache's sites for this stride (0: none): the cache sits at
    /// those photons, and its estimates must not use them (see [`super::IrradianceCache`]).
    pub(super) skip_sites: usize,
    /// Keep only the irradiance cache's sites for this stride (0: all).
    pub(super) only_sites: usize,
}

impl Filter {
    #[inline]
    fn skips(&self, ph: &super::Photon) -> bool {
        (self.skip_direct && ph.is_direct())
            || (self.skip_sites > 1 && super::cache::is_cache_site(ph, self.skip_sites))
            || (self.only_sites > 1 && !super::cache::is_cache_site(ph, self.only_sites))
    }
}

/// Visit the photons gathered at `p` (normal `n`): `f(photon index, kernel weight)`.
///
/// A k-nearest gather finds k + 1 photons and closes the disc with the farthest, which is
/// left out: given the radius, the k inside are uniform over the disc, and E[k / (π r²₍ₖ₊₁₎)]
/// is exactly the density (for a Poisson process; Silverman 1986, §5.2.2), so every kernel
/// normalised over its disc is unbiased. Summing the photon that closes the disc, as Jensen's
/// estimate does, is k/(k−1) too bright with the box kernel. When fewer than k + 1 photons lie
/// within the maximum radius, the farthest of them closes the disc (see below).
pub(super) fn gather(
    map: &PhotonMap,
    p: Vec3,
    n: Vec3,
    g: &GatherParams,
    filter: Filter,
    f: &mut impl FnMut(usize, f32),
) {
    let photons = map.photons();
    let max_r2 = g.max_radius * g.max_radius;
    let tolerance = plane_tolerance(p);
    if g.k == 0 {
        map.for_each_within(p, g.max_radius, &mut |i, d2| {
            let ph = &photons[i];
            if filter.skips(ph) {
                return;
            }
            if let Some(m) = disc_distance2(
                ph.position() - p,
                d2,
                n,
                ph.normal(),
                tolerance,
                STORED_NORMAL_ERROR,
            ) && m <= max_r2
            {
                f(i, g.kernel.weight(m, max_r2));
            }
        });
        return;
    }
    let metric = |_, ph: &super::Photon, d2: f32| {
        if filter.skips(ph) {
            return None;
        }
        disc_distance2(
            ph.position() - p,
            d2,
            n,
            ph.normal(),
            tolerance,
            STORED_NORMAL_ERROR,
        )
    };
    let best = map
        .index()
        .nearest_by(photons, p, g.k.saturating_add(1), max_r2, &metric);
    // The heap's root is the farthest photon found: with k + 1, the one that closes the disc.
    // With fewer (2 ≤ n ≤ k) inside the maximum radius, the farthest closes the disc all the
    // same: given n photons uniform in the maximum disc, the other n − 1 are uniform in the
    // disc the farthest closes, and E[(n − 1)/(π r²ₙ)] = n/(π r²ₘₐₓ), the unbiased estimate on
    // a plane. Where the surface that agrees with the normal is smaller than the maximum disc
    // (a small sphere, a thin strip), the closing radius adapts to it, where dividing by the
    // maximum disc read a sphere under a sky at 8% of its light. A lone photon keeps the
    // maximum radius (n = 1 has no disc of its own).
    let found = best.found();
    let (r2, closing) = match found.first() {
        Some(&(d2, i)) if best.is_full() || found.len() >= 2 => (d2, Some(i)),
        Some(_) => (max_r2, None),
        None => return,
    };
    if r2 <= 0.0 || r2.is_nan() {
        // Photons at one point: no disc to spread them over.
        return;
    }
    for &(m, i) in found {
        if Some(i) != closing {
            f(i, g.kernel.weight(m, r2));
        }
    }
}

/// Which photons of a map a radiance estimate sums.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Selection {
    All,
    /// Leave out photons straight from a light (direct light comes from next-event estimation).
    Indirect,
}

/// Reflected radiance at `p` toward `wo` from the `selection` of `map`'s photons: Σ f ΔΦ w,
/// with f the material's rough part (photons are stored only on rough parts). `ng` is the
/// geometric normal and `frame.n` the shading normal, both on the side of `wo`.
#[expect(
    clippy::too_many_arguments,
    reason = "a point, its surface and what to gather"
)]
pub fn radiance(
    map: &PhotonMap,
    p: Vec3,
    ng: Vec3,
    frame: &Frame,
    wo_local: Vec3,
    material: &Material,
    g: &GatherParams,
    selection: Selection,
) -> Rgb {
    let mut l = Rgb::ZERO;
    let photons = map.photons();
    let filter = Filter {
        skip_direct: selection == Selection::Indirect,
        ..Filter::default()
    };
    gather(map, p, ng, g, filter, &mut |i, w| {
        let wi = frame.to_local(photons[i].incoming());
        l += material.eval_part(wo_local, wi, TransportMode::Radiance, Part::Rough)
            * photons[i].relative_power()
            * w;
    });
    l * map.power_scale
}

/// Irradiance E at `p` on the side of normal `n`: Σ ΔΦ w (watts per m²).
pub fn irradiance(map: &PhotonMap, p: Vec3, n: Vec3, g: &GatherParams) -> Rgb {
    irradiance_filtered(map, p, n, g, Filter::default())
}

pub(super) fn irradiance_filtered(
    map: &PhotonMap,
    p: Vec3,
    n: Vec3,
    g: &GatherParams,
    filter: Filter,
) -> Rgb {
    let mut e = Rgb::ZERO;
    let photons = map.photons();
    gather(map, p, n, g, filter, &mut |i, w| {
        e += photons[i].relative_power() * w;
    });
    e * map.power_scale
}

#[cfg(test)]
mod tests {
    use super::disc_distance2;
    use crate::math::Vec3;

    /// Whether a photon at `q` with normal `nq` counts for a query at `p` with normal `np`.
    fn counts(p: Vec3, np: Vec3, q: Vec3, nq: Vec3) -> bool {
        let d = q - p;
        disc_distance2(
            d,
            d.length_squared(),
            np,
            nq,
            1e-6,
            super::STORED_NORMAL_ERROR,
        )
        .is_some()
    }

    #[test]
    fn a_parallel_surface_one_centimetre_away_is_another_surface() {
        let down = -Vec3::Y;
        let p = Vec3::new(0.0, 0.99, 0.0);
        for r in [0.02, 0.05, 0.2] {
            // Photons on the ceiling 1 cm above, facing the same way.
            assert!(!counts(p, down, Vec3::new(r, 1.0, 0.0), down), "r = {r}");
            // Photons on the light's own plane.
            assert!(counts(p, down, Vec3::new(r, 0.99, 0.0), down), "r = {r}");
        }
    }

    #[test]
    fn a_curved_surface_is_one_surface_across_the_disc() {
        // Points on a sphere (outward normals) and on the facets of a sphere tessellated
        // every 10° (each facet's normal at its middle): every neighbour within the normal
        // agreement (25°) counts.
        let radius = 0.3;
        let on_sphere = |a: f32| {
            (
                Vec3::new(a.sin(), a.cos(), 0.0) * radius,
                Vec3::new(a.sin(), a.cos(), 0.0),
            )
        };
        for a in [0.01f32, 0.1, 0.2, 0.4] {
            let (q, nq) = on_sphere(a);
            assert!(
                counts(Vec3::Y * radius, Vec3::Y, q, nq),
                "sphere at {a} rad"
            );
        }
        let step = 10f32.to_radians();
        let facet_normal = |i: f32| on_sphere((i + 0.5) * step).1;
        // The query on facet 0 (from 0° to 10°), photons on facets 1 and 2 (10° to 30°).
        let facet_point = |i: f32, s: f32| {
            let (a, b) = (on_sphere(i * step).0, on_sphere((i + 1.0) * step).0);
            a + (b - a) * s
        };
        for (qs, ps, facet) in [
            (0.9, 0.1, 1.0),
            (0.0, 0.5, 1.0),
            (0.5, 0.2, 2.0),
            (1.0, 0.9, 1.0),
        ] {
            let p = facet_point(0.0, qs);
            let q = facet_point(facet, ps);
            assert!(
                counts(p, facet_normal(0.0), q, facet_normal(facet)),
                "facet 0 at {qs}, facet {facet} at {ps}"
            );
        }
    }

    #[test]
    fn walls_meeting_in_a_corner_are_other_surfaces() {
        assert!(!counts(
            Vec3::ZERO,
            Vec3::Y,
            Vec3::new(0.01, 0.01, 0.0),
            Vec3::X
        ));
    }
}
