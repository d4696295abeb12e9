//! Scene descriptions: what a scene file says, before it becomes a [`Scene`].
//!
//! A [`SceneDesc`] is the one data model behind every way of getting a scene: the built-in
//! scenes are written as descriptions in code, `.toml` files are read into one
//! ([`toml_read`]), any description can be written back as TOML ([`toml_write`]), and glTF files
//! are imported as one ([`gltf`]). [`build`] turns a description into a renderable [`Scene`],
//! reading the mesh and texture files it names. Because built-ins and files share that one
//! path, a built-in exported as TOML and read back renders to the identical image.

pub mod build;
pub mod builtin;
pub mod environment;
pub mod gltf;
pub mod mesh;
pub mod source;
pub mod toml_read;
pub mod toml_write;

pub use build::load_mesh_file;

use crate::error::{Error, Result};
use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::{Scene, TriangleMesh};
use glam::{Affine3A, Mat4, Quat};
use std::path::{Path, PathBuf};

/// Everything a scene file can say.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDesc {
    pub name: String,
    pub camera: CameraSpec,
    pub render: crate::settings::RenderOptions,
    /// Named materials, in file order (the order fixes material indices, hence images).
    pub materials: Vec<(String, MaterialSpec)>,
    pub shapes: Vec<ShapeSpec>,
    pub lights: Vec<LightSpec>,
    /// Named participating media, in file order.
    pub media: Vec<(String, MediumSpec)>,
    /// The medium that fills the scene around its shapes (the camera and the lights are in
    /// it); `None`: vacuum.
    pub medium: Option<String>,
    /// Directory that relative file names are resolved against.
    pub base_dir: PathBuf,
    /// Where the camera, shapes and lights were written, for messages from the scene build.
    pub origins: source::Origins,
    /// The warning that says the scene is lit by a sky the importer added (a glTF file
    /// without enough light of its own). It stands in the loader's warnings while that sky
    /// does: [`SceneDesc::set_environment`] clears it.
    pub default_sky_warning: Option<String>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
    pub width: u32,
    pub height: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum MaterialSpec {
    /// Lambertian with a constant or textured albedo.
    Diffuse {
        albedo: ColorSpec,
    },
    Mirror {
        reflectance: Rgb,
    },
    /// Dielectric: smooth (`alpha` 0: Fresnel reflection and refraction) or rough (GGX),
    /// absorbing inside by `attenuation` (`None`: clear), its index varying with wavelength
    /// by `dispersion` (then `ior` is the index at the d line).
    Glass {
        ior: f32,
        transmittance: Rgb,
        alpha: f32,
        attenuation: Option<crate::material::Attenuation>,
        dispersion: crate::material::Dispersion,
    },
    /// GGX metal; `alpha` along the shading frame's two tangents (equal: isotropic).
    Conductor {
        fresnel: ConductorSpec,
        alpha: [f32; 2],
    },
    /// The glTF 2.0 metallic-roughness material.
    Pbr(PbrSpec),
}

/// A participating medium: absorption and scattering coefficients per scene unit of length,
/// per channel (per unit of density when a grid gives the density), and the
/// Henyey–Greenstein asymmetry of its scattering.
#[derive(Clone, Debug, PartialEq)]
pub struct MediumSpec {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    /// In (−1, 1): −1 back, 0 isotropic, 1 forward.
    pub g: f32,
    /// The density, when it varies: a voxel grid from a file.
    pub grid: Option<GridSpec>,
}

/// A density grid in a file (`.vdb` or `.vol`, relative to the scene), the name of its grid
/// (OpenVDB files hold several), and where to put it: `transform` applies after the file's
/// own placement (OpenVDB's index-to-world map; the unit cube for `.vol`).
#[derive(Clone, Debug, PartialEq)]
pub struct GridSpec {
    pub file: PathBuf,
    pub name: String,
    pub transform: Vec<TransformStep>,
}

/// How a conductor reflects: a named metal, a complex index of refraction, or an F0 colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConductorSpec {
    Metal(crate::material::Metal),
    Ior { eta: Rgb, k: Rgb },
    F0(Rgb),
}

/// glTF's metallic-roughness parameters and textures.
#[derive(Clone, Debug, PartialEq)]
pub struct PbrSpec {
    pub base_color: ColorSpec,
    pub metallic: f32,
    /// Perceptual: GGX α = roughness².
    pub roughness: f32,
    /// `KHR_materials_specular`'s factor: scales the dielectric coat (1: the plain glTF model,
    /// 0: a dielectric without a coat, diffuse only).
    pub specular: f32,
    /// Linear texture: blue multiplies `metallic`, green `roughness`.
    pub metallic_roughness: Option<ImageRef>,
    /// Tangent-space normal map and the scale of its x and y.
    pub normal_map: Option<(ImageRef, f32)>,
    /// Where the surface is there (glTF's `alphaMode`): opaque, cut out or blended.
    pub coverage: crate::scene::Coverage,
}

