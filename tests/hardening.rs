//! Hostile input and careless use (issue #13): each case was a panic, a hang or runaway
//! memory; each is now a message and exit code 2 (or, for a closed pipe, a quiet exit).

use crate::common;

use common::{assert_usage_error, photon, stderr, temp_dir};
use std::process::{Command, Stdio};

const SPHERE: &str = r#"
[camera]
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
[materials.white]
type = "diffuse"
[[shapes]]
type = "sphere"
radius = 1.0
material = "white"
[[lights]]
type = "point"
position = [0.0, 2.0, 2.0]
power = 50.0
"#;

/// A small PPM render of `s.toml` in `dir` into `out`, with `extra` flags.
fn ppm(dir: &std::path::Path, out: &str, passes: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "render",
        "s.toml",
        "--integrator",
        "ppm",
        "--passes",
        passes,
        "--photons-per-pass",
        "2000",
        "--width",
        "16",
        "--height",
        "16",
        "-q",
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    photon(&args, dir)
}

/// A long PPM render of `s.toml` in `dir` into `out` (`photons` per pass), started in the
/// background and waited on until its first checkpoint is written (up to a minute).
fn ppm_until_checkpoint(dir: &std::path::Path, out: &str, photons: &str) -> std::process::Child {
    let child = Command::new(env!("CARGO_BIN_EXE_photon"))
        .args([
            "render",
            "s.toml",
            "--integrator",
            "ppm",
            "--passes",
            "100000",
            "--photons-per-pass",
            photons,
            "--width",
            "16",
            "--height",
            "16",
            "-q",
            "-o",
            out,
        ])
        .current_dir(dir)
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let ck = dir.join(out).with_extension("checkpoint");
    let mut waited = 0;
    while !ck.exists() && waited < 1200 {
        std::thread::sleep(std::time::Duration::from_millis(50));
        waited += 1;
    }
    assert!(ck.exists(), "no checkpoint after the first pass");
    child
}

fn tiny(dir: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "render", "s.toml", "--width", "8", "--height", "8", "-q", "-o", "x.png",
    ];
    args.extend_from_slice(extra);
    photon(&args, dir)
}

#[test]
fn out_of_range_flags_are_refused() {
    let dir = temp_dir("hardening-flags");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    for (args, needle) in [
        (vec!["--k", "4294967295"], "--k"),
        (vec!["--k", "18446744073709551615"], "--k"),
        (vec!["--threads", "10000"], "--threads"),
        (vec!["--exposure", "nan"], "--exposure"),
        (vec!["--exposure", "1e30"], "--exposure"),
        // A seed TOML cannot write (scene files, job manifests), and counts that would never end.
        (
            vec!["--seed", "18446744073709551615"],
            "--seed 18446744073709551615: must be at most 9223372036854775807",
        ),
        (
            vec!["--integrator", "path", "--max-depth", "100000"],
            "--max-depth 100000: must be at most 65536",
        ),
        (vec!["--light-samples", "70000"], "--light-samples 70000"),
        (
            vec!["--resume", "x.checkpoint", "--spp", "4"],
            "--resume goes on with the checkpoint's own settings",
        ),
        (vec!["--indirect-scale", "3.4e38"], "--indirect-scale"),
        // Flags the integrator does not read were accepted and ignored.
        (
            vec!["--checkpoint", "c.checkpoint"],
            "for --integrator sppm or ppm",
        ),
        (vec!["--snapshots"], "for --integrator sppm or ppm"),
        (
            vec!["--integrator", "path", "--gather-rays", "8"],
            "--gather-rays 8: the path integrator does not take it (it is for photon)",
        ),
    ] {
        let o = tiny(&dir, &args);
        assert_usage_error(&o, needle);
    }
    // Resolutions whose pixels alone would not fit: refused with the estimate, before any
    // allocation (SPPM at 32768² aborted asking for 68 GB).
    for integrator in [
        &["--integrator", "sppm", "--passes", "1"][..],
        &["--integrator", "path"],
    ] {
        let mut args = vec![
            "render", "s.toml", "--width", "32768", "--height", "32768", "-q", "-o", "big.exr",
        ];
        args.extend_from_slice(integrator);
        let o = photon(&args, &dir);
        assert_usage_error(&o, "GB for its pixels");
    }
}

