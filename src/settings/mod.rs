//! Every render setting, defined once: its name (the TOML key and Python keyword; the flag is
//! the same with `-`), type, default, range, the integrators that take it, and its help. The
//! command line's flags, a scene's `[render]` table, Python's keyword arguments, job manifests
//! and the checks of [`RenderOptions`] are all made from [`SETTINGS`]; the Python stubs, the
//! Blender panel and the README are checked against it by tests.
//!
//! A setting given for an integrator that does not take it is an error, wherever it is given;
//! a scene's `[render]` table is the exception, so that a scene written for one integrator
//! renders with another: its settings apply only where they are taken.

pub mod defaults;
mod kinds;

pub use crate::error::SettingError;
pub use kinds::{GatherMode, IntegratorKind, SettingValue, Span, Takes};

use crate::film::PixelFilter;
use crate::photon::Kernel;
use serde::{Deserialize, Serialize};

/// Largest photons per estimate: each estimate keeps k + 1 candidates.
pub const MAX_K: usize = 1 << 16;
/// Largest indirect scale (a debugging knob; 1 is correct).
pub const MAX_INDIRECT_SCALE: f32 = 1e6;
/// Most passes a progressive render may ask for.
pub const MAX_PASSES: u64 = 1 << 40;
/// Largest photon counts a setting may ask for.
pub const MAX_PHOTON_COUNT: u64 = 1 << 40;

/// Where `--help` lists a setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Group {
    SceneAndOutput,
    Sampling,
    PhotonMapping,
    Progressive,
    Splitting,
}

impl Group {
    pub const fn heading(self) -> &'static str {
        match self {
            Group::SceneAndOutput => "Scene and output",
            Group::Sampling => "Sampling",
            Group::PhotonMapping => "Photon mapping (photon; radius also sppm and ppm)",
            Group::Progressive => "Progressive (sppm, ppm)",
            Group::Splitting => "Splitting a render into parts",
        }
    }
}

/// A setting's default: a value per integrator, or what decides it when no value does.
pub enum DefaultValue {
    /// The default's text for an integrator that takes the setting.
    Value(fn(IntegratorKind) -> String),
    /// What decides the value (`the scene's`).
    Decided(&'static str),
}

/// One render setting, as the front ends see it.
pub struct Setting {
    /// `snake_case`: the TOML key and Python keyword; the flag is `--kebab-case`.
    pub name: &'static str,
    pub help: &'static str,
    pub group: Group,
    pub takes: Takes,
    pub default: DefaultValue,
    /// Said after the default (`at least photons`).
    pub default_note: &'static str,
    pub choices: &'static [&'static str],
    pub is_switch: bool,
    pub metavar: &'static str,
}

impl Setting {
    /// `--gather-rays`.
    pub fn flag(&self) -> String {
        format!("--{}", self.name.replace('_', "-"))
    }

    /// The default as help and the README state it: one value, or a value per integrator
    /// (`8 (photon), 16 (direct), 64 (path)`).
    pub fn default_text(&self) -> String {
        let text = match &self.default {
            DefaultValue::Decided(what) => (*what).to_owned(),
            DefaultValue::Value(of) => {
                let mut groups: Vec<(String, Vec<&str>)> = Vec::new();
                for kind in self.takes.kinds() {
                    let value = of(kind);
                    match groups.iter_mut().find(|(v, _)| *v == value) {
                        Some((_, kinds)) => kinds.push(kind.name()),
                        None => groups.push((value, vec![kind.name()])),
                    }
                }
                if groups.len() == 1 {
                    groups.remove(0).0
                } else {
                    groups
                        .iter()
                        .map(|(v, kinds)| format!("{v} ({})", kinds.join(", ")))
                        .collect::<Vec<_>>()
                        .join(", ")
                }
            }
        };
        if self.default_note.is_empty() {
            text
        } else {
            format!("{text}; {}", self.default_note)
        }
    }
}

