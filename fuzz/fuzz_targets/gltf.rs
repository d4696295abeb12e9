//! glTF 2.0: a GLB (or JSON glTF) imported as a whole scene, then built.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("photon-fuzz-gltf-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let name = if data.starts_with(b"glTF") {
        "f.glb"
    } else {
        "f.gltf"
    };
    let path = dir.join(name);
    let _ = std::fs::write(&path, data);
    if let Ok(mut loaded) = photon::description::gltf::import_scene(&path) {
        let _ = photon::description::build::build_with(&loaded.desc, &mut loaded.meshes);
    }
});