#[test]
fn coordinates_beyond_the_limit_are_errors_not_bvh_panics() {
    let dir = temp_dir("hardening-coords");
    for (what, text) in [
        ("sphere", SPHERE.replace("radius = 1.0", "radius = 5e18")),
        (
            "box",
            SPHERE.replace(
                "type = \"sphere\"\nradius = 1.0",
                "type = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1e19, 1.0, 1.0]",
            ),
        ),
    ] {
        std::fs::write(dir.join("s.toml"), text).expect("write");
        let o = tiny(&dir, &[]);
        assert_usage_error(&o, "beyond");
        // Located at the shape's table (line 7 of SPHERE), named as the file names it.
        assert!(
            stderr(&o).contains("s.toml:7:1: shape 1 reaches"),
            "{what}: {}",
            stderr(&o)
        );
    }
}

/// Problems that only the scene build finds were reported with no file or line.
#[test]
fn build_errors_name_the_file_line_and_item() {
    let dir = temp_dir("hardening-build-errors");
    let light = |body: &str| format!("{SPHERE}[[lights]]\n{body}\n");
    for (text, needle) in [
        (
            // An emitter given by its power on a quad of no area.
            light(
                "type = \"quad\"\nvertices = [[0,2,0],[0,2,0],[0,2,0],[0,2,0]]\npower = [10, 10, 10]",
            ),
            "s.toml:15:1: light 2: an emitter given by its power has no area",
        ),
        (
            SPHERE.replace(
                "material = \"white\"",
                "material = \"white\"\ntransform = [{ scale = [1.0, 2.0, 1.0] }]",
            ),
            "s.toml:7:1: shape 1: spheres and disks accept only rotation, translation and uniform scale",
        ),
        (
            // Finite power over a sliver of area: the radiance overflows.
            light(
                "type = \"quad\"\nvertices = [[0,2,0],[1e-9,2,0],[1e-9,2,1e-9],[0,2,1e-9]]\npower = [3e38, 3e38, 3e38]",
            ),
            "s.toml:15:1: light 2 has an invalid emission",
        ),
        (
            SPHERE
                .replace("[0.0, 0.0, 4.0]", "[0.0, 0.0, 3e38]")
                .replace("look_at = [0.0, 0.0, 0.0]", "look_at = [0.0, 0.0, -3e38]"),
            "s.toml:2:1: [camera]: the camera is degenerate",
        ),
    ] {
        std::fs::write(dir.join("s.toml"), text).expect("write");
        let o = tiny(&dir, &[]);
        assert_usage_error(&o, needle);
    }
}