/// An image a material or emitter names: a file, or one already decoded. Colour images
/// (emission) are read as sRGB, data (metallic-roughness, normal maps) as linear values.
#[derive(Clone, Debug, PartialEq)]
pub enum ImageRef {
    File(PathBuf),
    /// Already in memory (glTF embedded images); never written to TOML.
    Decoded(SharedTexture),
}

/// Light from every direction (see [`crate::light::EnvironmentLight`]).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentSpec {
    pub sky: Sky,
    /// Multiplies the sky.
    pub intensity: f32,
    /// Degrees about +y.
    pub rotate_deg: f32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Sky {
    /// Uniform radiance, W·m⁻²·sr⁻¹.
    Uniform(Rgb),
    /// An equirectangular image (OpenEXR, Radiance HDR or PFM), linear radiance.
    File(PathBuf),
}

/// A colour: constant, or a texture (times a constant tint).
#[derive(Clone, Debug, PartialEq)]
pub enum ColorSpec {
    Constant(Rgb),
    Image {
        file: PathBuf,
        tint: Rgb,
    },
    /// An image already in memory (glTF embedded textures); never written to TOML.
    Decoded {
        texture: SharedTexture,
        tint: Rgb,
    },
    Checker {
        even: Rgb,
        odd: Rgb,
        scale: Vec2,
    },
}

/// A decoded texture shared between materials, with how this use of it is mapped; equal
/// when it is the same allocation mapped the same way.
#[derive(Clone, Debug)]
pub struct SharedTexture {
    pub image: std::sync::Arc<crate::texture::ImageTexture>,
    pub mapping: crate::texture::UvMapping,
}

impl PartialEq for SharedTexture {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.image, &other.image) && self.mapping == other.mapping
    }
}

/// Light leaving a surface, given as radiance or as total power.
#[derive(Clone, Debug, PartialEq)]
pub enum EmissionSpec {
    /// W·m⁻²·sr⁻¹ per channel, times an sRGB `texture` where there is one.
    Radiance {
        radiance: Rgb,
        two_sided: bool,
        texture: Option<ImageRef>,
        /// The colour as a spectrum (then `radiance` is grey: its brightness).
        spectrum: Option<LightSpectrum>,
    },
    /// Total flux, W per channel, spread evenly over the surface.
    Power {
        power: Rgb,
        two_sided: bool,
        /// The colour as a spectrum (then `power` is grey: its brightness).
        spectrum: Option<LightSpectrum>,
    },
}

/// A light's colour given as a spectrum rather than RGB: a blackbody of a temperature, or a
/// CIE standard illuminant. Each is normalised to luminance 1, so the light's intensity,
/// power, irradiance or radiance (then one number) is its brightness, as for white RGB light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSpectrum {
    /// Planck's law at this temperature in kelvin.
    Blackbody(f32),
    /// CIE illuminant D65 (daylight; the white of sRGB).
    D65,
    /// CIE illuminant A (incandescent, 2856 K).
    A,
}

impl LightSpectrum {
    /// Temperatures accepted: the CIE's Planckian locus is tabulated from 1000 K; above
    /// 40 000 K the colour no longer changes visibly.
    pub const KELVIN: std::ops::RangeInclusive<f32> = 1000.0..=40_000.0;

    /// By name: `D65`, `A` (any case).
    pub fn named(name: &str) -> Option<Self> {
        match name.to_ascii_uppercase().as_str() {
            "D65" => Some(LightSpectrum::D65),
            "A" => Some(LightSpectrum::A),
            _ => None,
        }
    }

    /// The spectrum times `brightness`.
    pub fn spectrum(self, brightness: f32) -> crate::spectrum::Spectrum {
        use crate::spectrum::Spectrum;
        let shape = match self {
            LightSpectrum::Blackbody(k) => Spectrum::blackbody(k),
            LightSpectrum::D65 => Spectrum::named("D65").expect("D65 is built in"),
            LightSpectrum::A => Spectrum::named("A").expect("A is built in"),
        };
        shape.scaled(brightness)
    }
}

/// One step of an object's placement. A list of steps applies first to last.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TransformStep {
    Translate(Vec3),
    /// Rotation by `degrees` about `axis` (right-handed).
    Rotate {
        axis: Vec3,
        degrees: f32,
    },
    Scale(Vec3),
    /// A 4×4 matrix, row-major, last row (0, 0, 0, 1).
    Matrix([f32; 16]),
    /// Places the object at `from` with its +z axis toward `to` and +y toward `up`.
    LookAt {
        from: Vec3,
        to: Vec3,
        up: Vec3,
    },
}

