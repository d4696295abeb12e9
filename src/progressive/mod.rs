//! Progressive photon mapping: pass after pass, the radius shrinks while photons accumulate, so
//! the image converges to the exact solution (no bias left in the limit).
//!
//! - **SPPM** (Hachisuka & Jensen, "Stochastic Progressive Photon Mapping", 2009): each pixel
//!   keeps a radius, a photon count and accumulated flux; every pass re-traces its visible
//!   point and shrinks the radius by the α rule.
//! - **Probabilistic PPM** (Knaus & Zwicker, "Progressive Photon Mapping: A Probabilistic
//!   Approach", 2011): every pass is an independent photon-mapping render with radius
//!   r_i, r_{i+1}² = r_i² (i + α)/(i + 1); the image is the average of the passes. Passes are
//!   summed in fixed point, so any grouping of passes (partial renders merged later) gives the
//!   same bits as one run.
//!
//! Direct light comes from next-event estimation at the visible points; photons that came
//! straight from a light are not used. Pass p uses the random streams keyed by (seed, p) only.

mod pixels;
pub mod state;
mod vcm_pass;

pub use pixels::{Pixels, SppmPixel};

pub use state::{Method, PassSeconds, PassStats, ProgressiveConfig, ProgressiveState};
pub use vcm_pass::default_radius as default_vcm_radius;
