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

/// Where `line` names a variant of the enum `kind` (`Material::Mirror`, `Light::Area`): the
/// enum's name as a whole word followed by `::` and a capital.
fn names_a_kind(line: &str, kind: &str) -> bool {
    let pattern = format!("{kind}::");
    line.match_indices(&pattern).any(|(at, _)| {
        let whole_word = !line[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_');
        whole_word && line[at + pattern.len()..].starts_with(|c: char| c.is_ascii_uppercase())
    })
}

/// The rule ARCHITECTURE.md states for materials and lights: integrators (and the photon and
/// progressive modules) decide by lobes and parts and call the BSDF, and ask a light for its
/// samples and densities; they never name a material or light kind, so a new material or
/// light renders everywhere once it is in `material/` or `light/`.
#[test]
fn light_transport_never_matches_on_a_material_or_light_kind() {
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
            if names_a_kind(line, "Material") || names_a_kind(line, "Light") {
                found.push(format!("{}:{}: {}", f.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "light transport names material or light kinds (decide by `lobes()`/`has(Part)`, \
         ask the light for `sample_li`/`pdf_li`):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_kind_check_sees_a_named_kind() {
    assert!(names_a_kind(
        "Light::Area(l) => l.pdf_li(p, q, n),",
        "Light"
    ));
    assert!(names_a_kind("if let Material::Mirror(_) = m {", "Material"));
    assert!(!names_a_kind("LightSample::new()", "Light"));
    assert!(!names_a_kind("EnvironmentLight::pdf", "Light"));
    assert!(!names_a_kind("Light::is_delta(l)", "Light"));
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

/// The layers of ARCHITECTURE.md's diagram, bottom first: each line's module names (the
/// first column), skipping the binary and continuation lines.
fn layers(map: &str) -> Vec<Vec<String>> {
    let block = map
        .split("## Layers")
        .nth(1)
        .and_then(|s| s.split("```").nth(1))
        .expect("a diagram under ## Layers");
    let mut layers: Vec<Vec<String>> = block
        .lines()
        .filter(|l| l.starts_with(' ') && !l.starts_with("  "))
        .map(|l| {
            let names = l.trim().split("  ").next().unwrap_or("");
            names.split_whitespace().map(str::to_owned).collect()
        })
        .filter(|names: &Vec<String>| names.first().is_some_and(|n| n != "main.rs"))
        .collect();
    layers.reverse();
    layers
}

/// The code of a Rust file without its comments (a path in a doc comment is not a use).
fn code_of(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The names after each `prefix` in `code`: `crate::scene::X` gives `scene`.
fn paths_after<'a>(code: &'a str, prefix: &str) -> Vec<&'a str> {
    code.match_indices(prefix)
        .filter(|(at, _)| {
            // A whole path segment: not `my_crate::`.
            !code[..*at]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
        .map(|(at, _)| {
            let rest = &code[at + prefix.len()..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            &rest[..end]
        })
        .filter(|name| !name.is_empty())
        .collect()
}

/// Every use of a module by a library file, against the layer order ARCHITECTURE.md draws.
fn layer_violations(root: &Path) -> Vec<String> {
    let map = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let layers = layers(&map);
    let level = |module: &str| layers.iter().position(|l| l.iter().any(|m| m == module));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let mut violations = Vec::new();
    for f in files {
        let rel = f.strip_prefix(root.join("src")).expect("under src");
        let first = rel.iter().next().expect("a name").to_string_lossy();
        if first == "main.rs" || first == "lib.rs" || first == "cli" {
            continue;
        }
        let module = first.trim_end_matches(".rs").to_string();
        let Some(own) = level(&module) else {
            violations.push(format!(
                "{}: module '{module}' is not in the diagram",
                rel.display()
            ));
            continue;
        };
        let code = code_of(&std::fs::read_to_string(&f).expect("read"));
        for used in paths_after(&code, "crate::") {
            if used == module {
                continue;
            }
            match level(used) {
                Some(l) if l < own => {}
                Some(_) => violations.push(format!(
                    "{}: '{module}' uses '{used}', which is not below it",
                    rel.display()
                )),
                None => violations.push(format!(
                    "{}: uses 'crate::{used}', which is not in the diagram",
                    rel.display()
                )),
            }
        }
        if module == "description" {
            violations.extend(description_violations(rel, &code));
        }
    }
    violations
}

/// Inside `description`: `builtin` > `build` > `gltf` > `mesh`, `toml_read`, `toml_write` >
/// `source` (all may use the root's types).
fn description_violations(rel: &Path, code: &str) -> Vec<String> {
    let order = |m: &str| match m {
        "source" => Some(0),
        "mesh" | "toml_read" | "toml_write" => Some(1),
        "gltf" => Some(2),
        "build" => Some(3),
        "builtin" => Some(4),
        _ => None,
    };
    let parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_owned())
        .collect();
    // description/X.rs or description/X/…: X; description/mod.rs is the facade.
    let Some(own) = parts.get(1).filter(|p| *p != "mod") else {
        return Vec::new();
    };
    let own_level = order(own).expect("a known part of description");
    // `super::` names a sibling from description/X.rs and description/X/mod.rs.
    let sibling_super = parts.len() == 2 || parts.get(2).is_some_and(|p| p == "mod");
    let mut used = paths_after(code, "crate::description::");
    if sibling_super {
        used.extend(paths_after(code, "super::"));
    }
    used.into_iter()
        .filter(|u| u != own)
        .filter_map(|u| {
            let l = order(u)?;
            (l >= own_level).then(|| {
                format!(
                    "{}: description/{own} uses description/{u}, which is not below it",
                    rel.display()
                )
            })
        })
        .collect()
}

#[test]
fn modules_use_only_the_layers_below_them() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let violations = layer_violations(root);
    assert!(
        violations.is_empty(),
        "imports against ARCHITECTURE.md's layers:\n{}",
        violations.join("\n")
    );
}

#[test]
fn the_layer_check_sees_a_wrong_import() {
    // The diagram is read as drawn: the binary and continuation lines are not layers.
    let map =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md"))
            .expect("ARCHITECTURE.md");
    let layers = layers(&map);
    assert_eq!(layers[0], ["math", "error", "hash"]);
    assert!(
        layers
            .iter()
            .all(|l| l.iter().all(|m| !m.contains('.') && !m.contains(',')))
    );
    let code = code_of(
        "use crate::scene::Scene; // crate::render is only mentioned\nfn f() { my_crate::x(); crate::io::input::read_file(p); }",
    );
    assert_eq!(paths_after(&code, "crate::"), ["scene", "io"]);
    assert_eq!(
        description_violations(
            Path::new("description/mesh/mod.rs"),
            "use super::gltf::read_meshes;"
        )
        .len(),
        1
    );
}
