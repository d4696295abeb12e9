//! Files: images in and out (PNG, OpenEXR, PFM), written atomically.

pub mod image;
