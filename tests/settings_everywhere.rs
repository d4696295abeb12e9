//! Every render setting is defined once, in `photon::settings::SETTINGS`. The command line's
//! flags, a scene's `[render]` table, Python's keyword arguments and job manifests are made
//! from it; what is written by hand elsewhere is checked against it here: the README's
//! settings tables, the Python stubs and the Blender panel.
//!
//! `UPDATE_SNAPSHOTS=1 cargo test --test integration settings_everywhere::` rewrites the README's tables.

use photon::settings::{DefaultValue, SETTINGS, Setting, Takes};
use std::path::Path;

const BEGIN: &str =
    "<!-- render settings: made from src/settings by tests/settings_everywhere.rs -->";
const END: &str = "<!-- end of render settings -->";

fn repository_file(path: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A table cell's text: `|` escaped, backticks kept.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// The README's tables of render settings, a table per group, as SETTINGS defines them.
fn settings_tables() -> String {
    let mut out = String::new();
    let mut groups = Vec::new();
    for s in SETTINGS {
        if !groups.contains(&s.group) {
            groups.push(s.group);
        }
    }
    for group in groups {
        out += &format!(
            "\n**{}**\n\n| setting | meaning | integrators | default |\n|---|---|---|---|\n",
            group.heading()
        );
        for s in SETTINGS.iter().filter(|s| s.group == group) {
            let value = if s.is_switch {
                String::new()
            } else if s.choices.is_empty() {
                format!(" {}", s.metavar)
            } else {
                format!(" {}", s.choices.join("|"))
            };
            let takes = if s.takes == Takes::ALL {
                "all".to_owned()
            } else {
                s.takes.names()
            };
            out += &format!(
                "| `{}{}` | {} | {} | {} |\n",
                s.flag(),
                cell(&value),
                cell(s.help.trim()),
                takes,
                cell(&s.default_text())
            );
        }
    }
    out
}

#[test]
fn the_readme_lists_every_setting_as_settings_define_it() {
    let readme = repository_file("README.md");
    let (Some(begin), Some(end)) = (readme.find(BEGIN), readme.find(END)) else {
        panic!("README.md has no block between '{BEGIN}' and '{END}'");
    };
    let written = &readme[begin + BEGIN.len()..end];
    let made = format!("{}\n", settings_tables());
    if written != made {
        if std::env::var_os("UPDATE_SNAPSHOTS").is_some() {
            let updated = format!("{}{made}{}", &readme[..begin + BEGIN.len()], &readme[end..]);
            std::fs::write(
                Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md"),
                updated,
            )
            .expect("writes README.md");
        } else {
            panic!(
                "README.md's settings tables differ from src/settings (UPDATE_SNAPSHOTS=1 rewrites them):\n{made}"
            );
        }
    }
}

/// The keyword arguments of `def NAME(` in the stubs, with their annotations.
fn stub_keywords(stubs: &str, name: &str) -> Vec<(String, String)> {
    let start = stubs
        .find(&format!("def {name}("))
        .unwrap_or_else(|| panic!("the stubs have no {name}"));
    let signature = &stubs[start..start + stubs[start..].find(") ->").expect("a signature")];
    signature
        .lines()
        .skip(1)
        .filter_map(|l| l.trim().trim_end_matches(',').split_once(": "))
        .map(|(k, t)| (k.to_owned(), t.to_owned()))
        .collect()
}

#[test]
fn the_python_stubs_take_every_setting_with_its_choices() {
    let stubs = repository_file("python/photon_render/_photon.pyi");
    let keywords = stub_keywords(&stubs, "render");
    let names: Vec<&str> = keywords
        .iter()
        .map(|(k, _)| k.as_str())
        .filter(|k| !["scene", "threads"].contains(k))
        .collect();
    let settings: Vec<&str> = SETTINGS.iter().map(|s| s.name).collect();
    assert_eq!(names, settings, "render()'s keywords in _photon.pyi");
    for (name, annotation) in &keywords {
        let Some(s) = SETTINGS.iter().find(|s| s.name == name) else {
            continue;
        };
        if !s.choices.is_empty() && s.choices.iter().all(|c| !c.contains(':')) {
            let literal = format!(
                "Literal[{}]",
                s.choices
                    .iter()
                    .map(|c| format!("\"{c}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            assert!(
                annotation.starts_with(&literal),
                "{name}: {annotation} is not {literal}"
            );
        }
        assert!(
            annotation.ends_with("| None = None"),
            "{name}: unset by default, so the scene's or the default applies ({annotation})"
        );
    }
}

/// `(name, kind, default, the rest of the property's text)` of each property of the Blender
/// add-on's settings group.
fn blender_properties(addon: &str) -> Vec<(String, String, String, String)> {
    let class = addon
        .find("class PhotonRenderSettings")
        .expect("the settings group");
    let body = &addon[class..];
    let body = &body[..body[1..].find("\nclass ").map_or(body.len(), |e| e + 1)];
    let mut found = Vec::new();
    let starts: Vec<usize> = body.match_indices(": bpy.props.").map(|(i, _)| i).collect();
    for (n, &at) in starts.iter().enumerate() {
        let name = body[..at]
            .rsplit(char::is_whitespace)
            .next()
            .expect("a name");
        let end = starts.get(n + 1).copied().unwrap_or(body.len());
        let text = &body[at + ": bpy.props.".len()..end];
        let kind = text[..text.find('(').expect("a call")].to_owned();
        let default = text
            .split("default=")
            .nth(1)
            .map(|d| {
                d.split([',', ')'])
                    .next()
                    .expect("a value")
                    .trim()
                    .trim_matches('"')
                    .replace('_', "")
            })
            // Python's booleans, as the renderer writes them.
            .map(|d| match d.as_str() {
                "True" | "False" => d.to_lowercase(),
                _ => d,
            })
            .unwrap_or_default();
        found.push((name.to_owned(), kind, default, text.to_owned()));
    }
    found
}

#[test]
fn the_blender_panel_sets_settings_with_their_choices_and_defaults() {
    let addon = repository_file("python/blender/photon_blender/__init__.py");
    let properties = blender_properties(&addon);
    assert!(properties.len() >= 5, "{properties:?}");
    for (name, kind, default, text) in properties {
        if name == "threads" {
            continue;
        }
        let s: &Setting = SETTINGS
            .iter()
            .find(|s| s.name == name)
            .unwrap_or_else(|| panic!("the Blender panel's '{name}' is not a render setting"));
        if kind == "EnumProperty" {
            for choice in text
                .match_indices("(\"")
                .map(|(i, _)| text[i + 2..].split('"').next().expect("an item").to_owned())
            {
                assert!(
                    s.choices.contains(&choice.as_str()),
                    "{name}: '{choice}' is not one of {:?}",
                    s.choices
                );
            }
            continue;
        }
        let DefaultValue::Value(of) = s.default else {
            continue;
        };
        let values: Vec<String> = s.takes.kinds().map(of).collect();
        let one_value = values.iter().all(|v| *v == values[0]);
        if one_value {
            assert_eq!(
                default, values[0],
                "the Blender panel's {name} default is not the renderer's"
            );
        } else {
            // A default that differs by integrator: 0 in the panel leaves it to the renderer.
            assert!(
                default == "0" && text.contains("0: the integrator's default"),
                "{name} defaults to {} by integrator; the panel's {default} must be 0, \
                 described as \"0: the integrator's default\"",
                s.default_text()
            );
        }
    }
}
