//! Vertex connection and merging (Georgiev, Křivánek, Davidovič and Slusallek, "Light
//! Transport Simulation with Vertex Connection and Merging", 2012), with bidirectional path
//! tracing and light tracing as modes of the same code, as in SmallVCM.
//!
//! A pass traces one light subpath per few pixels ([`VcmMode::pixels_per_light_subpath`])
//! and keeps its vertices on surfaces with a density (delta lobes cannot be connected to or merged at).
//! Then every pixel's camera subpath, at each such vertex of its own:
//! - samples a light (next-event estimation: a light subpath of one vertex);
//! - connects to every vertex of the pixel's light subpath (pixel i's is subpath i mod N,
//!   for N subpaths: the pixels that share one lie N pixels apart, a quarter of the image);
//! - merges with the light vertices of all subpaths within the pass's radius (photon
//!   density estimation, the radius shrinking over passes as in probabilistic PPM);
//! - and counts the emission it hits.
//!
//! Light vertices also connect to the camera (light tracing), splatting into whichever pixel
//! sees them. Every technique is weighed against all the others that could have made the
//! same path by the power heuristic, evaluated recursively from three quantities carried
//! along each subpath ([`PathMis`]: Georgiev's dVCM, dVC and dVM, from the technical report
//! "Implementing Vertex Connection and Merging", 2012).
//!
//! Participating media add vertices at scattering points, with the phase function for a
//! BSDF and volume for area (see [`site`]): they are connected like surface vertices and
//! merged with the light vertices within the radius in 3D, normalised by the ball's volume
//! (volumetric photon mapping's point estimate, Jensen and Christensen 1998). Distances in
//! media are drawn with one hero channel per pass for both subpaths, and every contribution
//! takes the spectral MIS factor of the whole path's channel densities (see
//! [`crate::medium`]).
//!
//! Conventions:
//! - A subpath's *depth* is its number of segments; its vertex at depth k is its k-th
//!   scattering vertex. A full path has at most `max_depth` scattering vertices.
//! - Every density conversion between solid angle and area uses geometric cosines; BSDFs
//!   use shading normals, with the adjoint correction on light subpaths (Veach 1997, §5.3).
//! - Russian roulette continues a subpath at a vertex with a probability set by its material
//!   alone ([`continuation`]), the same in both directions, so that the densities every
//!   technique computes for a path agree and the weights sum to one.
//! - The merging radius is the same at every vertex of a pass: r_p = r_0 · s_p with PPM's
//!   schedule ([`crate::progressive::state::ppm_radius_scale`]).

mod camera_path;
mod light_path;
mod site;

pub use camera_path::camera_sample;
pub use light_path::{LightSubpaths, trace_light_subpaths};

use crate::camera::Camera;
use crate::material::{Material, TransportMode};
use crate::math::{Rgb, Vec3};
use crate::medium::MediumId;
use crate::photon::grid::{Located, PhotonGrid, QueryScratch};
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::Lambda;
use site::{Scattered, Scatterer, Site};
use std::f32::consts::PI;

/// Which techniques a pass uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VcmMode {
    /// Connections and merging: every technique.
    Vcm,
    /// Connections only: bidirectional path tracing (Veach 1997; Lafortune and Willems 1993).
    Bdpt,
    /// Light subpaths connected to the camera, and camera paths only for the emission seen
    /// directly or through delta lobes: light tracing (Arvo 1986, Dutré et al. 1993).
    LightTrace,
}

impl VcmMode {
    pub fn connects(self) -> bool {
        self != VcmMode::LightTrace
    }

    pub fn merges(self) -> bool {
        self == VcmMode::Vcm
    }

    /// Pixels per light subpath of a pass. SmallVCM traces one per pixel. Every camera
    /// subpath still connects to one light subpath, and the weights count the light subpaths
    /// a pass really has (light tracing's and merging's N), so any number is unbiased.
    /// Fewer make a pass cheaper (its merges and light tracing): at equal time one per four
    /// pixels measured 1.2–1.6× lower relMSE than one per pixel for `vcm` on the diffuse and
    /// glossy Cornell boxes, a door ajar and a lamp shade, and the same on a caustic seen in a
    /// mirror; one per eight lost again on the diffuse box. Light tracing has no other
    /// samples, so it keeps one per pixel.
    pub fn pixels_per_light_subpath(self) -> u32 {
        match self {
            VcmMode::Vcm | VcmMode::Bdpt => 4,
            VcmMode::LightTrace => 1,
        }
    }
}

