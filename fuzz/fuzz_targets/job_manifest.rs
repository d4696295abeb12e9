//! A job folder's `job.toml`, which workers on other machines read as untrusted input.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(manifest) = photon::job::Manifest::parse(text, std::path::Path::new("job.toml")) {
        // What workers, status and merge do with a manifest that passed.
        let _ = manifest.job_id();
        let _ = manifest.range_flag();
        for i in 0..manifest.tasks.len().min(4) {
            let _ = photon::job::part_path(std::path::Path::new("j"), i);
        }
    }
});
