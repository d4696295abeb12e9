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

/// A use tree parsed from `code` at `at`: the paths it names, each as its segments.
/// `a::{b, c::{d, e as f}, *}` gives `a::b`, `a::c::d`, `a::c::e`, `a::*`.
fn use_tree(code: &str, mut at: usize) -> (Vec<Vec<String>>, usize) {
    let bytes = code.as_bytes();
    let skip_space = |mut at: usize| {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        at
    };
    let is_ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    at = skip_space(at);
    if bytes.get(at) == Some(&b'{') {
        // A group: trees separated by commas, up to the matching brace.
        let mut paths = Vec::new();
        at += 1;
        loop {
            at = skip_space(at);
            match bytes.get(at) {
                None => return (paths, at),
                Some(b'}') => return (paths, at + 1),
                Some(b',') => at += 1,
                Some(_) => {
                    let (inner, next) = use_tree(code, at);
                    paths.extend(inner);
                    // Past what the tree leaves (`as name`), to the next item or the end.
                    at = next;
                    while at < bytes.len() && !matches!(bytes[at], b',' | b'}' | b'{' | b';') {
                        at += 1;
                    }
                    if matches!(bytes.get(at), Some(b'{' | b';')) {
                        return (paths, at);
                    }
                }
            }
        }
    }
    let start = at;
    if bytes.get(at) == Some(&b'*') {
        at += 1;
    } else {
        while at < bytes.len() && is_ident(bytes[at]) {
            at += 1;
        }
    }
    if at == start {
        return (vec![Vec::new()], at);
    }
    let segment = code[start..at].to_owned();
    let after = skip_space(at);
    if code[after..].starts_with("::") {
        let (rest, end) = use_tree(code, after + 2);
        let paths = rest
            .into_iter()
            .map(|mut p| {
                p.insert(0, segment.clone());
                p
            })
            .collect();
        return (paths, end);
    }
    (vec![vec![segment]], at)
}

/// Every path in `code` that starts at the segment `root` (`crate`, `super`), grouped imports
/// expanded: `use crate::{scene::Scene, io::{image, phm}}` gives `scene::Scene`,
/// `io::image` and `io::phm`, each as its segments after `root`.
fn paths_from(code: &str, root: &str) -> Vec<Vec<String>> {
    let head = format!("{root}::");
    code.match_indices(&head)
        .filter(|(at, _)| {
            // A path's first segment: not `my_crate::` nor the `super` of `super::super::`.
            !code[..*at]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':')
        })
        .flat_map(|(at, _)| use_tree(code, at + head.len()).0)
        .collect()
}