/// Everything fixed for one pass.
pub struct PassContext<'a> {
    pub scene: &'a Scene,
    pub camera: &'a Camera,
    pub mode: VcmMode,
    /// Most scattering vertices on a full path.
    pub max_depth: u32,
    /// The pass's wavelengths, shared by its camera and light subpaths.
    pub lambda: Lambda,
    /// Light subpaths traced: one per [`VcmMode::pixels_per_light_subpath`] pixels.
    pub light_paths: u32,
    /// Merging radius.
    pub radius: f32,
    /// The channel both subpaths draw distances in media with (see [`crate::medium`]).
    pub hero: usize,
    /// Merging against connecting at a vertex on a surface.
    surface: MergeFactors,
    /// The same at a vertex in a medium.
    volume: MergeFactors,
}

/// How merging at a vertex weighs against the other techniques: η_VCM, the kernel's measure
/// times the light paths (π r² · N on a surface, 4/3 π r³ · N in a medium).
#[derive(Clone, Copy, Debug)]
struct MergeFactors {
    /// η_VCM raised to the heuristic's power (0 when not merging).
    mis_vm: f32,
    /// The inverse, for connections against merging (0 when not merging or not connecting).
    mis_vc: f32,
    /// 1 / η_VCM: a merge's density-estimation normalisation.
    normalization: f32,
}

impl MergeFactors {
    fn new(mode: VcmMode, eta: f32) -> Self {
        Self {
            mis_vm: if mode.merges() { mis(eta) } else { 0.0 },
            mis_vc: if mode.merges() && mode.connects() {
                mis(1.0 / eta)
            } else {
                0.0
            },
            normalization: 1.0 / eta,
        }
    }
}

impl<'a> PassContext<'a> {
    pub fn new(
        scene: &'a Scene,
        camera: &'a Camera,
        mode: VcmMode,
        max_depth: u32,
        lambda: Lambda,
        radius: f32,
        hero: usize,
    ) -> Self {
        let light_paths = (camera.width * camera.height).div_ceil(mode.pixels_per_light_subpath());
        let n = light_paths as f32;
        Self {
            scene,
            camera,
            mode,
            max_depth,
            lambda,
            light_paths,
            radius,
            hero,
            surface: MergeFactors::new(mode, PI * radius * radius * n),
            volume: MergeFactors::new(mode, 4.0 / 3.0 * PI * radius * radius * radius * n),
        }
    }

    /// The merge factors of a vertex with this scatterer.
    fn merge_factors(&self, s: &Scatterer) -> &MergeFactors {
        match s {
            Scatterer::Surface { .. } => &self.surface,
            Scatterer::Medium { .. } => &self.volume,
        }
    }
}

/// The power heuristic's exponent β = 2 applied to a density or a ratio of densities.
#[inline]
fn mis(x: f32) -> f32 {
    x * x
}

/// Georgiev's recursive quantities of a subpath at its last vertex: from them and the local
/// densities of a connection or merge, the sum over every other technique of its density
/// (to the power β) relative to the one used.
///
/// Georgiev's third quantity, dVM (for merges), is dVC / η_VCM of the vertex merged at:
/// both sum the same techniques further back, each merge there with its own vertex's η (a
/// surface's or a medium's), relative to a connection. Keeping dVC alone lets η differ from
/// vertex to vertex.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PathMis {
    /// dVCM: the technique that would sample this vertex from the other side.
    vcm: f32,
    /// dVC: the connections and merges further back.
    vc: f32,
}

impl PathMis {
    /// Arrive at a vertex over a segment of length² `dist2` whose direction makes the
    /// factor `measure` there (the geometric cosine, or the extinction in a medium: see
    /// [`Scatterer::measure`]); `count_distance`: false only for the first segment from a
    /// light at infinity, which starts on a disc, not at a point.
    fn arrive(&mut self, dist2: f32, measure: f32, count_distance: bool) {
        if count_distance {
            self.vcm *= mis(dist2);
        }
        let inv = 1.0 / mis(measure.max(1e-8));
        self.vcm *= inv;
        self.vc *= inv;
    }

