//! Never a panic: thousands of randomly damaged scene, OBJ, PLY and glTF files (bytes
//! replaced, deleted, inserted, duplicated, truncated) must each load and build or fail with
//! an error. Deterministic: the damage comes from a keyed RNG.

use crate::common;

use photon::description::build::build;
use photon::description::load_mesh_file;
use photon::description::toml_read::read_str;
use photon::sampling::Rng;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `input` with a few random edits. Edits favour the bytes that matter in text formats.
fn damage(input: &[u8], rng: &mut Rng) -> Vec<u8> {
    const INTERESTING: &[u8] = b"[]{}=\",.-0123456789e \n#/\0\xff";
    let mut out = input.to_vec();
    let edits = 1 + rng.next_u32() % 4;
    for _ in 0..edits {
        if out.is_empty() {
            break;
        }
        let at = rng.next_u32() as usize % out.len();
        let byte = if rng.next_u32().is_multiple_of(2) {
            INTERESTING[rng.next_u32() as usize % INTERESTING.len()]
        } else {
            rng.next_u32() as u8
        };
        match rng.next_u32() % 5 {
            0 => out[at] = byte,
            1 => {
                out.remove(at);
            }
            2 => out.insert(at, byte),
            3 => {
                let len = (rng.next_u32() as usize % 16).min(out.len() - at);
                let chunk = out[at..at + len].to_vec();
                out.splice(at..at, chunk);
            }
            _ => out.truncate(at),
        }
    }
    out
}

fn check<F: Fn(&[u8])>(name: &str, input: &[u8], cases: u32, seed: u64, run: F) {
    let mut rng = Rng::keyed(seed, &[]);
    for case in 0..cases {
        let damaged = damage(input, &mut rng);
        if catch_unwind(AssertUnwindSafe(|| run(&damaged))).is_err() {
            panic!(
                "{name}, case {case}: panicked on this input:\n{}",
                String::from_utf8_lossy(&damaged)
            );
        }
    }
}

#[test]
fn damaged_scene_files_never_panic() {
    let scenes = repo().join("scenes");
    for (k, name) in ["caustics.toml", "point-light.toml", "spot-light.toml"]
        .iter()
        .enumerate()
    {
        let text = std::fs::read(scenes.join(name)).expect("scene");
        check(name, &text, 1000, k as u64, |bytes| {
            let text = String::from_utf8_lossy(bytes);
            if let Ok(desc) = read_str(&text, Path::new(name), &scenes) {
                let _ = build(&desc);
            }
        });
    }
}

#[test]
fn damaged_mesh_files_never_panic() {
    let dir = common::temp_dir("fuzz-mesh");
    let assets = repo().join("scenes/assets");
    let mut inputs: Vec<(&str, Vec<u8>)> = vec![
        ("obj", std::fs::read(assets.join("cube.obj")).expect("obj")),
        (
            "ply",
            std::fs::read(assets.join("octahedron.ply")).expect("ply"),
        ),
        (
            "gltf",
            std::fs::read(assets.join("tetrahedron.gltf")).expect("gltf"),
        ),
    ];
    // A binary PLY: the octahedron's six vertices and eight faces.
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nelement face 8\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for p in common::OCTAHEDRON_VERTICES {
        p.iter().for_each(|x| ply.extend(x.to_le_bytes()));
    }
    for f in common::OCTAHEDRON_FACES {
        ply.push(3);
        f.iter().for_each(|&i| ply.extend((i as i32).to_le_bytes()));
    }
    inputs.push(("ply", ply));
    // The glTF as GLB, so binary chunk headers get damaged too.
    let gltf: serde_json::Value = serde_json::from_slice(&inputs[2].1).expect("gltf json");
    let uri = gltf["buffers"][0]["uri"].as_str().expect("uri").to_owned();
    let bin = {
        use base64::Engine;
        base64::engine::general_purpose::STANDARD
            .decode(uri.split_once(",").expect("data uri").1)
            .expect("base64")
    };
    let mut doc = gltf.clone();
    doc["buffers"][0] = serde_json::json!({"byteLength": bin.len()});
    inputs.push(("glb", common::glb(&doc, &bin)));
    // The MTL and texture the OBJ refers to stay intact beside it.
    for f in ["cube.mtl", "tiles.png"] {
        std::fs::copy(assets.join(f), dir.join(f)).expect("copy");
    }
    for (k, (ext, bytes)) in inputs.iter().enumerate() {
        let path = dir.join(format!("m{k}.{ext}"));
        check(ext, bytes, 1000, 100 + k as u64, |damaged| {
            std::fs::write(&path, damaged).expect("write");
            let _ = load_mesh_file(&path);
        });
    }
}
