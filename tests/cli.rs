//! The `photon` binary as a user runs it: tiny renders in a temporary folder, and bad input
//! that must give a clear message and exit code 2, never a panic.

use crate::common;

use common::{assert_usage_error, photon, stderr};

#[test]
fn renders_every_format_and_compares() {
    let dir = common::temp_dir("formats");
    for out in ["a.png", "a.exr", "a.pfm"] {
        let o = photon(
            &[
                "render", "cornell", "--width", "16", "--height", "12", "--spp", "2", "-q", "-o",
                out,
            ],
            &dir,
        );
        assert!(o.status.success(), "{out}: {}", stderr(&o));
        assert!(dir.join(out).metadata().expect("written").len() > 100);
        assert!(
            stderr(&o).contains("rays/s"),
            "summary line: {}",
            stderr(&o)
        );
    }
    let png = image::open(dir.join("a.png")).expect("valid PNG");
    assert_eq!((png.width(), png.height()), (16, 12));
    // EXR and PFM hold the same linear image.
    let o = photon(&["compare", "a.pfm", "a.exr", "--json"], &dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["overall"]["rmse"].as_f64(), Some(0.0));
    assert_eq!(v["overall"]["mean_ratio"].as_f64(), Some(1.0));
    let o = photon(&["compare", "a.pfm", "a.exr"], &dir);
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("relMSE") && table.contains("overall"),
        "{table}"
    );
    // No partial files are left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .expect("list")
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".partial"))
        .collect();
    assert!(leftovers.is_empty());
}

/// An EXR's channels, by name, in the file's order.
type Channels = Vec<(String, Vec<f32>)>;

/// The channels of an EXR's first layer, and its header's chromaticities.
fn exr_channels(path: &std::path::Path) -> (Channels, Option<[f32; 8]>) {
    let image = exr::prelude::read_first_flat_layer_from_file(path).expect("a readable EXR");
    let channels = image
        .layer_data
        .channel_data
        .list
        .iter()
        .map(|c| {
            let values = c.sample_data.values_as_f32().collect();
            (c.name.to_string(), values)
        })
        .collect();
    let chromaticities = image.attributes.chromaticities.map(|c| {
        [
            c.red.0, c.red.1, c.green.0, c.green.1, c.blue.0, c.blue.1, c.white.0, c.white.1,
        ]
    });
    (channels, chromaticities)
}

#[test]
fn xyz_output_is_the_same_light_in_cie_xyz() {
    let dir = common::temp_dir("xyz");
    let render = |extra: &[&str]| {
        let mut args = vec![
            "render",
            "cornell",
            "--spectral",
            "--integrator",
            "sppm",
            "--passes",
            "2",
            "--photons-per-pass",
            "4000",
            "--width",
            "12",
            "--height",
            "10",
            "-q",
        ];
        args.extend(extra);
        let o = photon(&args, &dir);
        assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
    };
    render(&["-o", "rgb.exr"]);
    render(&["--xyz", "-o", "xyz.exr"]);
    let (rgb, none) = exr_channels(&dir.join("rgb.exr"));
    let (xyz, primaries) = exr_channels(&dir.join("xyz.exr"));
    assert_eq!(
        none, None,
        "an RGB file keeps OpenEXR's default (Rec. 709) primaries"
    );
    let names = |c: &[(String, Vec<f32>)]| c.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    assert_eq!(names(&rgb), ["B", "G", "R"]);
    assert_eq!(names(&xyz), ["X", "Y", "Z"]);
    // OpenEXR's chromaticities of XYZ data.
    assert_eq!(
        primaries,
        Some([1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0 / 3.0, 1.0 / 3.0])
    );
    // IEC 61966-2-1's matrix from linear sRGB to XYZ: Y is luminance. The walls are lit:
    // the image is not black.
    let (b, g, r) = (&rgb[0].1, &rgb[1].1, &rgb[2].1);
    let (x, y, z) = (&xyz[0].1, &xyz[1].1, &xyz[2].1);
    let mut lit = 0;
    for i in 0..r.len() {
        let expected = [
            0.4124 * r[i] + 0.3576 * g[i] + 0.1805 * b[i],
            0.2126 * r[i] + 0.7152 * g[i] + 0.0722 * b[i],
            0.0193 * r[i] + 0.1192 * g[i] + 0.9505 * b[i],
        ];
        for (got, want) in [x[i], y[i], z[i]].into_iter().zip(expected) {
            assert!(
                (got - want).abs() <= 1e-3 * want.abs().max(1e-3),
                "pixel {i}: {got} vs {want}"
            );
        }
        lit += usize::from(y[i] > 0.0);
    }
    assert!(lit > r.len() / 2, "{lit} lit pixels of {}", r.len());
    // XYZ is written to OpenEXR only, and refused before rendering otherwise.
    let o = photon(&["render", "cornell", "--xyz", "-o", "x.png"], &dir);
    assert_usage_error(&o, "exr");
    assert!(!dir.join("x.png").exists());
}

