//! Files: images (PNG, OpenEXR, PFM), photon maps (.phm) and point clouds (PLY), all written
//! atomically.

pub mod image;
pub mod phm;
pub mod ply;
