//! Scene files from the command line: `photon scenes --export` and rendering the file gives
//! the built-in's image byte for byte; a file's [render] settings apply unless a flag
//! overrides them; glTF files render and report what they could not map.

use crate::common;

use common::photon;
use std::process::Output;

fn ok(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "photon failed: {err}");
    err
}

const FAST: &[&str] = &[
    "--width",
    "24",
    "--height",
    "24",
    "--spp",
    "1",
    "--photons",
    "20000",
    "--caustic-photons",
    "20000",
    "-q",
];

#[test]
fn exported_built_ins_render_to_the_same_bytes() {
    let dir = common::temp_dir("cli-export");
    for name in ["seed", "cornell"] {
        let file = format!("{name}.toml");
        ok(&photon(&["scenes", "--export", name, "-o", &file], &dir));
        let text = std::fs::read_to_string(dir.join(&file)).expect("exported");
        assert!(
            text.contains("[camera]") && text.contains("[[lights]]"),
            "{text}"
        );
        let (a, b) = (format!("{name}-builtin.pfm"), format!("{name}-file.pfm"));
        ok(&photon(&[&["render", name, "-o", &a], FAST].concat(), &dir));
        ok(&photon(
            &[&["render", &file, "-o", &b], FAST].concat(),
            &dir,
        ));
        let (a, b) = (
            std::fs::read(dir.join(a)).expect("a"),
            std::fs::read(dir.join(b)).expect("b"),
        );
        assert!(a.len() > 24 * 24 * 12);
        assert!(a == b, "{name}: the exported file renders differently");
    }
    // The export refuses other extensions and unknown scenes, with exit code 2.
    let o = photon(&["scenes", "--export", "seed", "-o", "seed.json"], &dir);
    assert_eq!(o.status.code(), Some(2));
    let o = photon(&["scenes", "--export", "nope", "-o", "x.toml"], &dir);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("unknown scene 'nope'"));
}

#[test]
fn scene_render_settings_apply_unless_overridden() {
    let dir = common::temp_dir("cli-settings");
    std::fs::write(
        dir.join("s.toml"),
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nresolution = [20, 10]\n\
         [render]\nintegrator = \"direct\"\nspp = 2\nphotons = 1000\n\
         [materials.m]\ntype = \"diffuse\"\n\
         [[shapes]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 2, 2]\npower = 50\n",
    )
    .expect("write");
    let summary = |args: &[&str]| -> String {
        let err = ok(&photon(
            &[&["render", "s.toml", "-o", "x.png", "-q"], args].concat(),
            &dir,
        ));
        err.lines().last().unwrap_or_default().to_owned()
    };
    let s = summary(&[]);
    assert!(s.contains("20×10 2 spp (direct)"), "{s}");
    let s = summary(&["--spp", "3", "--width", "8"]);
    assert!(s.contains("8×10 3 spp (direct)"), "{s}");
    // photons = … in the file belongs to the photon integrator: path ignores it.
    let s = summary(&["--integrator", "path"]);
    assert!(s.contains("(path"), "{s}");
    let s = summary(&["--integrator", "photon"]);
    assert!(s.contains("(photon)"), "{s}");
}

#[test]
fn photon_settings_in_the_scene_equal_the_same_flags() {
    let dir = common::temp_dir("cli-photon-settings");
    let scene = |render: &str| {
        format!(
            "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nresolution = [16, 16]\n\
             [render]\nspp = 1\nphotons = 2000\ncaustic_photons = 2000\n{render}\
             [materials.m]\ntype = \"diffuse\"\n\
             [[shapes]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n\
             [[shapes]]\ntype = \"quad\"\nvertices = [[-3, -1, -3], [-3, -1, 3], [3, -1, 3], [3, -1, -3]]\nmaterial = \"m\"\n\
             [[lights]]\ntype = \"point\"\nposition = [0, 2, 2]\npower = 50\n"
        )
    };
    std::fs::write(dir.join("plain.toml"), scene("")).expect("write");
    std::fs::write(
        dir.join("tuned.toml"),
        scene("kernel = \"box\"\ngather = \"none\"\nk = 8\nfilter = \"gaussian:0.5\"\n"),
    )
    .expect("write");
    let run = |args: &[&str], out: &str| {
        ok(&photon(&[args, &["-o", out, "-q"]].concat(), &dir));
        std::fs::read(dir.join(out)).expect("image")
    };
    let tuned = run(&["render", "tuned.toml"], "tuned.pfm");
    let flags = run(
        &[
            "render",
            "plain.toml",
            "--kernel",
            "box",
            "--gather",
            "none",
            "--k",
            "8",
            "--filter",
            "gaussian:0.5",
        ],
        "flags.pfm",
    );
    let plain = run(&["render", "plain.toml"], "plain.pfm");
    assert!(tuned == flags, "the file's settings act as the flags do");
    assert!(tuned != plain, "the settings change the image");
}

#[test]
fn gltf_files_render_and_report_what_they_cannot_map() {
    let dir = common::temp_dir("cli-gltf");
    // A triangle lit by a directional light (photometric: 683 lux = 1 W/m²) and a point light,
    // with no camera.
    let bin: Vec<u8> = [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    use base64::Engine;
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bin)
    );
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "intensity": 683.0},
            {"type": "point", "intensity": 6830.0}
        ]}},
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [0.0, 0.0, 2.0], "extensions": {"KHR_lights_punctual": {"light": 1}}}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36, "uri": uri}]
    });
    std::fs::write(
        dir.join("tri.gltf"),
        serde_json::to_vec_pretty(&doc).expect("json"),
    )
    .expect("write");
    let err = ok(&photon(
        &[
            &[
                "render",
                "tri.gltf",
                "-o",
                "tri.pfm",
                "--integrator",
                "direct",
            ],
            &FAST[..6],
        ]
        .concat(),
        &dir,
    ));
    assert!(
        err.contains("warning:") && err.contains("no perspective camera"),
        "{err}"
    );
    // Framed from +z, the lit triangle fills the middle of the image.
    let img = photon::io::image::read_image(&dir.join("tri.pfm")).expect("image");
    let centre = img.pixels[(12 * 24 + 12) as usize];
    assert!(centre.x > 0.0, "the triangle is lit: {centre:?}");

    // The Blender-exported seed scene renders from the command line.
    let seed = common::shared_dir().join("seed/seed_scene.glb");
    let seed = seed.to_string_lossy();
    ok(&photon(
        &[&["render", &seed, "-o", "seed.png"], FAST].concat(),
        &dir,
    ));
    assert!(dir.join("seed.png").exists());
}
