//! Procedural modelling: lathe and solidify, Catmull–Clark subdivision, NURBS surfaces, and
//! the plant pot of the original project built from them. Double precision throughout; the
//! results become triangle meshes for the scene.

pub mod lathe;
pub mod mesh;
pub mod nurbs;
pub mod pot;
pub mod subdivision;

pub use mesh::PolyMesh;
