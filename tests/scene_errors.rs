//! Broken scene, mesh and glTF files through the `photon` binary: each must give a located,
//! clear message and exit code 2, never a panic, and leave no output image. The exact messages
//! are kept as snapshots in tests/snapshots/scene_errors/ (set UPDATE_SNAPSHOTS=1 to rewrite
//! them after a deliberate change, and review the diff).

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

const CAMERA: &str = "[camera]\nposition = [0, 1, 4]\nlook_at = [0, 0.5, 0]\n";

const MATERIAL: &str = "\n[materials.white]\ntype = \"diffuse\"\n";

/// A broken input: its name, the files to write (name, bytes), and the scene to render.
struct Case {
    name: &'static str,
    files: Vec<(&'static str, Vec<u8>)>,
    scene: &'static str,
}

fn toml_case(name: &'static str, text: String) -> Case {
    Case {
        name,
        files: vec![("scene.toml", text.into_bytes())],
        scene: "scene.toml",
    }
}

fn with_mesh(name: &'static str, file: &'static str, bytes: Vec<u8>) -> Case {
    let scene = format!(
        "{CAMERA}{MATERIAL}\n[[shapes]]\ntype = \"mesh\"\nfile = \"{file}\"\nmaterial = \"white\"\n"
    );
    Case {
        name,
        files: vec![("scene.toml", scene.into_bytes()), (file, bytes)],
        scene: "scene.toml",
    }
}

fn ply_header(format: &str, vertices: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n"
    )
}

/// A GLB whose POSITION accessor claims more vertices than its buffer view holds.
fn bad_accessor_glb() -> Vec<u8> {
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 1000, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36}]
    });
    common::glb(&doc, &[0u8; 36])
}

fn cases() -> Vec<Case> {
    let sphere = |body: &str| {
        format!("{CAMERA}{MATERIAL}\n[[shapes]]\ntype = \"sphere\"\n{body}material = \"white\"\n")
    };
    vec![
        toml_case(
            "toml_syntax",
            format!("{CAMERA}\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 1, 0\nradius = 1\n"),
        ),
        toml_case("wrong_type", sphere("radius = \"big\"\n")),
        toml_case("unknown_key", sphere("radus = 0.5\n")),
        toml_case(
            "unknown_material",
            format!("{CAMERA}{MATERIAL}\n[[shapes]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"whte\"\n"),
        ),
        toml_case("unknown_shape_type", sphere("radius = 1\n").replace("\"sphere\"", "\"sphre\"")),
        toml_case(
            "no_camera",
            format!("{MATERIAL}\n[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\npower = 10\n"),
        ),
        toml_case(
            "camera_up_along_view",
            "[camera]\nposition = [0, 3, 0]\nlook_at = [0, 0, 0]\n".to_owned(),
        ),
        toml_case(
            "spot_without_direction",
            format!("{CAMERA}\n[[lights]]\ntype = \"spot\"\nposition = [0, 2, 0]\nlook_at = [0, 2, 0]\npower = 10\n"),
        ),
        toml_case(
            "unknown_integrator",
            format!("{CAMERA}\n[render]\nintegrator = \"bidir\"\n"),
        ),
        toml_case(
            "missing_texture",
            format!("{CAMERA}\n[materials.wood]\ntype = \"diffuse\"\nalbedo = {{ texture = \"wood.png\" }}\n"),
        ),
        toml_case(
            "glass_attenuation_above_one",
            format!("{CAMERA}\n[materials.glass]\ntype = \"glass\"\nattenuation = {{ color = [1.2, 0.5, 0.5], distance = 1.0 }}\n"),
        ),
        toml_case(
            "glass_attenuation_distance_zero",
            format!("{CAMERA}\n[materials.glass]\ntype = \"glass\"\nattenuation = {{ color = 0.5, distance = 0 }}\n"),
        ),
        toml_case(
            "missing_mesh_file",
            format!("{CAMERA}{MATERIAL}\n[[shapes]]\ntype = \"mesh\"\nfile = \"bunny.obj\"\n"),
        ),
        with_mesh(
            "obj_index_out_of_range",
            "tri.obj",
            b"# a triangle that names a fourth vertex\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n".to_vec(),
        ),
        with_mesh(
            "obj_bad_number",
            "tri.obj",
            b"v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n".to_vec(),
        ),
        Case {
            name: "mesh_without_material",
            files: vec![
                (
                    "scene.toml",
                    format!("{CAMERA}\n[[shapes]]\ntype = \"mesh\"\nfile = \"m.ply\"\n").into_bytes(),
                ),
                (
                    "m.ply",
                    format!("{}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ply_header("ascii", "3")).into_bytes(),
                ),
            ],
            scene: "scene.toml",
        },
        with_mesh("ply_truncated", "m.ply", {
            let mut b = ply_header("binary_little_endian", "3").into_bytes();
            b.extend([0u8; 20]);
            b
        }),
        with_mesh(
            "ply_absurd_count",
            "m.ply",
            ply_header("binary_little_endian", "1000000000000").into_bytes(),
        ),
        with_mesh(
            "ply_face_out_of_range",
            "m.ply",
            format!("{}0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", ply_header("ascii", "3")).into_bytes(),
        ),
        Case {
            name: "missing_scene_file",
            files: Vec::new(),
            scene: "nowhere.toml",
        },
        Case {
            name: "gltf_bad_accessor",
            files: vec![("bad.glb", bad_accessor_glb())],
            scene: "bad.glb",
        },
        Case {
            // gltf-json 1.4 itself panicked on this one (found by tests/scene_fuzz.rs).
            name: "gltf_missing_accessor",
            files: vec![(
                "gone.gltf",
                br#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 3}}]}]}"#.to_vec(),
            )],
            scene: "gone.gltf",
        },
        Case {
            // gltf 1.4 overflowed on a GLB length below its header size (found by scene_fuzz).
            name: "glb_bad_length",
            files: vec![("short.glb", {
                let mut b = bad_accessor_glb();
                b[8..12].copy_from_slice(&4u32.to_le_bytes());
                b
            })],
            scene: "short.glb",
        },
        Case {
            name: "gltf_bad_json",
            files: vec![(
                "bad.gltf",
                b"{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [\n    {\"mesh\": 0,}\n  ]\n}\n".to_vec(),
            )],
            scene: "bad.gltf",
        },
    ]
}

fn snapshot_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots/scene_errors")
}

