//! Photon mapping's first pass: photons emitted from the lights, traced through the scene and
//! stored in kd-tree photon maps (Jensen, "Global Illumination Using Photon Maps", 1996).
//!
//! The split follows Tungsten's: a plain [`Photon`] record, a spatial index generic over
//! anything with a position ([`kdtree`]), a pure [`trace_photons`] and a [`PhotonConfig`].
//! Photon power is flux in watts and already includes 1/N of the emitted count, so a radiance
//! estimate is Σ f · Φ / area with no further division.

pub mod beam;
pub mod cache;
pub mod estimate;
pub mod grid;
pub mod hot;
pub mod kdtree;
mod map;
mod record;
mod trace;

pub use cache::{IrradianceCache, is_cache_site};
pub use estimate::{GatherParams, Kernel};
pub use map::{MapKind, PhotonMap};
pub use record::{Channel, PassPhoton, Photon, VolumePhoton, decode_octahedral, encode_octahedral};
pub use trace::{
    MAX_PHOTONS, PassPhotons, PhotonConfig, PhotonMaps, SAVED_MAPS_AND_MEDIA, TraceStats,
    trace_indirect_photons, trace_photons,
};
