//! Radiance HDR environment maps: any bytes read to a map of finite, non-negative radiance or
//! an error, within the decoded-image budget (set low here so that a header asking for
//! gigabytes is refused, not allocated).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    photon_fuzz_budget();
    let dir = std::env::temp_dir().join(format!("photon-fuzz-hdr-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("f.hdr");
    let _ = std::fs::write(&path, data);
    if let Ok(map) = photon::io::image::read_environment(&path) {
        assert_eq!(map.texels.len(), map.width as usize * map.height as usize);
        assert!(map.texels.iter().all(|t| t.is_finite() && t.min_element() >= 0.0));
    }
});

fn photon_fuzz_budget() {
    // SAFETY: set once, before any thread of this process reads the environment.
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| unsafe { std::env::set_var("PHOTON_IMAGE_MEMORY", "256M") });
}