fn run_case(case: &Case, dir: &Path) -> String {
    for (name, bytes) in &case.files {
        std::fs::write(dir.join(name), bytes).expect("write input");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_photon"))
        .args([
            "render", case.scene, "-o", "out.png", "--width", "8", "--height", "8",
        ])
        .current_dir(dir)
        .output()
        .expect("run photon");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}: exit code; stderr:\n{err}",
        case.name
    );
    assert!(!err.contains("panicked"), "{}: panicked:\n{err}", case.name);
    assert!(
        !dir.join("out.png").exists(),
        "{}: wrote an image",
        case.name
    );
    // Paths of the temporary folder vary from run to run.
    let canonical = dir.canonicalize().expect("dir");
    err.replace(&canonical.display().to_string(), "$DIR")
        .replace(&dir.display().to_string(), "$DIR")
}

#[test]
fn broken_inputs_give_located_messages_matching_the_snapshots() {
    let update = std::env::var_os("UPDATE_SNAPSHOTS").is_some();
    let mut mismatches = Vec::new();
    let all = cases();
    assert!(all.len() >= 10);
    for case in &all {
        let dir = common::temp_dir(&format!("err-{}", case.name));
        let got = run_case(case, &dir);
        let file = snapshot_dir().join(format!("{}.txt", case.name));
        if update {
            std::fs::create_dir_all(snapshot_dir()).expect("snapshot dir");
            std::fs::write(&file, &got).expect("write snapshot");
            continue;
        }
        let want = std::fs::read_to_string(&file).unwrap_or_default();
        if got != want {
            mismatches.push(format!(
                "--- {} ---\nexpected:\n{want}\ngot:\n{got}",
                case.name
            ));
        }
        // Every message names the input file.
        let input = case.files.last().map_or(case.scene, |f| f.0);
        assert!(
            got.contains(input) || got.contains("scene.toml"),
            "{}: {got}",
            case.name
        );
    }
    assert!(
        mismatches.is_empty(),
        "messages changed (UPDATE_SNAPSHOTS=1 rewrites them):\n{}",
        mismatches.join("\n")
    );
}

#[test]
fn text_format_errors_carry_line_and_column() {
    // The located cases must say file:line:column.
    for case in cases().iter().filter(|c| {
        matches!(
            c.name,
            "toml_syntax"
                | "wrong_type"
                | "unknown_key"
                | "unknown_material"
                | "unknown_shape_type"
                | "missing_texture"
                | "missing_mesh_file"
                | "obj_index_out_of_range"
                | "obj_bad_number"
                | "gltf_bad_json"
        )
    }) {
        let dir = common::temp_dir(&format!("loc-{}", case.name));
        let err = run_case(case, &dir);
        let located = err.lines().next().is_some_and(|l| {
            let mut parts = l.split(':').skip(1);
            // "error: $DIR/FILE:LINE:COL: message"
            parts.next().is_some()
                && parts
                    .next()
                    .is_some_and(|n| n.trim().parse::<u32>().is_ok())
                && parts
                    .next()
                    .is_some_and(|n| n.trim().parse::<u32>().is_ok())
        });
        assert!(located, "{}: not located:\n{err}", case.name);
    }
}