/// The names after each `prefix` in `code`, grouped imports included: `crate::scene::X` and
/// `crate::{scene::X, io}` give `scene` (and `io`); `crate::description::` gives the part of
/// `description` a path names.
fn paths_after(code: &str, prefix: &str) -> Vec<String> {
    let mut segments = prefix.trim_end_matches("::").split("::");
    let root = segments.next().expect("a root");
    let within: Vec<&str> = segments.collect();
    paths_from(code, root)
        .into_iter()
        .filter(|p| p.len() > within.len() && p.iter().zip(&within).all(|(a, b)| a == b))
        .map(|p| p[within.len()].clone())
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
            match level(&used) {
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

/// Inside `description`: `builtin` > `build` > `gltf` > `mesh`, `toml_read`, `toml_write`,
/// `environment` > `source` (all may use the root's types).
fn description_violations(rel: &Path, code: &str) -> Vec<String> {
    let order = |m: &str| match m {
        "source" => Some(0),
        "mesh" | "toml_read" | "toml_write" | "environment" => Some(1),
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
            let l = order(&u)?;
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
    // Grouped imports, nested and renamed, count as their paths.
    let grouped = code_of(
        "use crate::{\n    math::{Rgb, Vec3},\n    render::{self, render as go}, // a note\n    error::Result,\n};\nuse crate::{film::*};",
    );
    assert_eq!(
        paths_after(&grouped, "crate::"),
        ["math", "math", "render", "render", "error", "film"]
    );
    assert_eq!(
        paths_after(
            "use crate::description::{source::Diagnostic, gltf::{self, x}};",
            "crate::description::"
        ),
        ["source", "gltf", "gltf"]
    );
    assert_eq!(
        description_violations(
            Path::new("description/source.rs"),
            "use super::{Diagnostic, toml_read::{read_str, values}};"
        )
        .len(),
        2
    );
    assert_eq!(
        paths_after("super::super::math::Vec3", "super::"),
        ["super"]
    );
    assert_eq!(
        description_violations(
            Path::new("description/mesh/mod.rs"),
            "use super::gltf::read_meshes;"
        )
        .len(),
        1
    );
}

/// The modules the binary declares (`mod cli;` in `src/main.rs`): the library is `src/`
/// without them and without `main.rs`.
fn binary_modules(root: &Path) -> Vec<String> {
    let main = std::fs::read_to_string(root.join("src/main.rs")).expect("src/main.rs");
    code_of(&main)
        .lines()
        .filter_map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub ").unwrap_or(l);
            l.strip_prefix("mod ")?.strip_suffix(';').map(str::to_owned)
        })
        .collect()
}

fn library_files(root: &Path) -> Vec<PathBuf> {
    let binary = binary_modules(root);
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    files.retain(|f| {
        let rel = f.strip_prefix(root.join("src")).expect("under src");
        let first = rel.iter().next().expect("a name").to_string_lossy();
        let module = first.trim_end_matches(".rs");
        first != "main.rs" && !binary.iter().any(|b| b == module)
    });
    files
}

/// Where `code` prints or ends the process: the macros that write to stdout or stderr, the
/// standard streams themselves, and `process::exit`/`abort`.
fn printing_or_exiting(code: &str) -> Vec<&'static str> {
    const MACROS: [&str; 5] = ["print!", "println!", "eprint!", "eprintln!", "dbg!"];
    const CALLS: [&str; 4] = [
        "process::exit",
        "process::abort",
        "io::stdout",
        "io::stderr",
    ];
    let whole = |pattern: &str| {
        code.match_indices(pattern).any(|(at, _)| {
            !code[..at]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
    };
    MACROS
        .into_iter()
        .chain(CALLS)
        .filter(|p| whole(p))
        .collect()
}

/// ARCHITECTURE.md: "The library never prints and never exits." Messages go up as values
/// (`Error`, `Diagnostic`, warnings) and progress as callbacks; the binary and the Python
/// module decide what a user sees.
#[test]
fn the_library_never_prints_or_exits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    assert_eq!(binary_modules(root), ["cli"]);
    let files = library_files(root);
    assert!(files.iter().any(|f| f.ends_with("src/lib.rs")));
    assert!(!files.iter().any(|f| f.ends_with("src/cli/mod.rs")));
    let mut found = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).expect("reads");
        for (i, line) in code_of(&text).lines().enumerate() {
            for what in printing_or_exiting(line) {
                found.push(format!(
                    "{}:{}: {what}: {}",
                    f.display(),
                    i + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(
        found.is_empty(),
        "the library prints or exits (return an Error or report through a callback):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_print_check_sees_a_print() {
    assert_eq!(printing_or_exiting("println!(\"{x}\");"), ["println!"]);
    assert_eq!(printing_or_exiting("eprintln!(\"{x}\");"), ["eprintln!"]);
    assert_eq!(printing_or_exiting("let y = dbg!(x);"), ["dbg!"]);
    assert_eq!(
        printing_or_exiting("std::process::exit(2)"),
        ["process::exit"]
    );
    assert_eq!(
        printing_or_exiting("let _ = writeln!(std::io::stderr(), \"x\");"),
        ["io::stderr"]
    );
    assert!(
        printing_or_exiting("writeln!(out, \"{x}\")?; let id = std::process::id();").is_empty()
    );
    assert!(printing_or_exiting(&code_of("/// println!(\"{x}\") in a doc comment")).is_empty());
}

/// ARCHITECTURE.md: no `unsafe` anywhere. Both crate roots forbid it, so the compiler refuses
/// an `unsafe` block (and an `#[allow(unsafe_code)]` cannot lift it).
#[test]
fn both_crate_roots_forbid_unsafe_code() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for file in ["src/lib.rs", "src/main.rs"] {
        let text = std::fs::read_to_string(root.join(file)).expect("reads");
        assert!(
            code_of(&text)
                .lines()
                .any(|l| l.trim() == "#![forbid(unsafe_code)]"),
            "{file} lacks #![forbid(unsafe_code)]"
        );
    }
}

/// Cargo builds only the test targets `Cargo.toml` names (`autotests = false`), so a test file
/// missing from `tests/main.rs` would never run.
#[test]
fn every_test_file_is_built() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let main = std::fs::read_to_string(root.join("tests/main.rs")).expect("tests/main.rs");
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("Cargo.toml");
    let mut unbuilt = Vec::new();
    for entry in std::fs::read_dir(root.join("tests")).expect("reads tests/") {
        let path = entry.expect("entry").path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_none_or(|e| e != "rs") || stem == "main" {
            continue;
        }
        let a_module = main.lines().any(|l| l.trim() == format!("mod {stem};"));
        let a_target = manifest.contains(&format!("path = \"tests/{stem}.rs\""));
        if !a_module && !a_target {
            unbuilt.push(format!("tests/{stem}.rs"));
        }
    }
    assert!(
        unbuilt.is_empty(),
        "add these to tests/main.rs as `mod NAME;`: {unbuilt:?}"
    );
}
