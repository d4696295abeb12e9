//! The reader against caches written by Blender 4.5's Mantaflow/OpenVDB 12 writer, with
//! reference numbers from OpenVDB's own Python module (`tests/fixtures/vdb/make_smoke.py` made them).

use photon::medium::vdb::{grid_names, read_float_grid};
use std::path::PathBuf;

const BAKES: [&str; 3] = [
    "smoke_blosc_half_f24",
    "smoke_zip_full_f24",
    "tiny_blosc_half",
];
const LIMIT: usize = 1 << 24;

fn data(name: &str, ext: &str) -> Vec<u8> {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "tests",
        "fixtures",
        "vdb",
        &format!("{name}.{ext}"),
    ]
    .iter()
    .collect();
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The `.ref` lines: `key v1 v2 ...`.
fn reference(name: &str) -> Vec<(String, Vec<String>)> {
    String::from_utf8(data(name, "ref"))
        .unwrap()
        .lines()
        .map(|l| {
            let mut words = l.split_whitespace().map(str::to_string);
            (words.next().unwrap(), words.collect())
        })
        .collect()
}

fn numbers(r: &[(String, Vec<String>)], key: &str) -> Vec<Vec<f64>> {
    r.iter()
        .filter(|(k, _)| k == key)
        .map(|(_, v)| v.iter().map(|s| s.parse().unwrap()).collect())
        .collect()
}

#[test]
fn every_bake_matches_the_openvdb_reference() {
    for bake in BAKES {
        let bytes = data(bake, "vdb");
        let r = reference(bake);
        let names: Vec<String> = r.iter().find(|(k, _)| k == "grids").unwrap().1.clone();
        let mut got_names = grid_names(&bytes).unwrap();
        got_names.sort();
        let mut want = names.clone();
        want.sort();
        assert_eq!(got_names, want, "{bake}");

        let g = read_float_grid(&bytes, "density", LIMIT).unwrap();
        let lo = &numbers(&r, "bbox_min")[0];
        let hi = &numbers(&r, "bbox_max")[0];
        for a in 0..3 {
            assert_eq!(g.index_min[a] as f64, lo[a], "{bake} bbox min");
            assert_eq!(
                g.resolution[a] as f64,
                hi[a] - lo[a] + 1.0,
                "{bake} resolution"
            );
        }
        let [nx, ny, nz] = g.resolution;
        assert_eq!(g.values.len(), nx * ny * nz);
        let sum: f64 = g.values.iter().map(|&v| v as f64).sum();
        let want_sum = numbers(&r, "sum")[0][0];
        assert!(
            (sum - want_sum).abs() <= 1e-9 * want_sum.abs().max(1.0),
            "{bake}: sum {sum} vs {want_sum}"
        );
        let max = g.values.iter().copied().fold(f32::MIN, f32::max);
        assert_eq!(max, numbers(&r, "max")[0][0] as f32, "{bake} max");
        for (row, want) in numbers(&r, "matrix_row").iter().enumerate() {
            for (c, w) in want.iter().enumerate() {
                assert!(
                    (g.index_to_world[row][c] - w).abs() < 1e-12,
                    "{bake} transform {row} {c}"
                );
            }
        }
        let samples = numbers(&r, "sample");
        assert!(samples.len() > 30);
        for s in samples {
            let d = [0, 1, 2].map(|a| (s[a] as i64 - g.index_min[a] as i64) as usize);
            let v = g.values[d[0] + nx * (d[1] + ny * d[2])];
            assert_eq!(v, s[3] as f32, "{bake} value at {:?}", &s[..3]);
        }
    }
}

#[test]
fn default_bake_is_blosc_half_version_224() {
    let bytes = data("smoke_blosc_half_f24", "vdb");
    assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), 224);
    assert_eq!(
        grid_names(&bytes).unwrap(),
        ["density", "heat", "flame", "velocity"]
    );
}

#[test]
fn other_grids_report_type_or_emptiness() {
    let bytes = data("smoke_blosc_half_f24", "vdb");
    let err = read_float_grid(&bytes, "velocity", LIMIT)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("unsupported grid type 'Tree_vec3s_5_4_3': only float grids"),
        "{err}"
    );
    let flame = read_float_grid(&bytes, "flame", LIMIT).unwrap();
    assert_eq!((flame.resolution, flame.values.len()), ([0, 0, 0], 0));
    let heat = read_float_grid(&bytes, "heat", LIMIT).unwrap();
    assert!(heat.values.iter().any(|&v| v > 1.0));
}

#[test]
fn wrong_grid_name_lists_the_grids() {
    let bytes = data("smoke_zip_full_f24", "vdb");
    let err = read_float_grid(&bytes, "smoke", LIMIT)
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("byte "), "{err}");
    assert!(
        err.ends_with("expected the grid 'smoke', the file has: density, heat, flame, velocity"),
        "{err}"
    );
}