/// An OBJ whose material library has `Kd 1 2`: `tobj` panicked; now the line is named.
#[test]
fn malformed_mtl_lines_are_located() {
    let dir = temp_dir("hardening-mtl");
    std::fs::write(
        dir.join("m.obj"),
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    )
    .expect("write");
    for (mtl, needle) in [
        ("newmtl a\nKd 1 2\n", "m.mtl:2"),
        ("newmtl a\nNs abc\n", "m.mtl:2"),
        ("newmtl a\nKd nan 1 1\n", "m.mtl:2"),
    ] {
        std::fs::write(dir.join("m.mtl"), mtl).expect("write");
        let scene = SPHERE.replace(
            "type = \"sphere\"\nradius = 1.0\nmaterial = \"white\"",
            "type = \"mesh\"\nfile = \"m.obj\"",
        );
        std::fs::write(dir.join("s.toml"), scene).expect("write");
        let o = tiny(&dir, &[]);
        assert_usage_error(&o, needle);
    }
    // A colour of one number is the format's grey, not a panic (found by fuzzing `tobj`).
    std::fs::write(dir.join("m.mtl"), "newmtl a\nKd  0.5\n").expect("write");
    let o = tiny(&dir, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Devices, FIFOs and directories named as inputs are refused at once: they were read until
/// memory ran out, or waited on forever, or reported as "not found".
#[test]
fn non_regular_files_are_refused_by_name() {
    let dir = temp_dir("hardening-files");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    let fifo = dir.join("fifo.pfm");
    let _ = std::fs::remove_file(&fifo);
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    let zero = dir.join("zero.pfm");
    let _ = std::fs::remove_file(&zero);
    std::os::unix::fs::symlink("/dev/zero", &zero).expect("symlink");
    let mut inputs = vec![
        (
            vec!["compare", "zero.pfm", "zero.pfm"],
            "not a regular file",
        ),
        (vec!["compare", "sub.pfm", "sub.pfm"], "directory"),
        (vec!["photons", "info", "/dev/zero"], "not a regular file"),
        (
            vec![
                "render",
                "s.toml",
                "--photon-map",
                "/dev/zero",
                "-q",
                "-o",
                "x.png",
            ],
            "not a regular file",
        ),
    ];
    std::fs::create_dir_all(dir.join("sub.pfm")).expect("mkdir");
    if made {
        inputs.push((
            vec!["compare", "fifo.pfm", "fifo.pfm"],
            "not a regular file",
        ));
    }
    for (args, needle) in inputs {
        let o = photon(&args, &dir);
        assert_usage_error(&o, needle);
    }
    // /dev/zero as a material library: refused, not read forever.
    std::fs::write(
        dir.join("z.obj"),
        "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .expect("write");
    let scene = SPHERE.replace(
        "type = \"sphere\"\nradius = 1.0\nmaterial = \"white\"",
        "type = \"mesh\"\nfile = \"z.obj\"\nmaterial = \"white\"",
    );
    std::fs::write(dir.join("s.toml"), scene).expect("write");
    let o = tiny(&dir, &[]);
    assert_usage_error(&o, "not a regular file");
}

/// `photon compare … | head -1`: the reader goes away; Photon ends quietly instead of panicking.
#[test]
fn a_closed_pipe_is_not_a_panic() {
    let dir = temp_dir("hardening-pipe");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    let o = photon(
        &[
            "render", "s.toml", "--width", "8", "--height", "8", "-q", "-o", "a.pfm",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for _ in 0..5 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_photon"))
            .args(["compare", "a.pfm", "a.pfm"])
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("waits");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{err}");
        assert_ne!(out.status.code(), Some(101), "{err}");
    }
}

/// Two identical renders write identical OpenEXR files (the blocks were in the order the
/// compressing threads finished).
#[test]
fn exr_files_are_byte_identical_across_runs() {
    let dir = temp_dir("hardening-exr");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    let mut files = Vec::new();
    for name in ["a.exr", "b.exr"] {
        let o = photon(
            &[
                "render",
                "s.toml",
                "--integrator",
                "path",
                "--spp",
                "1",
                "--width",
                "512",
                "--height",
                "512",
                "-q",
                "-o",
                name,
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", stderr(&o));
        files.push(std::fs::read(dir.join(name)).expect("reads"));
    }
    assert!(files[0] == files[1], "the two EXR files differ");
}

/// A tiny glTF whose nodes share children (each node's children are the next two): 60 levels
/// place a one-triangle mesh about 10¹² times. It took 3.2 GB before aborting at 40 levels;
/// now the walk stops at the limit with a message.
#[test]
fn gltf_node_sharing_is_bounded() {
    let dir = temp_dir("hardening-gltf");
    let mut bin = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for x in v {
            bin.extend_from_slice(&x.to_le_bytes());
        }
    }
    let levels = 60;
    let nodes: Vec<serde_json::Value> = (0..levels)
        .map(|i| {
            let children: Vec<usize> = [i + 1, i + 2].into_iter().filter(|&c| c < levels).collect();
            if children.is_empty() {
                serde_json::json!({"mesh": 0})
            } else {
                serde_json::json!({"mesh": 0, "children": children})
            }
        })
        .collect();
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36}]
    });
    std::fs::write(dir.join("bomb.glb"), common::glb(&doc, &bin)).expect("write");
    let o = photon(
        &[
            "render", "bomb.glb", "--width", "8", "--height", "8", "-q", "-o", "x.png",
        ],
        &dir,
    );
    assert_usage_error(&o, "node hierarchy");
}

/// Careless paths that destroyed the user's files: a checkpoint over the scene file or over the
/// image, and `--export` over the scene it reads. A SIGKILLed writer's `.partial` file is
/// cleaned up by the next write of the same file.
#[test]
fn nothing_the_user_had_is_overwritten() {
    let dir = temp_dir("hardening-lost");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    for (args, needle) in [
        (vec!["--checkpoint", "s.toml"], "scene file"),
        (vec!["--checkpoint", "out.exr"], "output image"),
        (vec!["--checkpoint", "other.toml"], "not a scene file"),
    ] {
        let mut full = vec![
            "render",
            "s.toml",
            "--integrator",
            "ppm",
            "--passes",
            "1",
            "--photons-per-pass",
            "1000",
            "--width",
            "8",
            "--height",
            "8",
            "-q",
            "-o",
            "out.exr",
        ];
        full.extend_from_slice(&args);
        let o = photon(&full, &dir);
        assert_usage_error(&o, needle);
    }
    assert_eq!(
        std::fs::read_to_string(dir.join("s.toml")).expect("reads"),
        SPHERE
    );
    let o = photon(&["scenes", "--export", "s.toml", "-o", "s.toml"], &dir);
    assert_usage_error(&o, "write over");
    assert_eq!(
        std::fs::read_to_string(dir.join("s.toml")).expect("reads"),
        SPHERE
    );
    // A partial file of this host's process that is gone (PID 0x7ffffffe does not run)
    // disappears.
    let host = photon::io::atomic::host_name();
    let stale = dir.join(format!(".x.png.{host}.2147483646.partial"));
    std::fs::write(&stale, b"left by a killed writer").expect("write");
    let o = tiny(&dir, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists(), "the stale partial file is still there");
}

/// A new render does not replace another's checkpoint; a SIGKILL after the first pass leaves
/// a checkpoint (there was none for 30 s); resuming it gives the bytes of an uninterrupted run.
#[test]
fn checkpoints_survive_reruns_and_kills() {
    let dir = temp_dir("hardening-kill");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    let o = ppm(&dir, "good.exr", "3", &["--keep-checkpoint"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(dir.join("good.checkpoint")).expect("checkpoint");
    let o = ppm(&dir, "good.exr", "1", &[]);
    assert_usage_error(&o, "--resume");
    assert_eq!(
        std::fs::read(dir.join("good.checkpoint")).expect("still there"),
        before
    );

    // Killed mid-run: the checkpoint of its first passes is there and resumes exactly.
    let mut child = ppm_until_checkpoint(&dir, "k.exr", "2000");
    let ck = dir.join("k.checkpoint");
    child.kill().expect("SIGKILL");
    let _ = child.wait();
    let o = photon(
        &["render", "--resume", "k.checkpoint", "--passes", "4", "-q"],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = ppm(&dir, "whole.exr", "4", &["--keep-checkpoint"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let resumed = photon::io::checkpoint::load(&ck).expect("loads");
    let whole = photon::io::checkpoint::load(&dir.join("whole.checkpoint")).expect("loads");
    assert_eq!(resumed.passes, whole.passes);
    assert!(
        resumed.pixels == whole.pixels,
        "a resumed run differs from an uninterrupted one"
    );
}

/// Numbers read from files follow the TOML reader's rules: an OBJ vertex of NaN, a face of two
/// vertices, a PLY vertex of Inf, a glTF light of negative intensity and a negative base
/// colour were all accepted (some dropped silently, some lighting the scene negatively).
#[test]
fn non_finite_and_negative_numbers_in_files_are_errors() {
    let dir = temp_dir("hardening-numbers");
    let mesh_scene = |file: &str| {
        SPHERE.replace(
            "type = \"sphere\"\nradius = 1.0",
            &format!("type = \"mesh\"\nfile = \"{file}\""),
        )
    };
    for (name, text, needle) in [
        (
            "nan.obj",
            "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "nan.obj:1",
        ),
        ("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "two.obj:4"),
    ] {
        std::fs::write(dir.join(name), text).expect("write");
        std::fs::write(dir.join("s.toml"), mesh_scene(name)).expect("write");
        assert_usage_error(&tiny(&dir, &[]), needle);
    }
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\ninf 0 0\n0 1 0\n3 0 1 2\n";
    std::fs::write(dir.join("inf.ply"), ply).expect("write");
    std::fs::write(dir.join("s.toml"), mesh_scene("inf.ply")).expect("write");
    assert_usage_error(&tiny(&dir, &[]), "inf.ply");
    // Binary PLY reads NaN as a number: the scene refuses the triangle that uses it.
    let mut bin_ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for v in [[0.0f32, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for x in v {
            bin_ply.extend_from_slice(&x.to_le_bytes());
        }
    }
    bin_ply.push(3);
    for i in [0i32, 1, 2] {
        bin_ply.extend_from_slice(&i.to_le_bytes());
    }
    std::fs::write(dir.join("nan.ply"), bin_ply).expect("write");
    std::fs::write(dir.join("s.toml"), mesh_scene("nan.ply")).expect("write");
    assert_usage_error(&tiny(&dir, &[]), "non-finite");
    // glTF: a light of negative intensity, a material of negative base colour.
    let mut bin = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for x in v {
            bin.extend_from_slice(&x.to_le_bytes());
        }
    }
    let gltf = |material: serde_json::Value, intensity: f32| {
        serde_json::json!({
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": intensity}]}},
            "scene": 0,
            "scenes": [{"nodes": [0, 1]}],
            "nodes": [{"mesh": 0}, {"translation": [0.0, 0.0, 2.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
            "materials": [material],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "buffers": [{"byteLength": 36}]
        })
    };
    for (doc, needle) in [
        (
            gltf(serde_json::json!({"name": "m"}), -100.0),
            "not negative",
        ),
        (
            gltf(
                serde_json::json!({"name": "m", "pbrMetallicRoughness": {"baseColorFactor": [-1.0, 0.5, 0.5, 1.0]}}),
                100.0,
            ),
            "negative",
        ),
    ] {
        std::fs::write(dir.join("bad.glb"), common::glb(&doc, &bin)).expect("write");
        let o = photon(
            &[
                "render", "bad.glb", "--width", "8", "--height", "8", "-q", "-o", "x.png",
            ],
            &dir,
        );
        assert_usage_error(&o, needle);
    }
}

/// `--resume` from another folder finds the image (the checkpoint held a relative path), and
/// keeps the run's `--exposure` (it was not stored, and the resumed PNG came out at 0).
#[test]
fn resume_works_from_anywhere_and_keeps_the_exposure() {
    let dir = temp_dir("hardening-resume");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    assert!(
        ppm(
            &dir,
            "r.png",
            "2",
            &["--exposure", "2", "--keep-checkpoint"]
        )
        .status
        .success()
    );
    assert!(
        ppm(&dir, "whole.png", "3", &["--exposure", "2"])
            .status
            .success()
    );
    let elsewhere = temp_dir("hardening-resume-elsewhere");
    let checkpoint = dir.join("r.checkpoint");
    let o = photon(
        &[
            "render",
            "--resume",
            checkpoint.to_str().expect("utf-8"),
            "--passes",
            "3",
            "-q",
        ],
        &elsewhere,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (
        std::fs::read(dir.join("r.png")).expect("resumed image where it was"),
        std::fs::read(dir.join("whole.png")).expect("whole"),
    );
    assert!(
        a == b,
        "the resumed PNG differs from an uninterrupted one at the same exposure"
    );
}

/// The inputs fuzzing found panics with (`fuzz/corpus/*/regression-*`), fed the way the fuzz
/// targets feed them: errors or scenes now, never panics.
#[test]
fn fuzzing_regressions_stay_fixed() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus");
    let dir = temp_dir("hardening-fuzz");
    let mut seen = 0;
    for target in ["mesh_files", "gltf"] {
        for entry in std::fs::read_dir(root.join(target)).expect("corpus") {
            let path = entry.expect("entry").path();
            if !path
                .file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("regression-"))
            {
                continue;
            }
            seen += 1;
            let data = std::fs::read(&path).expect("reads");
            let result = std::panic::catch_unwind(|| match target {
                "mesh_files" => {
                    let (kind, rest) = data.split_first().expect("a kind byte");
                    let file = if kind % 2 == 0 {
                        let (obj, mtl) = match rest.iter().position(|&b| b == 0) {
                            Some(i) => (&rest[..i], &rest[i + 1..]),
                            None => (rest, &[][..]),
                        };
                        std::fs::write(dir.join("m.mtl"), mtl).expect("write");
                        std::fs::write(dir.join("f.obj"), obj).expect("write");
                        dir.join("f.obj")
                    } else {
                        std::fs::write(dir.join("f.ply"), rest).expect("write");
                        dir.join("f.ply")
                    };
                    let _ = photon::description::load_mesh_file(&file);
                }
                _ => {
                    std::fs::write(dir.join("f.glb"), &data).expect("write");
                    if let Ok(mut l) = photon::description::gltf::import_scene(&dir.join("f.glb")) {
                        let _ = photon::description::build::build_with(&l.desc, &mut l.meshes);
                    }
                }
            });
            assert!(result.is_ok(), "{} panics again", path.display());
        }
    }
    assert!(seen >= 2, "the regression inputs are in the corpus");
}

/// A first Ctrl-C finishes the pass and saves; a second one, even at once (`timeout` signals
/// the process and its group), abandons the pass in flight: the checkpoint of the completed
/// passes and their image are still written, and the render exits with 130.
#[test]
fn a_second_interrupt_abandons_the_pass_and_keeps_the_work() {
    let dir = temp_dir("hardening-sigint");
    std::fs::write(dir.join("s.toml"), SPHERE).expect("write");
    // Passes of 12 M photons take about a second here: both signals arrive within one.
    let child = ppm_until_checkpoint(&dir, "i.exr", "12000000");
    let pid = child.id().to_string();
    for _ in 0..2 {
        let _ = Command::new("kill").args(["-TERM", &pid]).status();
    }
    let out = child.wait_with_output().expect("waits");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(130), "{err}");
    let state = photon::io::checkpoint::load(&dir.join("i.checkpoint")).expect("the checkpoint");
    assert!(
        err.contains(&format!("interrupted after pass {};", state.passes)),
        "the checkpoint holds every completed pass: {} passes; {err}",
        state.passes
    );
    let image = photon::io::image::read_image(&dir.join("i.exr")).expect("the image is written");
    assert_eq!(image.pixels, state.image().pixels);
    // Resuming the checkpoint continues where the completed passes end.
    let o = photon(
        &[
            "render",
            "--resume",
            "i.checkpoint",
            "--passes",
            &(state.passes + 1).to_string(),
            "-q",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
}
