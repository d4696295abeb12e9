//! ARCHITECTURE.md is the map: every source file of the library is named in its module table,
//! so a new file cannot land without its place on the map.

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("reads src/") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn every_library_file_is_on_the_architecture_map() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let map = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let table: Vec<&str> = map.lines().filter(|l| l.starts_with("| `")).collect();
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let mut missing = Vec::new();
    for f in files {
        let rel = f.strip_prefix(root.join("src")).expect("under src");
        let mut parts = rel.iter().map(|p| p.to_string_lossy().into_owned());
        let first = parts.next().expect("a name");
        // The binary's files (main.rs, cli/) are described in prose; lib.rs is the root.
        if first == "main.rs" || first == "lib.rs" || first == "cli" {
            continue;
        }
        let module = first.trim_end_matches(".rs").to_string();
        let name = rel
            .file_name()
            .expect("file")
            .to_string_lossy()
            .into_owned();
        // The module's row: its name, then the files it holds.
        let row = table
            .iter()
            .find(|l| l.starts_with(&format!("| `{module}` |")));
        // The file's own name, or its path from the module's folder (`toml_read/scene.rs`).
        let nested = rel
            .parent()
            .and_then(|p| p.file_name())
            .map(|p| format!("{}/{name}", p.to_string_lossy()));
        let named = row.is_some_and(|r| {
            r.contains(&format!("`{name}`"))
                || nested.as_ref().is_some_and(|d| r.contains(d.as_str()))
                || r.contains(&format!("`{}`", rel.to_string_lossy()))
        });
        if !named {
            missing.push(rel.display().to_string());
        }
    }
    assert!(
        missing.is_empty(),
        "files not named in ARCHITECTURE.md's module table: {missing:?}"
    );
}

/// The rule ARCHITECTURE.md states for materials: integrators (and the photon and progressive
/// modules) decide by lobes and parts and call the BSDF; they never name a material kind, so a
/// new material renders everywhere once it is in `material/`.
#[test]
fn light_transport_never_matches_on_a_material_kind() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for dir in ["integrator", "photon", "progressive"] {
        rust_files(&root.join(dir), &mut files);
    }
    files.push(root.join("render.rs"));
    let mut found = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).expect("reads");
        for (i, line) in text.lines().enumerate() {
            if let Some(at) = line.find("Material::")
                && line[at + "Material::".len()..].starts_with(|c: char| c.is_ascii_uppercase())
            {
                found.push(format!("{}:{}: {}", f.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "light transport names material kinds (decide by `lobes()`/`has(Part)` instead):\n{}",
        found.join("\n")
    );
}

/// The input policy ARCHITECTURE.md states: files the user names are read only through
/// `io::input` (a regular file, within a size limit), so no format or flag can make Photon
/// read a FIFO forever or `/dev/zero` until memory runs out.
#[test]
fn files_are_opened_only_through_the_input_policy() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let forbidden = [
        "File::open(",
        "fs::read(",
        "fs::read_to_string(",
        "read_first_rgba_layer_from_file",
        "Gltf::open(",
        "load_mtl(",
    ];
    let mut found = Vec::new();
    for f in files {
        if f.ends_with("io/input.rs") {
            continue;
        }
        let text = std::fs::read_to_string(&f).expect("reads");
        for (i, line) in text.lines().enumerate() {
            if forbidden.iter().any(|p| line.contains(p)) {
                found.push(format!("{}:{}: {}", f.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "files opened outside io::input (use io::input::read_file):\n{}",
        found.join("\n")
    );
}
