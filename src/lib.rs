//! Photon: a photon-mapping global-illumination renderer.
//!
//! The library holds everything that renders; the `photon` binary is a thin command line over
//! it. See ARCHITECTURE.md for the map of modules, the data flow and the invariants.

#![forbid(unsafe_code)]

pub mod accel;
pub mod bench;
pub mod camera;
pub mod compare;
pub mod description;
pub mod error;
pub mod film;
pub mod geometry;
pub mod hash;
pub mod integrator;
pub mod io;
pub mod job;
pub mod light;
pub mod material;
pub mod math;
pub mod medium;
pub mod modeling;
pub mod photon;
pub mod progressive;
pub mod render;
pub mod render_job;
pub mod sampling;
pub mod scene;
pub mod session;
pub mod settings;
pub mod spectrum;
pub mod texture;
pub mod validate;

pub use error::{Error, Result};