macro_rules! render_settings {
    ($(
        $(#[doc = $doc:literal])+
        $name:ident: $ty:ty {
            group: $group:ident,
            takes: $takes:expr,
            default: $default:expr,
            note: $note:literal,
            check: $check:expr $(,)?
        }
    )*) => {
        /// Everything a user may set for a render; `None` takes the scene's or the default.
        #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct RenderOptions {
            $(
                $(#[doc = $doc])+
                #[serde(skip_serializing_if = "Option::is_none")]
                pub $name: Option<$ty>,
            )*
        }

        /// Every render setting, in the order `--help` lists them.
        pub static SETTINGS: &[Setting] = &[$(
            Setting {
                name: stringify!($name),
                help: concat!($($doc),+),
                group: Group::$group,
                takes: $takes,
                default: $default,
                default_note: $note,
                choices: <$ty as SettingValue>::CHOICES,
                is_switch: <$ty as SettingValue>::IS_SWITCH,
                metavar: <$ty as SettingValue>::METAVAR,
            },
        )*];

        impl RenderOptions {
            /// The settings given, as their table entries and their values' text.
            pub fn given(&self) -> Vec<(&'static Setting, String)> {
                let mut given = Vec::new();
                $(
                    if let Some(v) = &self.$name {
                        given.push((setting(stringify!($name)), v.text()));
                    }
                )*
                given
            }

            /// Set `name` from its text, as a flag or a TOML string gives it.
            pub fn set_text(&mut self, name: &str, text: &str) -> Result<(), SettingError> {
                match name {
                    $(stringify!($name) => {
                        self.$name = Some(<$ty as SettingValue>::parse(text).map_err(|problem| {
                            SettingError { name: stringify!($name), value: Some(text.to_owned()), problem }
                        })?);
                    })*
                    other => return Err(unknown(other)),
                }
                Ok(())
            }

            /// Set `name` from a JSON value, as Python's keywords and TOML's numbers give it;
            /// null leaves it unset.
            pub fn set_json(&mut self, name: &str, value: serde_json::Value) -> Result<(), SettingError> {
                match name {
                    $(stringify!($name) => {
                        let shown = value.to_string();
                        self.$name = serde_json::from_value(value).map_err(|e| SettingError {
                            name: stringify!($name),
                            value: Some(shown),
                            problem: format!("expected {}", expected(stringify!($name), &e.to_string())),
                        })?;
                    })*
                    other => return Err(unknown(other)),
                }
                Ok(())
            }

            /// Each setting's own range, and whether `kind` takes it.
            pub fn check_each(&self, kind: IntegratorKind) -> Result<(), SettingError> {
                // A switch given as off asks for nothing, whichever integrator runs.
                if let Some((entry, value)) = self
                    .given()
                    .into_iter()
                    .find(|(s, v)| !s.takes.includes(kind) && !(s.is_switch && v == "false"))
                {
                    return Err(SettingError {
                        name: entry.name,
                        value: (!entry.is_switch).then_some(value),
                        problem: format!(
                            "the {} integrator does not take it (it is for {})",
                            kind.name(),
                            entry.takes.names()
                        ),
                    });
                }
                self.check_values()
            }

            /// Each setting's own range, whichever integrator runs.
            pub fn check_values(&self) -> Result<(), SettingError> {
                $(
                    if let Some(v) = &self.$name {
                        let check: fn(&$ty) -> Result<(), String> = $check;
                        check(v).map_err(|problem| SettingError {
                            name: stringify!($name),
                            value: (!<$ty as SettingValue>::IS_SWITCH).then(|| v.text()),
                            problem,
                        })?;
                    }
                )*
                Ok(())
            }

            /// Fill every setting not given here from `scene`'s (a `[render]` table), where
            /// `kind` takes it.
            pub fn fill_from_scene(&mut self, scene: &RenderOptions, kind: IntegratorKind) {
                $(
                    if self.$name.is_none() && setting(stringify!($name)).takes.includes(kind) {
                        self.$name = scene.$name.clone();
                    }
                )*
            }
        }
    };
}

/// The table entry of the setting `name`.
pub fn setting(name: &str) -> &'static Setting {
    SETTINGS
        .iter()
        .find(|s| s.name == name)
        .expect("every setting has a table entry")
}

