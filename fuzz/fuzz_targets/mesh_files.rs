//! OBJ (with an MTL beside it) and PLY: the first byte picks the format, the rest is the file
//! (for OBJ, split at the first NUL into the OBJ and its `m.mtl`).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, rest)) = data.split_first() else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("photon-fuzz-mesh-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = if kind % 2 == 0 {
        let (obj, mtl) = match rest.iter().position(|&b| b == 0) {
            Some(i) => (&rest[..i], &rest[i + 1..]),
            None => (rest, &[][..]),
        };
        let _ = std::fs::write(dir.join("m.mtl"), mtl);
        let p = dir.join("f.obj");
        let _ = std::fs::write(&p, obj);
        p
    } else {
        let p = dir.join("f.ply");
        let _ = std::fs::write(&p, rest);
        p
    };
    let _ = photon::description::load_mesh_file(&path);
});
