//! Scenes built into the program, written as descriptions in code so the binary needs no
//! files and `photon scenes --export` can write any of them as TOML.

mod cornell;
mod seed;
pub mod sphere;

pub use cornell::LIGHT_RADIANCE as CORNELL_LIGHT_RADIANCE;
pub use seed::LIGHT_POWER as SEED_LIGHT_POWER;

use super::SceneDesc;
use crate::error::{Error, Result};
use crate::scene::Scene;

/// A built-in scene: its name, a one-line description, and its description in code.
pub struct Builtin {
    pub name: &'static str,
    pub description: &'static str,
    pub desc: fn() -> SceneDesc,
}

pub const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "seed",
        description: "the original project's Cornell box: red/green walls, two boxes, chrome and glass (IOR 2.4) spheres, the procedural plant pot, 314 W disk light (default)",
        desc: seed::desc,
    },
    Builtin {
        name: "cornell",
        description: "the measured Cornell box with a glass and a mirror sphere, quad light of radiance (17, 12, 4); the validation scene",
        desc: cornell::desc,
    },
    Builtin {
        name: "closed-sphere",
        description: "analytic test: inside a diffuse sphere (R = 1, albedo 0.5) lit by a point light of intensity π; radiance is exactly 1",
        desc: sphere::desc,
    },
];

/// The scene `photon render` uses when none is named.
pub const DEFAULT_SCENE: &str = "seed";

/// The description of a built-in scene, if `name` is one.
pub fn desc(name: &str) -> Option<SceneDesc> {
    BUILTINS.iter().find(|b| b.name == name).map(|b| (b.desc)())
}

/// The error for a name that is neither a built-in scene nor a file.
pub fn unknown(name: &str) -> Error {
    Error::UnknownScene {
        name: name.to_owned(),
        available: BUILTINS
            .iter()
            .map(|b| b.name)
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// Build a built-in scene by name.
pub fn load(name: &str) -> Result<Scene> {
    let desc = desc(name).ok_or_else(|| unknown(name))?;
    super::build::build(&desc)
}
