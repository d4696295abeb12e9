//! Files: images (PNG, OpenEXR, PFM, NumPy), photon maps (.phm), point clouds and procedural
//! models (PLY, OBJ), all written atomically; and images streamed to the tev viewer.

pub mod atomic;
pub mod checkpoint;
pub mod container;
pub mod decoded;
pub mod image;
pub mod input;
pub mod mesh;
pub mod phm;
pub mod ply;
pub mod sample_part;
pub mod tev;
pub mod texture;
