//! TOML scene files: read, then built (meshes named by the scene resolve against an empty
//! folder, so only inline geometry is built). Any input: an error or a scene, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let dir = Path::new("/nonexistent-photon-fuzz");
    if let Ok(desc) = photon::description::toml_read::read_str(text, &dir.join("f.toml"), dir) {
        let _ = photon::description::build::build(&desc);
    }
});
