//! Where a subpath's vertex is and what scatters light there: a surface's material, or a
//! medium's phase function at a point (volumetric path space: Pauly, Kollig and Keller 2000;
//! Lafortune and Willems 1996). The integrator's code treats both through [`Scatterer`] and
//! [`Site`]; only the measure of a vertex differs: area on a surface, volume in a medium.

use crate::material::{Material, TransportMode};
use crate::math::{Frame, Ray, Rgb, Vec3};
use crate::medium::{HenyeyGreenstein, MediumId};
use crate::sampling::Sampler;
use crate::scene::{Hit, Scene};
use crate::spectrum::Lambda;

/// Where a vertex is, for the rays that leave or reach it.
#[derive(Clone, Copy, Debug)]
pub(super) enum Site {
    /// On a surface, reached through `medium` (the medium on the side the subpath came from).
    Surface { hit: Hit, medium: Option<MediumId> },
    /// At a scattering point in a medium.
    Medium { p: Vec3, medium: MediumId },
}

impl Site {
    pub fn p(&self) -> Vec3 {
        match self {
            Site::Surface { hit, .. } => hit.p,
            Site::Medium { p, .. } => *p,
        }
    }

    /// The start of a ray leaving toward `w`, and the medium it runs in.
    pub fn leave(&self, scene: &Scene, w: Vec3) -> (Vec3, Option<MediumId>) {
        match self {
            Site::Surface { hit, medium } => {
                (hit.offset_origin(w), scene.medium_after(hit, *medium, w))
            }
            Site::Medium { p, medium } => (*p, Some(*medium)),
        }
    }

    /// The end of a ray that reaches this vertex travelling along `w`: moved off its surface
    /// toward where the ray comes from.
    pub fn reached_along(&self, w: Vec3) -> Vec3 {
        match self {
            Site::Surface { hit, .. } => hit.offset_origin(-w),
            Site::Medium { p, .. } => *p,
        }
    }
}

/// The fraction of light that travels from `from` to `to` (no surface between, and the
/// transmittance of the media crossed, estimated with `rng` in grids) at the wavelengths
/// `lambda`.
pub(super) fn transmittance(
    scene: &Scene,
    from: &Site,
    to: &Site,
    lambda: &Lambda,
    rng: &mut impl Sampler,
) -> Rgb {
    let d = to.p() - from.p();
    let dist = d.length();
    if dist.is_nan() || dist == 0.0 {
        return Rgb::ZERO;
    }
    let w = d / dist;
    let (origin, medium) = from.leave(scene, w);
    transmittance_to(scene, origin, medium, to.reached_along(w), lambda, rng)
}

/// The fraction of light that travels from `origin`, in `medium`, to `target`.
pub(super) fn transmittance_to(
    scene: &Scene,
    origin: Vec3,
    medium: Option<MediumId>,
    target: Vec3,
    lambda: &Lambda,
    rng: &mut impl Sampler,
) -> Rgb {
    if scene.has_media() {
        return scene.transmittance(origin, target, medium, lambda, rng);
    }
    if scene.segment_is_clear(origin, target) {
        Rgb::ONE
    } else {
        Rgb::ZERO
    }
}

/// What scatters light at a vertex, seen from the direction `wo` the subpath arrived from.
#[derive(Clone, Copy, Debug)]
pub(super) enum Scatterer {
    Surface {
        material: Material,
        frame: Frame,
        /// The geometric normal as modelled.
        ng: Vec3,
        wo_local: Vec3,
    },
    Medium {
        phase: HenyeyGreenstein,
        wo: Vec3,
        /// The extinction the weights take for the point's density as a vertex: the mean of
        /// σt's channels there (see [`Scatterer::measure`]).
        extinction: f32,
        /// The largest channel's single-scattering albedo σs/σt.
        albedo: f32,
    },
}

/// A direction a subpath goes on in from a vertex.
pub(super) struct Scattered {
    pub wi: Vec3,
    /// f · cos / pdf (the phase function's: 1).
    pub weight: Rgb,
    pub pdf: f32,
    pub specular: bool,
}

impl Scatterer {
    /// The scatterer of the surface at `hit` seen from `wo`, for a subpath of wavelengths
    /// `lambda` (updated as the material requires: a dispersive glass ends all but the hero).
    pub fn at_surface(scene: &Scene, hit: &Hit, wo: Vec3, lambda: &mut Lambda) -> Self {
        let (material, frame) = scene.surface(hit, wo, lambda);
        Scatterer::Surface {
            material,
            frame,
            ng: hit.ng,
            wo_local: frame.to_local(wo),
        }
    }

