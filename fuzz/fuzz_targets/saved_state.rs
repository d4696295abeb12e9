//! What Photon saves and reads back: photon maps (.phm), and checkpoints and `.part` files of
//! progressive renders (one format). The first byte picks which.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, rest)) = data.split_first() else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("photon-fuzz-state-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("f.bin");
    let _ = std::fs::write(&path, rest);
    if kind % 2 == 0 {
        let _ = photon::io::phm::load(&path);
    } else {
        let _ = photon::io::checkpoint::load(&path);
    }
});
