//! Scenes built into the program, defined in code so the binary needs no files.

mod cornell;
mod seed;
pub mod sphere;

use super::Scene;
use crate::error::{Error, Result};

/// A built-in scene: its name, a one-line description, and how to build it.
pub struct Builtin {
    pub name: &'static str,
    pub description: &'static str,
    pub build: fn() -> Result<Scene>,
}

pub const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "seed",
        description: "the original project's Cornell box: red/green walls, two boxes, chrome and glass (IOR 2.4) spheres, the procedural plant pot, 314 W disk light (default)",
        build: seed::build,
    },
    Builtin {
        name: "cornell",
        description: "the measured Cornell box with a glass and a mirror sphere, quad light of radiance (17, 12, 4); the validation scene",
        build: cornell::build,
    },
    Builtin {
        name: "closed-sphere",
        description: "analytic test: inside a diffuse sphere (R = 1, albedo 0.5) lit by a point light of intensity π; radiance is exactly 1",
        build: sphere::build,
    },
];

/// The scene `photon render` uses when none is named.
pub const DEFAULT_SCENE: &str = "seed";

/// Build a built-in scene by name.
pub fn load(name: &str) -> Result<Scene> {
    match BUILTINS.iter().find(|b| b.name == name) {
        Some(b) => (b.build)(),
        None => Err(Error::UnknownScene {
            name: name.to_owned(),
            available: BUILTINS
                .iter()
                .map(|b| b.name)
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}
