//! What Photon saves and reads back: photon maps (.phm), checkpoints and `.part` files of
//! progressive renders (one format), and sample-range `.part` files. The first byte picks
//! which.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, rest)) = data.split_first() else {
        return;
    };
    if kind % 3 == 2 {
        let _ = photon::io::sample_part::decode(rest);
        return;
    }
    let dir = std::env::temp_dir().join(format!("photon-fuzz-state-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("f.bin");
    let _ = std::fs::write(&path, rest);
    if kind % 3 == 0 {
        let _ = photon::io::phm::load(&path);
    } else {
        let _ = photon::io::checkpoint::load(&path);
    }
});
