//! The values a render setting takes: integrators, gather modes, kernels, pixel filters,
//! ranges and numbers, each with one way to read it from text (a flag, a TOML string) and one
//! way to print it (help, errors, job manifests).

use crate::film::PixelFilter;
use crate::photon::Kernel;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A value a render setting can hold.
pub trait SettingValue: Sized + Clone + PartialEq + std::fmt::Debug {
    /// The value from its text (`--flag TEXT`, a TOML string), or what was expected.
    fn parse(text: &str) -> Result<Self, String>;
    /// The value as a user writes it.
    fn text(&self) -> String;
    /// The names a value may take, for help and errors; empty when any of its type may.
    const CHOICES: &'static [&'static str] = &[];
    /// Whether the setting is a switch (`--per-channel`) rather than `--flag VALUE`.
    const IS_SWITCH: bool = false;
    /// How help names the value (`N`, `SECONDS`, …).
    const METAVAR: &'static str = "VALUE";
}

macro_rules! number_values {
    ($($ty:ty => $metavar:literal),*) => {$(
        impl SettingValue for $ty {
            fn parse(text: &str) -> Result<Self, String> {
                text.trim()
                    .parse()
                    .map_err(|_| format!("'{text}' is not a number of the kind expected ({})", stringify!($ty)))
            }
            fn text(&self) -> String {
                self.to_string()
            }
            const METAVAR: &'static str = $metavar;
        }
    )*};
}
number_values!(u32 => "N", u64 => "N", usize => "N", f32 => "X", f64 => "X");

impl SettingValue for bool {
    fn parse(text: &str) -> Result<Self, String> {
        match text {
            "true" => Ok(true),
            "false" => Ok(false),
            _ => Err(format!("'{text}' is not true or false")),
        }
    }
    fn text(&self) -> String {
        self.to_string()
    }
    const IS_SWITCH: bool = true;
}

/// A closed set of named values: one table gives the names for parsing, printing, help and
/// serde.
macro_rules! named_values {
    ($ty:ty, $metavar:literal, [$($variant:expr => $name:literal),* $(,)?]) => {
        impl SettingValue for $ty {
            fn parse(text: &str) -> Result<Self, String> {
                match text.to_ascii_lowercase().as_str() {
                    $($name => Ok($variant),)*
                    _ => Err(format!(
                        "'{text}' is not one of {}",
                        Self::CHOICES.join(", ")
                    )),
                }
            }
            fn text(&self) -> String {
                match self {
                    $(v if *v == $variant => $name.to_owned(),)*
                    _ => unreachable!("every value is named"),
                }
            }
            const CHOICES: &'static [&'static str] = &[$($name),*];
            const METAVAR: &'static str = $metavar;
        }
        impl Serialize for $ty {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(&self.text())
            }
        }
        impl<'de> Deserialize<'de> for $ty {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let text = String::deserialize(d)?;
                <$ty>::parse(&text).map_err(serde::de::Error::custom)
            }
        }
    };
}

/// The rendering algorithms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IntegratorKind {
    /// Two-pass photon mapping: direct light, caustic map, final gathering of the global map.
    Photon,
    /// Ray-traced direct light with mirror and glass recursion; no indirect diffuse light.
    Direct,
    /// Unidirectional path tracing with NEE and MIS: the reference.
    Path,
    /// Stochastic progressive photon mapping (Hachisuka & Jensen 2009).
    Sppm,
    /// Probabilistic progressive photon mapping (Knaus & Zwicker 2011): independent passes.
    Ppm,
    /// Vertex connection and merging (Georgiev et al. 2012): bidirectional paths and photon
    /// merging under one multiple importance sampling.
    Vcm,
    /// Bidirectional path tracing: vcm's connections alone.
    Bdpt,
    /// Light tracing: vcm's light subpaths connected to the camera alone.
    LightTrace,
}

named_values!(IntegratorKind, "NAME", [
    IntegratorKind::Photon => "photon",
    IntegratorKind::Direct => "direct",
    IntegratorKind::Path => "path",
    IntegratorKind::Sppm => "sppm",
    IntegratorKind::Ppm => "ppm",
    IntegratorKind::Vcm => "vcm",
    IntegratorKind::Bdpt => "bdpt",
    IntegratorKind::LightTrace => "lighttrace",
]);

impl IntegratorKind {
    pub const ALL: [Self; 8] = [
        Self::Photon,
        Self::Direct,
        Self::Path,
        Self::Sppm,
        Self::Ppm,
        Self::Vcm,
        Self::Bdpt,
        Self::LightTrace,
    ];