#[test]
fn voxel_limit_is_enforced_before_allocating() {
    let bytes = data("smoke_blosc_half_f24", "vdb");
    let err = read_float_grid(&bytes, "density", 1000)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("26 x 17 x 36 voxels, more than the limit of 1000"),
        "{err}"
    );
    assert!(read_float_grid(&bytes, "density", 26 * 17 * 36).is_ok());
}

#[test]
fn truncated_files_are_errors() {
    for bake in BAKES {
        let bytes = data(bake, "vdb");
        let step = if bytes.len() > 400_000 { 997 } else { 97 };
        for len in (0..bytes.len()).step_by(step).chain([bytes.len() - 1]) {
            assert!(
                read_float_grid(&bytes[..len], "density", LIMIT).is_err(),
                "{bake} cut at {len}"
            );
            assert!(
                grid_names(&bytes[..len]).is_err(),
                "{bake} names cut at {len}"
            );
        }
    }
}

#[test]
fn flipped_bytes_never_panic() {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for bake in [
        "tiny_blosc_half",
        "smoke_zip_full_f24",
        "smoke_blosc_half_f24",
    ] {
        let clean = data(bake, "vdb");
        for _ in 0..150 {
            let mut bytes = clean.clone();
            // Half of the flips hit the header, grid table and topology, where sizes live.
            let range = if next() % 2 == 0 {
                bytes.len().min(20_000)
            } else {
                bytes.len()
            };
            for _ in 0..1 + next() % 3 {
                let at = (next() % range as u64) as usize;
                bytes[at] ^= 1 << (next() % 8);
            }
            let _ = read_float_grid(&bytes, "density", LIMIT);
            let _ = grid_names(&bytes);
        }
    }
}

#[test]
fn every_byte_of_the_tiny_bake_flipped_never_panics() {
    let clean = data("tiny_blosc_half", "vdb");
    for at in (0..clean.len()).step_by(5) {
        let mut bytes = clean.clone();
        bytes[at] ^= 0x80 >> (at % 8);
        let _ = read_float_grid(&bytes, "density", LIMIT);
    }
}

/// A longer random-mutation run: `VDB_STRESS=200000 cargo test --release -- --ignored`.
#[test]
#[ignore]
fn stress_random_mutations() {
    let rounds: usize = std::env::var("VDB_STRESS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for bake in [
        "tiny_blosc_half",
        "smoke_zip_full_f24",
        "smoke_blosc_half_f24",
    ] {
        let clean = data(bake, "vdb");
        for _ in 0..rounds / 3 {
            let mut bytes = clean.clone();
            let range = if next() % 2 == 0 {
                bytes.len().min(30_000)
            } else {
                bytes.len()
            };
            for _ in 0..1 + next() % 8 {
                let at = (next() % range as u64) as usize;
                bytes[at] = next() as u8;
            }
            bytes.truncate(bytes.len() - (next() % 2) as usize * (next() as usize % bytes.len()));
            let _ = read_float_grid(&bytes, "density", LIMIT);
        }
    }
}

// ---- Small hand-built, uncompressed files for what the smoke bakes do not contain: internal
// and root tiles, active-mask compression with stored inactive values, other maps. ----

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend((s.len() as u32).to_le_bytes());
    out.extend(s.as_bytes());
}

fn mask(bits: usize, on: &[usize]) -> Vec<u8> {
    let mut m = vec![0u8; bits / 8];
    for &n in on {
        m[n / 8] |= 1 << (n % 8);
    }
    m
}

fn floats(out: &mut Vec<u8>, values: impl IntoIterator<Item = f32>) {
    for v in values {
        out.extend(v.to_le_bytes());
    }
}

/// One float grid 'density': a root child at the origin holding one node4, which holds a
/// leaf at its entry 0 (voxel (1,2,3) active = 2.0, the rest inactive = 0.25) and an active
/// tile 0.5 at entry 256 (x 8..15, y 0..7, z 0..7); plus the given root tiles.
fn build(map: (&str, &[f64]), masked: bool, root_tiles: &[([i32; 3], f32, bool)]) -> Vec<u8> {
    let mut grid = Vec::new();
    grid.extend(if masked { 2u32 } else { 0 }.to_le_bytes());
    grid.extend(0u32.to_le_bytes()); // no grid metadata
    string(&mut grid, map.0);
    for v in map.1 {
        grid.extend(v.to_le_bytes());
    }
    grid.extend(1i32.to_le_bytes());
    floats(&mut grid, [0.0]); // background
    grid.extend((root_tiles.len() as u32).to_le_bytes());
    grid.extend(1u32.to_le_bytes());
    for (origin, value, active) in root_tiles {
        origin.iter().for_each(|c| grid.extend(c.to_le_bytes()));
        floats(&mut grid, [*value]);
        grid.push(*active as u8);
    }
    grid.extend([0u8; 12]); // root child origin
    grid.extend(mask(32768, &[0]));
    grid.extend(mask(32768, &[]));
    grid.push(6);
    floats(&mut grid, vec![0.0; 32768]);
    grid.extend(mask(4096, &[0]));
    grid.extend(mask(4096, &[256]));
    grid.push(6);
    floats(
        &mut grid,
        (0..4096).map(|n| if n == 256 { 0.5 } else { 0.0 }),
    );
    let voxel = (1 << 6) | (2 << 3) | 3;
    grid.extend(mask(512, &[voxel]));
    let block = grid.len();
    grid.extend(mask(512, &[voxel]));
    if masked {
        grid.push(2);
        floats(&mut grid, [0.25, 2.0]);
    } else {
        grid.push(6);
        floats(
            &mut grid,
            (0..512).map(|n| if n == voxel { 2.0 } else { 0.25 }),
        );
    }

    let mut head = vec![0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0];
    head.extend(224u32.to_le_bytes());
    head.extend([12, 0, 0, 0, 0, 0, 0, 0, 1]);
    head.extend([b'0'; 36]);
    head.extend(0u32.to_le_bytes());
    head.extend(1i32.to_le_bytes());
    string(&mut head, "density");
    string(&mut head, "Tree_float_5_4_3");
    string(&mut head, "");
    let start = (head.len() + 24) as i64;
    for pos in [start, start + block as i64, start + grid.len() as i64] {
        head.extend(pos.to_le_bytes());
    }
    head.extend(grid);
    head
}