impl TransformStep {
    pub fn to_affine(&self) -> Affine3A {
        match *self {
            TransformStep::Translate(t) => Affine3A::from_translation(t),
            TransformStep::Rotate { axis, degrees } => Affine3A::from_quat(Quat::from_axis_angle(
                axis.normalize_or(Vec3::Z),
                degrees.to_radians(),
            )),
            TransformStep::Scale(s) => Affine3A::from_scale(s),
            TransformStep::Matrix(m) => Affine3A::from_mat4(Mat4::from_cols_array(&m).transpose()),
            TransformStep::LookAt { from, to, up } => {
                let z = (to - from).normalize_or(Vec3::Z);
                let x = up.cross(z).normalize_or(z.any_orthonormal_vector());
                let y = z.cross(x);
                Affine3A::from_cols(x.into(), y.into(), z.into(), from.into())
            }
        }
    }
}

/// The composed object-to-world transform of a list of steps.
pub fn compose(steps: &[TransformStep]) -> Affine3A {
    steps
        .iter()
        .fold(Affine3A::IDENTITY, |acc, s| s.to_affine() * acc)
}

#[derive(Clone, Debug, PartialEq)]
pub enum ShapeKind {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    Disk {
        center: Vec3,
        normal: Vec3,
        radius: f32,
    },
    /// Planar quad; front side is where the vertices run counter-clockwise.
    Quad {
        vertices: [Vec3; 4],
    },
    /// Axis-aligned box with outward faces (transform it to turn it).
    Box {
        min: Vec3,
        max: Vec3,
    },
    /// Triangles given in the file itself.
    Triangles(TriangleMesh),
    /// A mesh file: .obj, .ply, .gltf or .glb.
    MeshFile {
        file: PathBuf,
        /// Interpolate the file's vertex normals (when it has them).
        smooth: bool,
    },
    /// The procedural plant pot (lathe, solidify, Catmull–Clark, NURBS leaves).
    Pot {
        subdivisions: u32,
        seed: u64,
        soil_material: Option<String>,
        leaf_material: Option<String>,
    },
}

/// A shape with its material, placement and optional emission.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeSpec {
    pub kind: ShapeKind,
    /// Material name; `None` on an area light (black), a mesh file (its own materials) or an
    /// invisible boundary of a medium.
    pub material: Option<String>,
    pub transform: Vec<TransformStep>,
    pub emission: Option<EmissionSpec>,
    /// The media the shape separates, if it bounds any.
    pub media: Option<MediaSides>,
}

impl ShapeSpec {
    /// A shape with an interior medium and neither material nor emission: it only marks
    /// where the medium ends (see [`crate::medium::Boundary`]).
    pub fn is_invisible_boundary(&self) -> bool {
        self.material.is_none()
            && self.emission.is_none()
            && self.media.as_ref().is_some_and(|m| m.interior.is_some())
    }
}

/// The media on the two sides of a closed shape, by name. Outside defaults to the scene's
/// medium.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MediaSides {
    pub interior: Option<String>,
    pub exterior: Option<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum LightSpec {
    /// Isotropic point light; `intensity` in W/sr (power = 4π·intensity).
    Point {
        position: Vec3,
        intensity: Intensity,
        /// The colour as a spectrum (then the intensity is grey: its brightness).
        spectrum: Option<LightSpectrum>,
    },
    Spot {
        position: Vec3,
        look_at: Vec3,
        intensity: Intensity,
        /// Half-angle of the cone, degrees.
        angle_deg: f32,
        /// Width of the soft edge inside the cone, degrees.
        falloff_deg: f32,
        spectrum: Option<LightSpectrum>,
    },
    /// Light from one direction (the sun): irradiance in W/m² on a surface facing it.
    Directional {
        direction: Vec3,
        irradiance: Rgb,
        spectrum: Option<LightSpectrum>,
    },
    /// An emissive shape (disk, quad, sphere, mesh …).
    Area(Box<ShapeSpec>),
    /// The sky: light from every direction, at most one per scene.
    Environment(EnvironmentSpec),
}

/// How bright a point or spot light is: intensity in W/sr, or total power in W.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Intensity {
    Intensity(Rgb),
    Power(Rgb),
}

impl SceneDesc {
    /// An empty scene seen by `camera`; relative paths resolve against the working directory.
    pub fn new(name: &str, camera: CameraSpec) -> Self {
        Self {
            name: name.to_owned(),
            camera,
            render: crate::settings::RenderOptions::default(),
            materials: Vec::new(),
            shapes: Vec::new(),
            lights: Vec::new(),
            media: Vec::new(),
            medium: None,
            base_dir: PathBuf::new(),
            origins: source::Origins::default(),
            default_sky_warning: None,
        }
    }

