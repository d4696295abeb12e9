//! OpenEXR images, as `photon compare` and environment maps read them: any bytes read to an
//! image or an error, within the decoded-image budget (set low here so that a header asking
//! for gigabytes is refused, not allocated).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    photon_fuzz_budget();
    let dir = std::env::temp_dir().join(format!("photon-fuzz-exr-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("f.exr");
    let _ = std::fs::write(&path, data);
    if let Ok(image) = photon::io::image::read_image(&path) {
        assert_eq!(image.pixels.len(), image.width as usize * image.height as usize);
    }
    let _ = photon::io::image::read_environment(&path);
});

fn photon_fuzz_budget() {
    // SAFETY: set once, before any thread of this process reads the environment.
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| unsafe { std::env::set_var("PHOTON_IMAGE_MEMORY", "256M") });
}