const SCALE_TRANSLATE: [f64; 18] = [
    1.0, 2.0, 3.0, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 2.0, 2.0, 2.0, 4.0, 4.0, 4.0, 1.0, 1.0, 1.0,
];

#[test]
fn tiles_leaves_and_inactive_values_fill_the_box() {
    for masked in [false, true] {
        let far_tile = ([4096, 0, 0], 9.0, false);
        let file = build(("ScaleTranslateMap", &SCALE_TRANSLATE), masked, &[far_tile]);
        let g = read_float_grid(&file, "density", 1 << 20).unwrap();
        assert_eq!((g.index_min, g.resolution), ([1, 0, 0], [15, 8, 8]));
        let at = |x: usize, y: usize, z: usize| g.values[(x - 1) + 15 * (y + 8 * z)];
        assert_eq!(at(1, 2, 3), 2.0);
        assert_eq!(at(2, 2, 3), 0.25, "inactive leaf voxels keep their value");
        assert_eq!(
            (at(8, 0, 0), at(15, 7, 7)),
            (0.5, 0.5),
            "the active tile fills 8^3"
        );
        let sum: f32 = g.values.iter().sum();
        assert_eq!(sum, 2.0 + 0.25 * (7.0 * 8.0 * 8.0 - 1.0) + 0.5 * 512.0);
        assert_eq!(
            g.index_to_world,
            [
                [0.5, 0.0, 0.0, 1.0],
                [0.0, 0.5, 0.0, 2.0],
                [0.0, 0.0, 0.5, 3.0]
            ]
        );
    }
}

#[test]
fn an_active_root_tile_hits_the_voxel_limit() {
    let file = build(
        ("ScaleMap", &[1.0; 15]),
        false,
        &[([-4096, 0, 0], 1.0, true)],
    );
    let err = read_float_grid(&file, "density", 1 << 24)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("4112 x 4096 x 4096 voxels, more than the limit of 16777216"),
        "{err}"
    );
    let misaligned = build(("ScaleMap", &[1.0; 15]), false, &[([5, 0, 0], 1.0, true)]);
    let err = read_float_grid(&misaligned, "density", 1 << 24)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("root entry origin 5 is not a multiple of 4096"),
        "{err}"
    );
    // The root is a map: an origin given twice would refill the box once per copy (a small
    // file asking for unbounded work).
    let twice = build(
        ("ScaleMap", &[1.0; 15]),
        false,
        &[([4096, 0, 0], 1.0, false), ([4096, 0, 0], 2.0, false)],
    );
    let err = read_float_grid(&twice, "density", 1 << 24)
        .unwrap_err()
        .to_string();
    assert!(err.contains("[4096, 0, 0] appears twice"), "{err}");
}

#[test]
fn affine_translation_and_unknown_maps() {
    // Row-vector matrix: world = (i, j, k, 1) * M, so M's rows are the images of the axes.
    let m = [
        0.0, 2.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0, 5.0, 6.0, 7.0, 1.0,
    ];
    let g = read_float_grid(&build(("AffineMap", &m), false, &[]), "density", 1 << 20).unwrap();
    assert_eq!(
        g.index_to_world,
        [
            [0.0, -1.0, 0.0, 5.0],
            [2.0, 0.0, 0.0, 6.0],
            [0.0, 0.0, 3.0, 7.0]
        ]
    );
    let t = read_float_grid(
        &build(("TranslationMap", &[1.0, 2.0, 3.0]), false, &[]),
        "density",
        1 << 20,
    );
    assert_eq!(t.unwrap().index_to_world[2], [0.0, 0.0, 1.0, 3.0]);
    let err = read_float_grid(
        &build(("NonlinearFrustumMap", &[]), false, &[]),
        "density",
        1 << 20,
    );
    let err = err.unwrap_err().to_string();
    assert!(
        err.contains("unsupported transform map 'NonlinearFrustumMap'"),
        "{err}"
    );
}
