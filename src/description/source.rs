//! Where scene items were written ([`Origins`]), and typo suggestions ([`nearest`]). The
//! located message itself, [`Diagnostic`], lives in `error`, at the bottom of the layers.

use crate::error::Error;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use crate::error::Diagnostic;

/// Where the items of a scene description were written, so that problems only the scene build
/// can find (an emitter given by power that has no area, a sphere scaled unevenly, a coordinate
/// past the limit) are reported at the line that caused them.
///
/// Not part of what a scene is: descriptions that differ only in their origins are equal.
#[derive(Clone, Default)]
pub struct Origins {
    file: Option<Arc<SourceFile>>,
    camera: Option<Range<usize>>,
    shapes: Vec<Range<usize>>,
    lights: Vec<Range<usize>>,
}

struct SourceFile {
    path: PathBuf,
    /// The text that spans index, for text formats.
    text: Option<String>,
}

/// One item of a scene description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Item {
    Camera,
    /// 0-based index into `SceneDesc::shapes`.
    Shape(usize),
    /// 0-based index into `SceneDesc::lights`.
    Light(usize),
}

impl fmt::Display for Item {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Camera => write!(f, "[camera]"),
            Self::Shape(i) => write!(f, "shape {}", i + 1),
            Self::Light(i) => write!(f, "light {}", i + 1),
        }
    }
}

impl Origins {
    /// Origins in the text of file `path`; spans are added as the items are read.
    pub fn in_file(path: &Path, text: &str) -> Self {
        Self {
            file: Some(Arc::new(SourceFile {
                path: path.to_owned(),
                text: Some(text.to_owned()),
            })),
            ..Self::default()
        }
    }

    /// Origins in a binary file (glTF): messages name the file and the item, not a line.
    pub fn in_binary_file(path: &Path) -> Self {
        Self {
            file: Some(Arc::new(SourceFile {
                path: path.to_owned(),
                text: None,
            })),
            ..Self::default()
        }
    }

    pub fn set_camera(&mut self, span: Range<usize>) {
        self.camera = Some(span);
    }

    pub fn push_shape(&mut self, span: Range<usize>) {
        self.shapes.push(span);
    }

    pub fn push_light(&mut self, span: Range<usize>) {
        self.lights.push(span);
    }

    /// `error`, found while building `item`, named by that item and located at its span when
    /// the item was read from a file. Errors that carry their own location pass unchanged.
    pub fn locate(&self, item: Item, error: Error) -> Error {
        let (message, separator) = match error {
            Error::InvalidScene(m) => (m, ": "),
            Error::InvalidObject { message, .. } => (message, " "),
            other => return other,
        };
        let message = format!("{item}{separator}{message}");
        let span = match item {
            Item::Camera => self.camera.clone(),
            Item::Shape(i) => self.shapes.get(i).cloned(),
            Item::Light(i) => self.lights.get(i).cloned(),
        };
        let Some(file) = &self.file else {
            return Error::InvalidScene(message);
        };
        let diagnostic = match (&file.text, span) {
            (Some(text), Some(span)) => Diagnostic::at_span(&file.path, text, span, message),
            _ => Diagnostic::whole_file(&file.path, message),
        };
        Error::SceneFile(Box::new(diagnostic))
    }
}

impl PartialEq for Origins {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl fmt::Debug for Origins {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.file.as_ref().map(|s| s.path.display().to_string());
        f.debug_struct("Origins")
            .field("file", &path)
            .finish_non_exhaustive()
    }
}

/// The candidate nearest to `word` by edit distance, if it is close enough to be a likely typo.
pub fn nearest<'a>(word: &str, candidates: &[&'a str]) -> Option<&'a str> {
    candidates
        .iter()
        .map(|c| (edit_distance(word, c), *c))
        .filter(|&(d, c)| d <= (c.len().max(word.len()) / 3).max(1))
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

/// "; did you mean 'X'?" for the likely intended candidate, or nothing.
pub fn did_you_mean(word: &str, candidates: &[&str]) -> String {
    nearest(word, candidates).map_or_else(String::new, |n| format!("; did you mean '{n}'?"))
}

/// Levenshtein distance (insert, delete, substitute; case-insensitive).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.to_lowercase().chars().collect();
    let b: Vec<char> = b.to_lowercase().chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_become_lines_columns_and_carets() {
        let src = "a = 1\nradus = 2\n";
        let d = Diagnostic::at_span(Path::new("s.toml"), src, 6..11, "unknown key");
        assert_eq!((d.line, d.column), (Some(2), Some(1)));
        let text = d.to_string();
        assert!(text.starts_with("s.toml:2:1: unknown key"), "{text}");
        assert!(text.contains("2 | radus = 2\n  | ^^^^^"), "{text}");
    }

    #[test]
    fn nearest_finds_typos_only() {
        let keys = ["radius", "center", "material"];
        assert_eq!(nearest("radus", &keys), Some("radius"));
        assert_eq!(nearest("materail", &keys), Some("material"));
        assert_eq!(nearest("colour", &keys), None);
    }
}