    /// Leave a vertex (whose merges weigh `m`) by a sampled direction: the vertex's measure
    /// factor `measure_out` for the direction, densities `pdf_forward` (of sampling it) and
    /// `pdf_reverse` (of sampling the arrival direction from it), both with the continuation
    /// probability.
    fn scatter(&mut self, m: &MergeFactors, measure_out: f32, pdf_forward: f32, pdf_reverse: f32) {
        let g = mis(measure_out / pdf_forward);
        self.vc = g * (self.vc * mis(pdf_reverse) + self.vcm + m.mis_vm);
        self.vcm = mis(1.0 / pdf_forward);
    }

    /// Leave by a delta lobe: no technique can connect or merge at this vertex, and the
    /// forward and reverse probabilities cancel.
    fn scatter_specular(&mut self, cos_out: f32) {
        self.vcm = 0.0;
        self.vc *= mis(cos_out);
    }
}

/// A subpath's next direction from a vertex with scatterer `s`: a lobe (or the phase
/// function) sampled in `mode`, then Russian roulette with the vertex's continuation
/// probability `q`, and the subpath's MIS quantities carried over the scattering. `None`
/// where the subpath ends.
fn continue_subpath(
    ctx: &PassContext,
    s: &Scatterer,
    q: f32,
    mode: TransportMode,
    rng: &mut impl Sampler,
    path_mis: &mut PathMis,
) -> Option<Scattered> {
    let sampled = s.sample(mode, rng)?;
    if rng.next_f32() >= q {
        return None;
    }
    let measure_out = s.measure(sampled.wi);
    if sampled.specular {
        path_mis.scatter_specular(measure_out);
    } else {
        let (_, _, reverse) = s.eval(sampled.wi, mode);
        path_mis.scatter(
            ctx.merge_factors(s),
            measure_out,
            sampled.pdf * q,
            reverse * q,
        );
    }
    Some(sampled)
}

/// The probability that a subpath goes on from a vertex with scatterer `s`, a property of
/// the vertex alone, so that the reverse density of a vertex equals the forward one of the
/// subpath from the other side: on a surface, its material's albedo at normal incidence (at
/// most 1; glass always continues, its reflection and refraction together keeping almost all
/// light); in a medium, its largest channel's single-scattering albedo, at most
/// [`MEDIUM_CONTINUATION`].
fn continuation(s: &Scatterer) -> f32 {
    match s {
        Scatterer::Surface { material, .. } => surface_continuation(material),
        Scatterer::Medium { albedo, .. } => albedo.min(MEDIUM_CONTINUATION),
    }
}

/// The most a subpath continues with in a medium: without a bound, a subpath in a medium
/// that does not absorb would wander to the depth limit.
const MEDIUM_CONTINUATION: f32 = 0.95;

fn surface_continuation(m: &Material) -> f32 {
    if m.encloses_volume() {
        return 1.0;
    }
    m.albedo(Vec3::Z).max_element().clamp(0.0, 1.0)
}

/// |w·ns| / |w·ng| for the arrival direction `w` at a light vertex: the shading irradiance
/// per unit of the subpath's geometric flux density (Veach 1997, §5.3); zero at a grazing
/// geometric angle.
fn shading_ratio(w: Vec3, ns: Vec3, ng: Vec3) -> f32 {
    let g = w.dot(ng).abs();
    if g > 0.0 { w.dot(ns).abs() / g } else { 0.0 }
}

/// A vertex of a light subpath on a surface with a density, or in a medium.
#[derive(Clone, Copy, Debug)]
pub struct LightVertex {
    site: Site,
    /// Unit direction toward the previous vertex (where its light came from).
    wo: Vec3,
    /// The subpath's throughput here, times [`shading_ratio`] of `wo`: what a BSDF at this
    /// vertex multiplies.
    beta: Rgb,
    mis: PathMis,
    /// [`continuation`] of the vertex's material.
    continuation: f32,
    /// Segments from the light.
    depth: u32,
    /// The wavelengths as the subpath arrived (before this vertex's material).
    lambda_in: Lambda,
    /// Whether the subpath goes on with its hero wavelength alone after this vertex.
    hero_only: bool,
    /// Each channel's density of the subpath's distances in media over the hero's.
    ratio: Rgb,
}