    /// f(wo, wi) in `mode` for the world direction `wi`, with the densities (per solid angle,
    /// before Russian roulette) of sampling `wi` from `wo` and `wo` from `wi`.
    #[inline]
    pub fn eval(&self, wi: Vec3, mode: TransportMode) -> (Rgb, f32, f32) {
        match self {
            Scatterer::Surface {
                material,
                frame,
                wo_local,
                ..
            } => {
                let wi_local = frame.to_local(wi);
                let f = material.eval(*wo_local, wi_local, mode);
                if f == Rgb::ZERO {
                    return (f, 0.0, 0.0);
                }
                (
                    f,
                    material.pdf(*wo_local, wi_local),
                    material.pdf(wi_local, *wo_local),
                )
            }
            Scatterer::Medium { phase, wo, .. } => {
                let p = phase.eval(*wo, wi);
                (Rgb::splat(p), p, p)
            }
        }
    }

    /// The factor that turns a density per solid angle of directions along `w` at this
    /// vertex into a density of the vertex in its own measure (over the squared distance):
    /// |w·ng| per unit area on a surface. In a medium, the density per unit volume also takes
    /// the extinction there and the transmittance up to it; the weights use the mean σt and
    /// leave the transmittance out. MIS weights need only be the same function of the path for
    /// every technique (Veach 1997, §9.2), and these are, so the estimate stays unbiased.
    #[inline]
    pub fn measure(&self, w: Vec3) -> f32 {
        match self {
            Scatterer::Surface { ng, .. } => w.dot(*ng).abs(),
            Scatterer::Medium { extinction, .. } => *extinction,
        }
    }

    /// The cosine the camera side's contribution takes for light arriving along `w`: |w·ns|
    /// on a surface; none in a medium.
    #[inline]
    pub fn shading_cosine(&self, w: Vec3) -> f32 {
        match self {
            Scatterer::Surface { frame, .. } => w.dot(frame.n).abs(),
            Scatterer::Medium { .. } => 1.0,
        }
    }

    /// Whether a connection or merge can reach this vertex (a delta lobe alone cannot).
    pub fn has_density(&self) -> bool {
        match self {
            Scatterer::Surface { material, .. } => material.lobes().has_density(),
            Scatterer::Medium { .. } => true,
        }
    }

    /// Sample the direction a subpath goes on in.
    pub fn sample(&self, mode: TransportMode, rng: &mut impl Sampler) -> Option<Scattered> {
        let u_lobe = rng.next_f32();
        let u = rng.next_2d();
        match self {
            Scatterer::Surface {
                material,
                frame,
                wo_local,
                ..
            } => {
                let s = material.sample(*wo_local, u_lobe, u, mode)?;
                Some(Scattered {
                    wi: frame.to_world(s.wi),
                    weight: s.weight,
                    pdf: s.pdf,
                    specular: s.is_specular(),
                })
            }
            Scatterer::Medium { phase, wo, .. } => {
                let s = phase.sample(*wo, u);
                (s.pdf > 0.0).then_some(Scattered {
                    wi: s.wi,
                    weight: Rgb::ONE,
                    pdf: s.pdf,
                    specular: false,
                })
            }
        }
    }
}

/// The scatterer at a scattering point `p` of `medium`, seen from `wo`, with the pass's
/// wavelengths `lambda`.
pub(super) fn medium_scatterer(
    scene: &Scene,
    medium: MediumId,
    p: Vec3,
    wo: Vec3,
    lambda: &Lambda,
) -> Scatterer {
    let m = scene.medium(medium);
    let at = m.at(lambda);
    let sigma_t = at.sigma_t_at(p);
    let c = at.coefficients();
    let albedo = Rgb::select(
        c.sigma_t().cmpgt(Rgb::ZERO),
        c.sigma_s / c.sigma_t(),
        Rgb::ZERO,
    );
    Scatterer::Medium {
        phase: *m.phase(),
        wo,
        extinction: ((sigma_t.x + sigma_t.y + sigma_t.z) / 3.0).max(1e-8),
        albedo: albedo.max_element().clamp(0.0, 1.0),
    }
}

/// The ray that continues a subpath from `site` in direction `wi`, with the medium it runs in.
pub(super) fn ray_from(scene: &Scene, site: &Site, wi: Vec3) -> (Ray, Option<MediumId>) {
    let (origin, medium) = site.leave(scene, wi);
    (Ray::new(origin, wi), medium)
}