    /// Add a named material; returns its name for use in shapes.
    /// The scene's environment light, if it has one.
    pub fn environment_mut(&mut self) -> Option<&mut EnvironmentSpec> {
        self.lights.iter_mut().find_map(|l| match l {
            LightSpec::Environment(e) => Some(e),
            _ => None,
        })
    }

    /// Add an environment light, replacing the scene's own if it has one.
    pub fn set_environment(&mut self, e: EnvironmentSpec) {
        self.default_sky_warning = None;
        self.lights
            .retain(|l| !matches!(l, LightSpec::Environment(_)));
        self.lights.push(LightSpec::Environment(e));
    }

    pub fn material(&mut self, name: &str, spec: MaterialSpec) -> String {
        self.materials.push((name.to_owned(), spec));
        name.to_owned()
    }

    /// Add a diffuse material of constant albedo.
    pub fn diffuse(&mut self, name: &str, albedo: [f32; 3]) -> String {
        self.material(
            name,
            MaterialSpec::Diffuse {
                albedo: ColorSpec::Constant(Rgb::from_array(albedo)),
            },
        )
    }

    /// Add an untransformed, non-emitting shape.
    pub fn shape(&mut self, kind: ShapeKind, material: &str) {
        self.shapes.push(ShapeSpec {
            kind,
            material: Some(material.to_owned()),
            transform: Vec::new(),
            emission: None,
            media: None,
        });
    }
}

/// Where a scene came from and what the loader could not map.
pub struct Loaded {
    pub desc: SceneDesc,
    /// One message per kind of thing that was not imported.
    pub warnings: Vec<String>,
    /// Mesh files the loader already read (a glTF scene's own meshes), for [`build::build_with`].
    pub meshes: mesh::MeshCache,
}

/// Load a scene: a built-in name, or a `.toml`, `.gltf` or `.glb` file.
pub fn load(name_or_path: &str) -> Result<Loaded> {
    if let Some(desc) = builtin::desc(name_or_path) {
        return Ok(Loaded {
            desc,
            warnings: Vec::new(),
            meshes: mesh::MeshCache::new(),
        });
    }
    let path = Path::new(name_or_path);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("toml") => Ok(Loaded {
            desc: toml_read::read_file(path)?,
            warnings: Vec::new(),
            meshes: mesh::MeshCache::new(),
        }),
        Some("gltf" | "glb") => gltf::import_scene(path),
        _ if path.exists() => Err(Error::SceneFile(Box::new(source::Diagnostic::whole_file(
            path,
            "unsupported scene file; expected a .toml, .gltf or .glb file (put .obj and .ply meshes in a .toml scene)",
        )))),
        _ => Err(builtin::unknown(name_or_path)),
    }
}

/// Load and build a scene, returning it with the description (for its render settings) and
/// the loader's warnings.
///
/// A scene read from a file is named by the file's absolute path, which is what checkpoints
/// and photon-map files record to find it again.
pub fn load_scene(name_or_path: &str) -> Result<(Scene, Loaded)> {
    load_scene_edited(name_or_path, |_| Ok(()))
}

/// [`load_scene`] with the environment light `env` gives or changes (see [`environment`]);
/// its warning, if any, is among the loaded warnings.
pub fn load_scene_with_environment(
    name_or_path: &str,
    env: &crate::io::checkpoint::EnvSettings,
) -> Result<(Scene, Loaded)> {
    let mut warning = None;
    let (scene, mut loaded) = load_scene_edited(name_or_path, |desc| {
        warning = environment::apply(desc, env)?;
        Ok(())
    })?;
    loaded.warnings.extend(warning);
    Ok((scene, loaded))
}

/// [`load_scene`], with the description changed by `edit` before it is built (the CLI's
/// `--env`).
pub fn load_scene_edited(
    name_or_path: &str,
    edit: impl FnOnce(&mut SceneDesc) -> Result<()>,
) -> Result<(Scene, Loaded)> {
    let mut loaded = load(name_or_path)?;
    let default_sky_warning = loaded.desc.default_sky_warning.clone();
    edit(&mut loaded.desc)?;
    if let Some(w) = default_sky_warning
        && loaded.desc.default_sky_warning.is_none()
    {
        // The edit gave the scene its own sky: the warning about the default one is void.
        loaded.warnings.retain(|x| *x != w);
    }
    let mut scene = build::build_with(&loaded.desc, &mut loaded.meshes)?;
    if !builtin::BUILTINS.iter().any(|b| b.name == name_or_path) {
        let path = Path::new(name_or_path);
        scene.name = std::path::absolute(path)
            .unwrap_or_else(|_| path.to_owned())
            .to_string_lossy()
            .into_owned();
    }
    Ok((scene, loaded))
}