impl LightVertex {
    /// What scatters light at the vertex, and its wavelengths after it.
    fn scatterer(&self, ctx: &PassContext) -> Scatterer {
        match &self.site {
            Site::Surface { hit, .. } => {
                let mut lambda = self.lambda_in;
                Scatterer::at_surface(ctx.scene, hit, self.wo, &mut lambda)
            }
            Site::Medium { p, medium } => {
                site::medium_scatterer(ctx.scene, *medium, *p, self.wo, &ctx.lambda)
            }
        }
    }
}

/// What merging reads of a light vertex, kept in the grid's buckets so that a search reads
/// contiguous memory (a whole [`LightVertex`] is 2.5× larger, and reading it at random was
/// most of a pass).
#[derive(Clone, Copy, Debug, Default)]
pub struct MergeVertex {
    position: Vec3,
    /// Toward the previous vertex.
    wo: Vec3,
    /// The geometric normal on the side of `wo`; zero in a medium.
    ng: Vec3,
    /// The medium the vertex is in; [`ON_SURFACE`] for a vertex on a surface.
    medium: MediumId,
    /// The subpath's throughput, without σs at the vertex in a medium (the camera subpath's
    /// has it).
    beta: Rgb,
    ratio: Rgb,
    vcm: f32,
    vc: f32,
    continuation: f32,
    depth: u32,
    hero_only: bool,
}

/// [`MergeVertex::medium`] of a vertex on a surface.
const ON_SURFACE: MediumId = MediumId::MAX;

impl MergeVertex {
    /// Whether the vertex is in the medium `id`.
    fn in_medium(&self, id: MediumId) -> bool {
        self.medium == id
    }
}

impl Located for MergeVertex {
    #[inline]
    fn location(&self) -> Vec3 {
        self.position
    }
}

/// The pass's light vertices in a hashed grid for merging: cells twice the radius wide, so a
/// query visits at most 8 cells.
pub struct VertexGrid {
    grid: PhotonGrid<MergeVertex>,
    radius: f32,
}

impl VertexGrid {
    pub fn new(ctx: &PassContext, vertices: &[LightVertex], radius: f32) -> Self {
        let entries = vertices
            .iter()
            .map(|v| MergeVertex {
                position: v.site.p(),
                wo: v.wo,
                ng: match &v.site {
                    Site::Surface { hit, .. } => hit.ng_facing(v.wo),
                    Site::Medium { .. } => Vec3::ZERO,
                },
                medium: match &v.site {
                    Site::Surface { .. } => ON_SURFACE,
                    Site::Medium { medium, .. } => *medium,
                },
                beta: match &v.site {
                    Site::Surface { .. } => v.beta,
                    Site::Medium { p, medium } => {
                        let sigma_s = ctx.scene.medium(*medium).at(&ctx.lambda).sigma_s_at(*p);
                        Rgb::select(sigma_s.cmpgt(Rgb::ZERO), v.beta / sigma_s, Rgb::ZERO)
                    }
                },
                ratio: v.ratio,
                vcm: v.mis.vcm,
                vc: v.mis.vc,
                continuation: v.continuation,
                depth: v.depth,
                hero_only: v.hero_only,
            })
            .collect();
        Self {
            grid: PhotonGrid::build(entries, 2.0 * radius),
            radius,
        }
    }

    /// Calls `visit` with every vertex within the radius of `p` and its distance², in a fixed
    /// order.
    fn for_each_near(
        &self,
        p: Vec3,
        scratch: &mut QueryScratch,
        mut visit: impl FnMut(&MergeVertex, f32),
    ) {
        self.grid
            .for_each_within(p, self.radius, scratch, &mut |v, d2| visit(v, d2));
    }

    /// The radius² merges are made within.
    fn radius2(&self) -> f32 {
        self.radius * self.radius
    }
}

/// The spectral MIS factor of a path made of a camera subpath and a light subpath whose
/// channel densities over the hero's are `camera` and `light` (1 without media).
#[inline]
fn spectral_weight(camera: Rgb, light: Rgb) -> f32 {
    crate::medium::spectral_mis(camera * light)
}

/// The factor for the product of a camera and a light subpath's values: 1/3 where both went
/// on with their hero wavelength alone, which each side tripled (see `Lambda::keep_hero_only`).
fn hero_tripled_once(camera_hero_only: bool, light_hero_only: bool) -> f32 {
    if camera_hero_only && light_hero_only {
        1.0 / 3.0
    } else {
        1.0
    }
}