#[test]
fn default_render_writes_render_png() {
    let dir = common::temp_dir("default");
    let o = photon(
        &[
            "render", "--width", "24", "--height", "24", "--spp", "1", "-q",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(dir.join("render.png"))
        .expect("render.png")
        .to_rgb8();
    // The seed scene: red wall on the left, green on the right.
    let left = img.get_pixel(2, 12);
    let right = img.get_pixel(21, 12);
    assert!(left[0] > 2 * left[1].max(1), "left wall is red: {left:?}");
    assert!(
        right[1] > 2 * right[0].max(1),
        "right wall is green: {right:?}"
    );
}

#[test]
fn scenes_lists_the_built_ins() {
    let dir = common::temp_dir("scenes");
    let o = photon(&["scenes"], &dir);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    for name in ["seed", "cornell", "closed-sphere"] {
        assert!(
            out.lines().any(|l| l.starts_with(name)),
            "{name} missing from: {out}"
        );
    }
}

#[test]
fn bad_input_gives_a_message_and_exit_code_2() {
    let dir = common::temp_dir("bad");
    let tiny = ["--width", "8", "--height", "8", "--spp", "1", "-q"];
    let with = |extra: &[&str]| -> Vec<String> {
        extra
            .iter()
            .chain(tiny.iter())
            .map(|s| s.to_string())
            .collect()
    };
    let run =
        |args: Vec<String>| photon(&args.iter().map(String::as_str).collect::<Vec<_>>(), &dir);

    assert_usage_error(
        &run(with(&["render", "nosuchscene"])),
        "unknown scene 'nosuchscene'",
    );
    assert_usage_error(
        &run(with(&["render", "-o", "/nonexistent-dir/x.png"])),
        "cannot write '/nonexistent-dir/x.png'",
    );
    assert_usage_error(
        &run(with(&["render", "-o", "out.bmp"])),
        "unsupported image format '.bmp'",
    );
    assert_usage_error(
        &run(with(&["render", "-o", "out"])),
        "unsupported image format",
    );
    let o = photon(&["render", "--width", "0", "-q"], &dir);
    assert_usage_error(&o, "--width 0: must be at least 1");
    let o = photon(&["render", "--spp", "0", "-q"], &dir);
    assert_usage_error(&o, "--spp 0: must be at least 1");
    let o = photon(&["render", "--filter", "gaussian:abc", "-q"], &dir);
    assert_usage_error(&o, "not a number");
    let o = photon(&["render", "--integrator", "magic", "-q"], &dir);
    assert_usage_error(&o, "magic");
    let o = photon(&["compare", "missing.exr", "also-missing.exr"], &dir);
    assert_usage_error(&o, "cannot read 'missing.exr'");
    std::fs::write(dir.join("garbage.exr"), b"not an exr").expect("write");
    std::fs::write(dir.join("short.pfm"), b"PF\n4 4\n-1.0\n\0\0").expect("write");
    let o = photon(&["compare", "garbage.exr", "short.pfm"], &dir);
    assert_usage_error(&o, "garbage.exr");
    let o = photon(&["compare", "short.pfm", "short.pfm"], &dir);
    assert_usage_error(&o, "truncated PFM");
    // Nothing was created by the failed renders.
    assert!(!dir.join("render.png").exists());
}

#[test]
fn an_existing_output_survives_a_failed_render() {
    let dir = common::temp_dir("survive");
    std::fs::write(dir.join("keep.png"), b"precious").expect("write");
    let o = photon(&["render", "nosuchscene", "-o", "keep.png"], &dir);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        std::fs::read(dir.join("keep.png")).expect("still there"),
        b"precious"
    );
}

#[test]
fn photons_trace_info_and_export() {
    let dir = common::temp_dir("photons");
    let o = photon(
        &[
            "photons",
            "trace",
            "cornell",
            "--photons",
            "20000",
            "-q",
            "-o",
            "c.phm",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("emitted/s"), "{}", stderr(&o));
    let o = photon(&["photons", "info", "c.phm"], &dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let info = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "scene:       cornell",
        "20000 photons emitted",
        "caustic  map:",
        "global   map:",
        "per depth:   1: ",
    ] {
        assert!(info.contains(needle), "'{needle}' missing from:\n{info}");
    }
    for (args, format) in [
        (
            vec!["--map", "caustic", "--color", "power"],
            "binary_little_endian",
        ),
        (
            vec![
                "--map",
                "global",
                "--depth",
                "2",
                "--channel",
                "r",
                "--ascii",
            ],
            "ascii",
        ),
        (vec!["--color", "depth"], "binary_little_endian"),
    ] {
        let mut all = vec!["photons", "export", "c.phm", "-o", "p.ply"];
        all.extend(args.iter());
        let o = photon(&all, &dir);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let bytes = std::fs::read(dir.join("p.ply")).expect("written");
        let text = String::from_utf8_lossy(&bytes);
        assert!(
            text.starts_with("ply\nformat ") && text.contains(format),
            "{args:?}"
        );
        let n: usize = text
            .lines()
            .find_map(|l| l.strip_prefix("element vertex "))
            .and_then(|n| n.parse().ok())
            .expect("vertex count");
        assert!(n > 0, "{args:?}: no photons exported");
        let header_end = text.find("end_header\n").expect("header") + "end_header\n".len();
        if format == "ascii" {
            assert_eq!(text[header_end..].lines().count(), n);
            // Depth 2 only.
            assert!(text[header_end..].lines().all(|l| l.ends_with(" 2")));
        } else {
            assert_eq!(
                bytes.len() - header_end,
                n * 32,
                "{args:?}: 32 bytes per vertex"
            );
        }
    }
}

#[test]
fn photons_bad_input_gives_exit_code_2() {
    let dir = common::temp_dir("photons-bad");
    let o = photon(
        &[
            "photons",
            "trace",
            "cornell",
            "--photons",
            "1000",
            "-q",
            "-o",
            "c.txt",
        ],
        &dir,
    );
    assert_usage_error(&o, "expected a .phm file name");
    let o = photon(&["photons", "trace", "nosuch", "-q", "-o", "c.phm"], &dir);
    assert_usage_error(&o, "unknown scene 'nosuch'");
    let o = photon(
        &[
            "photons",
            "trace",
            "cornell",
            "--photons",
            "0",
            "-q",
            "-o",
            "c.phm",
        ],
        &dir,
    );
    assert_usage_error(&o, "photon count 0");
    let o = photon(
        &[
            "photons",
            "trace",
            "cornell",
            "--absorption",
            "1.5",
            "-q",
            "-o",
            "c.phm",
        ],
        &dir,
    );
    assert_usage_error(&o, "absorption probability 1.5");
    let o = photon(&["photons", "info", "missing.phm"], &dir);
    assert_usage_error(&o, "cannot read 'missing.phm'");
    std::fs::write(dir.join("junk.phm"), b"PHOTONMP junk").expect("write");
    let o = photon(&["photons", "info", "junk.phm"], &dir);
    assert_usage_error(&o, "junk.phm");
    let o = photon(&["photons", "export", "junk.phm", "-o", "x.ply"], &dir);
    assert_usage_error(&o, "junk.phm");
}

#[test]
fn photon_render_writes_aov_layers_npy_and_reuses_saved_maps() {
    let dir = common::temp_dir("photon-render");
    let small = [
        "--width",
        "24",
        "--height",
        "24",
        "--spp",
        "1",
        "--photons",
        "20000",
        "--caustic-photons",
        "40000",
        "-q",
    ];
    let with = |extra: &[&str]| -> Vec<String> {
        extra
            .iter()
            .chain(small.iter())
            .map(|s| s.to_string())
            .collect()
    };
    let run =
        |args: Vec<String>| photon(&args.iter().map(String::as_str).collect::<Vec<_>>(), &dir);

    let o = run(with(&[
        "render",
        "cornell",
        "--integrator",
        "photon",
        "-o",
        "c.exr",
        "--aov",
        "direct,caustic,indirect,albedo,normal",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("trace")
            && stderr(&o).contains("build")
            && stderr(&o).contains("render"),
        "phase times: {}",
        stderr(&o)
    );
    let meta = exr::meta::MetaData::read_from_file(dir.join("c.exr"), false).expect("EXR");
    let names: Vec<String> = meta.headers[0]
        .channels
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    for layer in ["", "direct.", "caustic.", "indirect.", "albedo.", "normal."] {
        for c in ["R", "G", "B"] {
            assert!(
                names.contains(&format!("{layer}{c}")),
                "{layer}{c} missing from {names:?}"
            );
        }
    }
    // The beauty (plain R, G, B) is what readers show first: compare reads it.
    let o = photon(&["compare", "c.exr", "c.exr"], &dir);
    assert!(o.status.success(), "{}", stderr(&o));

    let o = run(with(&["render", "cornell", "-o", "c.npy"]));
    assert!(o.status.success(), "{}", stderr(&o));
    for ch in ["r", "g", "b"] {
        let bytes = std::fs::read(dir.join(format!("c_{ch}.npy"))).expect("npy per channel");
        assert_eq!(&bytes[..6], b"\x93NUMPY");
        let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        let header = String::from_utf8_lossy(&bytes[10..10 + header_len]);
        assert!(
            header.contains("'shape': (24, 24)") && header.contains("'<f4'"),
            "{header}"
        );
        assert_eq!((10 + header_len) % 64, 0);
        assert_eq!(bytes.len(), 10 + header_len + 24 * 24 * 4);
    }

    let o = run(with(&[
        "render",
        "seed",
        "--gather",
        "none",
        "--filter",
        "gaussian:0.5",
        "-o",
        "s.png",
        "--aov",
        "caustic",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("s.png").exists() && dir.join("s.caustic.png").exists());

    // Saved maps: reused for their scene, refused for another unless --force.
    let o = photon(
        &[
            "photons",
            "trace",
            "seed",
            "--photons",
            "20000",
            "-q",
            "-o",
            "seed.phm",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(with(&[
        "render",
        "seed",
        "--photon-map",
        "seed.phm",
        "-o",
        "from-map.png",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(with(&[
        "render",
        "cornell",
        "--photon-map",
        "seed.phm",
        "-o",
        "wrong.png",
    ]));
    assert_usage_error(&o, "traced for scene 'seed'");
    assert!(!dir.join("wrong.png").exists());
    let o = run(with(&[
        "render",
        "cornell",
        "--photon-map",
        "seed.phm",
        "--force",
        "-o",
        "forced.png",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));

    let path_with = |extra: &[&str]| {
        let mut args = vec!["render", "cornell", "--integrator", "path", "-q"];
        args.extend_from_slice(extra);
        photon(&args, &dir)
    };
    assert_usage_error(
        &path_with(&["--aov", "caustic", "-o", "p.exr"]),
        "need --integrator photon",
    );
    assert_usage_error(
        &path_with(&["--photon-map", "seed.phm", "-o", "x.png"]),
        "--photon-map is for --integrator photon",
    );
    let o = run(with(&["render", "cornell", "--radius=0", "-o", "r.png"]));
    assert_usage_error(&o, "--radius 0");
    let o = run(with(&[
        "render",
        "cornell",
        "--gather-rays",
        "0",
        "-o",
        "g.png",
    ]));
    assert_usage_error(&o, "--gather-rays 0: must be at least 1");
}

#[test]
fn model_pot_writes_obj_and_ply() {
    let dir = common::temp_dir("model");
    let o = photon(&["model", "pot", "-o", "pot.obj"], &dir);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("triangles"), "{}", stderr(&o));
    let obj = std::fs::read_to_string(dir.join("pot.obj")).expect("obj");
    for part in ["o pot", "o soil", "o leaves"] {
        assert!(obj.lines().any(|l| l == part), "{part} missing");
    }
    assert!(
        obj.lines().filter(|l| l.starts_with("vn ")).count()
            == obj.lines().filter(|l| l.starts_with("v ")).count()
    );
    let o = photon(
        &[
            "model",
            "pot",
            "-o",
            "pot.ply",
            "--subdivisions",
            "1",
            "--seed",
            "3",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let ply = std::fs::read_to_string(dir.join("pot.ply")).expect("ply");
    let faces: usize = ply
        .lines()
        .find_map(|l| l.strip_prefix("element face "))
        .and_then(|n| n.parse().ok())
        .expect("faces");
    let verts: usize = ply
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .and_then(|n| n.parse().ok())
        .expect("verts");
    let body = ply
        .lines()
        .skip_while(|l| *l != "end_header")
        .skip(1)
        .count();
    assert_eq!(body, faces + verts);
    assert_usage_error(
        &photon(&["model", "pot", "-o", "pot.stl"], &dir),
        "expected a .obj or .ply",
    );
    assert_usage_error(
        &photon(
            &["model", "pot", "-o", "p.obj", "--subdivisions", "9"],
            &dir,
        ),
        "too many",
    );
    assert_usage_error(&photon(&["model", "vase", "-o", "p.obj"], &dir), "vase");
}