    pub fn name(self) -> &'static str {
        Self::CHOICES[self as usize]
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::parse(name).ok()
    }

    /// Renders in progressive passes (sppm, ppm and the vcm family) rather than samples per
    /// pixel.
    pub fn is_progressive(self) -> bool {
        Takes::PROGRESSIVE.includes(self)
    }

    /// Renders in passes that are independent given their index (every progressive
    /// integrator but sppm), so a render can be split into pass ranges and merged.
    pub fn has_independent_passes(self) -> bool {
        Takes::PASS_RANGES.includes(self)
    }

    /// What `--help` says the integrator does.
    pub fn summary(self) -> &'static str {
        match self {
            Self::Photon => {
                "two-pass photon mapping: direct light, caustic map, final gathering of the global map"
            }
            Self::Direct => {
                "ray-traced direct light with mirror and glass recursion; no indirect diffuse light"
            }
            Self::Path => "path tracing with next-event estimation and MIS: the reference",
            Self::Sppm => {
                "stochastic progressive photon mapping (Hachisuka & Jensen 2009): converges to the exact image"
            }
            Self::Ppm => {
                "probabilistic progressive photon mapping (Knaus & Zwicker 2011): independent passes"
            }
            Self::Vcm => {
                "vertex connection and merging (Georgiev et al. 2012): bidirectional paths and photon merging, weighed by MIS"
            }
            Self::Bdpt => "bidirectional path tracing: vcm's connections alone",
            Self::LightTrace => {
                "light tracing: light paths connected to the camera (vcm's light subpaths alone)"
            }
        }
    }
}

/// How the photon integrator finds indirect light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GatherMode {
    /// Final gathering: rays from each diffuse point read precomputed irradiance.
    #[default]
    Final,
    /// Read the global photon map directly.
    None,
}

named_values!(GatherMode, "MODE", [GatherMode::Final => "final", GatherMode::None => "none"]);

named_values!(Kernel, "NAME", [
    Kernel::Box => "box",
    Kernel::Cone => "cone",
    Kernel::Gaussian => "gaussian",
    Kernel::Epanechnikov => "epanechnikov",
]);

impl SettingValue for PixelFilter {
    fn parse(text: &str) -> Result<Self, String> {
        text.parse()
    }
    fn text(&self) -> String {
        match self {
            PixelFilter::Box => "box".into(),
            PixelFilter::Gaussian { sigma } => format!("gaussian:{sigma}"),
        }
    }
    const METAVAR: &'static str = "box|gaussian:SIGMA";
}

impl Serialize for PixelFilter {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.text())
    }
}

impl<'de> Deserialize<'de> for PixelFilter {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        PixelFilter::parse(&text).map_err(serde::de::Error::custom)
    }
}

/// A half-open range `start..end` of passes or samples, written `a..b`; kept as an array
/// `[a, b]` in JSON and TOML.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(from = "(u64, u64)", into = "(u64, u64)")]
pub struct Span {
    pub start: u64,
    pub end: u64,
}

impl From<(u64, u64)> for Span {
    fn from((start, end): (u64, u64)) -> Self {
        Self { start, end }
    }
}

impl From<Span> for (u64, u64) {
    fn from(s: Span) -> Self {
        (s.start, s.end)
    }
}

impl SettingValue for Span {
    fn parse(text: &str) -> Result<Self, String> {
        let (a, b) = text
            .split_once("..")
            .ok_or_else(|| format!("'{text}' is not a range; expected a..b such as 0..64"))?;
        let number = |t: &str| {
            t.trim()
                .parse::<u64>()
                .map_err(|_| format!("'{t}' in '{text}' is not a whole number"))
        };
        Ok(Self {
            start: number(a)?,
            end: number(b)?,
        })
    }
    fn text(&self) -> String {
        format!("{}..{}", self.start, self.end)
    }
    const METAVAR: &'static str = "A..B";
}

/// The integrators that take a setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Takes(u8);

impl Takes {
    pub const ALL: Self = Self(0b1111_1111);
    pub const PHOTON: Self = Self::only(IntegratorKind::Photon);
    pub const PPM: Self = Self::only(IntegratorKind::Ppm);
    /// The photon-tracing progressive integrators.
    pub const PHOTON_PASSES: Self =
        Self::only(IntegratorKind::Sppm).and(Self::only(IntegratorKind::Ppm));
    /// Vertex connection and merging and its modes.
    pub const VCM_FAMILY: Self = Self::only(IntegratorKind::Vcm)
        .and(Self::only(IntegratorKind::Bdpt))
        .and(Self::only(IntegratorKind::LightTrace));
    pub const PROGRESSIVE: Self = Self::PHOTON_PASSES.and(Self::VCM_FAMILY);
    /// The integrators whose passes are independent, so that pass ranges render apart.
    pub const PASS_RANGES: Self = Self::PPM.and(Self::VCM_FAMILY);
    /// The integrators that render samples per pixel.
    pub const SAMPLES: Self = Self::only(IntegratorKind::Photon)
        .and(Self::only(IntegratorKind::Direct))
        .and(Self::only(IntegratorKind::Path));

    pub const fn only(kind: IntegratorKind) -> Self {
        Self(1 << kind as u8)
    }

    pub const fn and(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    pub const fn except(self, kind: IntegratorKind) -> Self {
        Self(self.0 & !(1 << kind as u8))
    }

    pub fn includes(self, kind: IntegratorKind) -> bool {
        self.0 & (1 << kind as u8) != 0
    }

    pub fn kinds(self) -> impl Iterator<Item = IntegratorKind> {
        IntegratorKind::ALL
            .into_iter()
            .filter(move |k| self.includes(*k))
    }

    /// `photon`, `sppm and ppm`, `photon, direct and path`.
    pub fn names(self) -> String {
        let names: Vec<&str> = self.kinds().map(IntegratorKind::name).collect();
        match names.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
            _ => names.join(""),
        }
    }
}