/// The setting named `name`, if there is one.
pub fn find(name: &str) -> Option<&'static Setting> {
    SETTINGS.iter().find(|s| s.name == name)
}

fn unknown(name: &str) -> SettingError {
    let names: Vec<&str> = SETTINGS.iter().map(|s| s.name).collect();
    SettingError {
        name: "",
        value: None,
        problem: format!(
            "'{name}' is not a render setting (expected one of: {})",
            names.join(", ")
        ),
    }
}

/// What a JSON value for `name` should have been, for an error.
fn expected(name: &str, serde_message: &str) -> String {
    let s = setting(name);
    if s.choices.is_empty() {
        format!("{} ({serde_message})", s.metavar)
    } else {
        format!("one of {}", s.choices.join(", "))
    }
}

fn at_least_one<T: PartialEq + From<u8>>(v: &T) -> Result<(), String> {
    if *v == T::from(0) {
        Err("must be at least 1".into())
    } else {
        Ok(())
    }
}

fn positive_finite_f32(v: &f32) -> Result<(), String> {
    if *v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err("must be a positive number".into())
    }
}

fn photon_count(v: &u64) -> Result<(), String> {
    if (1..=MAX_PHOTON_COUNT).contains(v) {
        Ok(())
    } else {
        Err(format!("must be 1 to {MAX_PHOTON_COUNT}"))
    }
}

fn nonempty_span(v: &Span) -> Result<(), String> {
    if v.start < v.end {
        Ok(())
    } else {
        Err("the range is empty: its start must come before its end".into())
    }
}

/// Most bounces, light samples and gather rays a setting may ask for: far beyond use, small
/// enough that a scene file cannot ask for a render that never ends.
pub const MAX_COUNT: u32 = 1 << 16;

fn at_most_max_count(v: &u32) -> Result<(), String> {
    if *v <= MAX_COUNT {
        Ok(())
    } else {
        Err(format!("must be at most {MAX_COUNT}"))
    }
}

fn one_to_max_count(v: &u32) -> Result<(), String> {
    at_least_one(v).and_then(|()| at_most_max_count(v))
}

/// Seeds are written to TOML files (scene files, job manifests), whose integers are 64-bit
/// signed.
fn seed_range(v: &u64) -> Result<(), String> {
    if i64::try_from(*v).is_ok() {
        Ok(())
    } else {
        Err(format!("must be at most {}", i64::MAX))
    }
}

fn anything<T>(_: &T) -> Result<(), String> {
    Ok(())
}

use defaults as d;
use kinds::IntegratorKind as I;

