//! PNG textures: any bytes decode to a texture or an error, within the decoded-image budget
//! (set low here so that a header asking for gigabytes is refused, not allocated).
#![no_main]
use libfuzzer_sys::fuzz_target;
use photon::io::texture::{Encoding, decode_texture_as};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    photon_fuzz_budget();
    for encoding in [Encoding::Srgb, Encoding::Linear] {
        if let Ok(t) = decode_texture_as(data, Path::new("f.png"), encoding) {
            assert_eq!(t.texels.len(), t.width as usize * t.height as usize);
            assert!(t.alpha.is_empty() || t.alpha.len() == t.texels.len());
        }
    }
});

fn photon_fuzz_budget() {
    // SAFETY: set once, before any thread of this process reads the environment.
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| unsafe { std::env::set_var("PHOTON_IMAGE_MEMORY", "256M") });
}