render_settings! {
    /// The rendering algorithm.
    integrator: IntegratorKind {
        group: SceneAndOutput, takes: Takes::ALL,
        default: DefaultValue::Value(|_| d::INTEGRATOR.name().into()), note: "",
        check: anything,
    }
    /// Image width in pixels.
    width: u32 {
        group: SceneAndOutput, takes: Takes::ALL,
        default: DefaultValue::Decided("the scene's"), note: "", check: at_least_one,
    }
    /// Image height in pixels.
    height: u32 {
        group: SceneAndOutput, takes: Takes::ALL,
        default: DefaultValue::Decided("the scene's"), note: "", check: at_least_one,
    }
    /// Pixel filter: `box`, or `gaussian:SIGMA` with SIGMA in pixels (the original project blurred with 0.5).
    filter: PixelFilter {
        group: SceneAndOutput, takes: Takes::SAMPLES,
        default: DefaultValue::Value(|_| d::FILTER.text()), note: "", check: anything,
    }
    /// Samples per pixel (Owen-scrambled Sobol points).
    spp: u32 {
        group: Sampling, takes: Takes::SAMPLES,
        default: DefaultValue::Value(|k| d::spp(k).to_string()), note: "", check: at_least_one,
    }
    /// Seed of every random stream; the same seed gives the same image.
    seed: u64 {
        group: Sampling, takes: Takes::ALL,
        default: DefaultValue::Value(|_| d::SEED.to_string()), note: "", check: seed_range,
    }
    /// Maximum number of bounces.
    max_depth: u32 {
        group: Sampling, takes: Takes::ALL,
        default: DefaultValue::Value(|k| d::max_depth(k).to_string()), note: "",
        check: at_most_max_count,
    }
    /// Samples per area light at each diffuse hit (passes of sppm and ppm average theirs).
    light_samples: u32 {
        group: Sampling, takes: Takes::ALL.except(I::Path).except(I::Vcm).except(I::Bdpt).except(I::LightTrace),
        default: DefaultValue::Value(|k| d::light_samples(k).to_string()), note: "",
        check: one_to_max_count,
    }
    /// Spectral rendering: every path carries three wavelengths (hero-wavelength sampling, Wilkie et al. 2014) and RGB colours are upsampled to spectra (Jakob and Hanika 2019); glass disperses. Off: the RGB channels.
    spectral: bool {
        group: SceneAndOutput, takes: Takes::ALL,
        default: DefaultValue::Value(|_| "false".into()), note: "", check: anything,
    }
    /// Largest radiance a camera sample may carry: a brighter sample is scaled down to it, keeping its colour (pbrt's maxcomponentvalue). It removes fireflies and biases the image darker.
    max_radiance: f32 {
        group: Sampling, takes: Takes::SAMPLES,
        default: DefaultValue::Decided("no limit"), note: "", check: positive_finite_f32,
    }
    /// Photons for the global map.
    photons: u64 {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| d::PHOTONS.to_string()), note: "", check: photon_count,
    }
    /// Photons traced for the caustic map.
    caustic_photons: u64 {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| d::CAUSTIC_PHOTONS.to_string()),
        note: "at least photons", check: photon_count,
    }
    /// Largest gather radius in scene units (sppm, ppm and vcm: the first pass's radius, 4× that
    /// for balls in media).
    radius: f32 {
        group: PhotonMapping, takes: Takes::PHOTON.and(Takes::PHOTON_PASSES).and(Takes::only(I::Vcm)),
        default: DefaultValue::Decided(
            "photon: 1% (caustic map) and 2.5% (global map) of the diagonal of what the camera sees; sppm and ppm: 6 and 4 pixel footprints at each visible point; vcm: 2 pixel footprints at the median distance seen",
        ),
        note: "", check: positive_finite_f32,
    }
    /// Photons per estimate; 0 gathers at a fixed radius.
    k: usize {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| d::K.to_string()),
        note: "256 for the global map with gather none",
        check: |k| if *k > MAX_K { Err(format!("at most {MAX_K} photons per estimate")) } else { Ok(()) },
    }
    /// Density-estimation kernel.
    kernel: Kernel {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| d::KERNEL.text()), note: "", check: anything,
    }
    /// How indirect light is found: final gathering, or the global map read directly.
    gather: GatherMode {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| d::GATHER.text()), note: "", check: anything,
    }
    /// Final-gather rays per camera sample.
    gather_rays: u32 {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| d::GATHER_RAYS.to_string()), note: "",
        check: at_most_max_count,
    }
    /// Weight on the indirect part (1 is physically correct; a debugging knob).
    indirect_scale: f32 {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| d::INDIRECT_SCALE.to_string()), note: "",
        check: |s| if (0.0..=MAX_INDIRECT_SCALE).contains(s) { Ok(()) } else {
            Err(format!("must be between 0 and {MAX_INDIRECT_SCALE} (1 is physically correct)"))
        },
    }
    /// Trace red, green and blue photons separately, as the original project did.
    per_channel: bool {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Value(|_| "false".into()), note: "", check: anything,
    }
    /// Fixed photon absorption probability instead of Russian roulette on albedo.
    absorption: f32 {
        group: PhotonMapping, takes: Takes::PHOTON,
        default: DefaultValue::Decided("Russian roulette on albedo"), note: "",
        check: |a| if (0.0..1.0).contains(a) { Ok(()) } else { Err("must be in [0, 1)".into()) },
    }
    /// Stop after this many passes.
    passes: u64 {
        group: Progressive, takes: Takes::PROGRESSIVE,
        default: DefaultValue::Decided("none: give passes, a time or both"), note: "",
        check: |p| match *p {
            0 => Err("a render needs at least one pass".into()),
            p if p > MAX_PASSES => Err(format!("must be at most {MAX_PASSES}")),
            _ => Ok(()),
        },
    }
    /// Stop after this many seconds (the image of the passes done by then; at least one pass).
    time: f64 {
        group: Progressive, takes: Takes::PROGRESSIVE,
        default: DefaultValue::Decided("none"), note: "",
        check: |s| if *s > 0.0 && s.is_finite() { Ok(()) } else {
            Err("must be a positive number of seconds".into())
        },
    }
    /// Photons traced per pass (the vcm family sets its own: a light path per four pixels).
    photons_per_pass: u64 {
        group: Progressive, takes: Takes::PHOTON_PASSES,
        default: DefaultValue::Value(|_| d::PHOTONS_PER_PASS.to_string()), note: "",
        check: photon_count,
    }
    /// Radius reduction α in (0, 1) (Hachisuka and Jensen 2009; Knaus and Zwicker 2011).
    alpha: f64 {
        group: Progressive, takes: Takes::PHOTON_PASSES.and(Takes::only(I::Vcm)),
        default: DefaultValue::Decided("2/3"), note: "",
        check: |a| if *a > 0.0 && *a < 1.0 { Ok(()) } else { Err("must be in (0, 1)".into()) },
    }
    /// Render only samples a..b (end exclusive) of each pixel's spp, into a part to merge.
    sample_range: Span {
        group: Splitting, takes: Takes::SAMPLES,
        default: DefaultValue::Decided("every sample"), note: "", check: nonempty_span,
    }
    /// Render only passes a..b (end exclusive; ppm and the vcm family, whose passes are independent), into a part to merge.
    pass_range: Span {
        group: Splitting, takes: Takes::PASS_RANGES,
        default: DefaultValue::Decided("every pass"), note: "", check: nonempty_span,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_default_per_integrator_is_stated_per_integrator() {
        assert_eq!(
            setting("spp").default_text(),
            "8 (photon), 16 (direct), 64 (path)"
        );
        assert_eq!(setting("photons_per_pass").default_text(), "100000");
        assert_eq!(
            setting("caustic_photons").default_text(),
            "2000000; at least photons"
        );
    }

    #[test]
    fn a_setting_for_another_integrator_is_refused_with_its_name() {
        let o = RenderOptions {
            photons: Some(1000),
            ..RenderOptions::default()
        };
        let e = o.check_each(IntegratorKind::Path).expect_err("refused");
        assert_eq!(e.name, "photons");
        assert_eq!(e.value.as_deref(), Some("1000"));
        assert!(
            e.problem
                .contains("the path integrator does not take it (it is for photon)"),
            "{e}"
        );
        assert!(o.check_each(IntegratorKind::Photon).is_ok());
    }

    #[test]
    fn text_and_json_give_the_same_options() {
        let mut a = RenderOptions::default();
        let mut b = RenderOptions::default();
        for (name, text, json) in [
            ("kernel", "cone", serde_json::json!("cone")),
            ("pass_range", "2..5", serde_json::json!([2, 5])),
            ("filter", "gaussian:0.5", serde_json::json!("gaussian:0.5")),
            ("time", "1.5", serde_json::json!(1.5)),
        ] {
            a.set_text(name, text).expect(name);
            b.set_json(name, json).expect(name);
        }
        assert_eq!(a, b);
        assert_eq!(a.given().len(), 4);
        let e = a.set_text("kernal", "box").expect_err("unknown");
        assert!(e.problem.contains("not a render setting"), "{e}");
        let e = a
            .set_json("gather", serde_json::json!("some"))
            .expect_err("bad");
        assert!(e.problem.contains("final, none"), "{e}");
    }
}
