//! Typed errors of the library. The binary turns them into messages and exit code 2.

use std::fmt;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(
        "unknown scene '{name}': it is neither a built-in scene ({available}) nor a .toml, .gltf or .glb file"
    )]
    UnknownScene { name: String, available: String },

    /// A problem in a scene, mesh or texture file, located where the format allows.
    #[error("{0}")]
    SceneFile(Box<Diagnostic>),

    #[error("invalid scene: {0}")]
    InvalidScene(String),

    /// A problem with object `index` of a scene builder (in the order objects were added),
    /// which the scene description maps back to the shape or light that made it.
    #[error("invalid scene: object {index} {message}")]
    InvalidObject { index: usize, message: String },

    /// The caller's cancel flag stopped a render.
    #[error("the render was cancelled")]
    Cancelled,

    #[error("invalid setting: {0}")]
    InvalidSetting(String),

    /// A problem with one render setting's value (see `settings`).
    #[error("invalid setting {0}")]
    Setting(SettingError),

    #[error("cannot write '{path}': {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },

    #[error("cannot read '{path}': {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },

    #[error("'{path}': unsupported image format '{extension}' (expected one of: {expected})")]
    UnsupportedImageFormat {
        path: PathBuf,
        extension: String,
        expected: &'static str,
    },

    #[error("'{path}': {message}")]
    BadImage { path: PathBuf, message: String },

    #[error("'{path}': {message}")]
    BadPhotonMap { path: PathBuf, message: String },

    #[error("'{path}': {message}")]
    BadCheckpoint { path: PathBuf, message: String },

    #[error(
        "'{path}' was traced for scene '{traced_for}', which differs from '{scene}' (it can be forced)"
    )]
    PhotonMapSceneMismatch {
        path: PathBuf,
        traced_for: String,
        scene: String,
    },
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// A problem with one render setting's value, which each front end names its own way (the
/// command line `--radius 0`, Python `radius=0`, a scene file the `[render]` key's line).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SettingError {
    /// The setting's name (`snake_case`).
    pub name: &'static str,
    /// The value as the user wrote it, when there is one.
    pub value: Option<String>,
    pub problem: String,
}

impl fmt::Display for SettingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.value {
            Some(v) => write!(f, "{} = {v}: {}", self.name, self.problem),
            None => write!(f, "{}: {}", self.name, self.problem),
        }
    }
}

/// A problem in a file, with its location when the format has lines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    pub path: PathBuf,
    /// 1-based line and column (in characters), when known.
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub message: String,
    /// The source line and a caret line under the span, ready to print.
    pub excerpt: Option<String>,
}

impl Diagnostic {
    /// A problem with the file as a whole (missing, unreadable, wrong kind, binary data).
    pub fn whole_file(path: &Path, message: impl Into<String>) -> Self {
        Self {
            path: path.to_owned(),
            line: None,
            column: None,
            message: message.into(),
            excerpt: None,
        }
    }

    /// A problem at byte range `span` of the text `source` of file `path`.
    pub fn at_span(
        path: &Path,
        source: &str,
        span: std::ops::Range<usize>,
        message: impl Into<String>,
    ) -> Self {
        let start = span.start.min(source.len());
        let line_start = source[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = source[start..]
            .find('\n')
            .map_or(source.len(), |i| start + i);
        let line_text = source[line_start..line_end].trim_end_matches('\r');
        let line = source[..start].matches('\n').count() + 1;
        let column = source[line_start..start].chars().count() + 1;
        let end = span.end.clamp(start, line_end.max(start));
        let width = source[start..end].chars().count().max(1);
        let number = line.to_string();
        let pad = " ".repeat(number.len());
        let excerpt = format!(
            "{pad} |\n{number} | {line_text}\n{pad} | {}{}",
            " ".repeat(column - 1),
            "^".repeat(width)
        );
        Self {
            path: path.to_owned(),
            line: Some(line),
            column: Some(column),
            message: message.into(),
            excerpt: Some(excerpt),
        }
    }

    /// A problem at 1-based `line` and `column` (in characters) of `source`.
    pub fn at_line_column(
        path: &Path,
        source: &str,
        line: usize,
        column: usize,
        message: impl Into<String>,
    ) -> Self {
        let start: usize = source
            .split_inclusive('\n')
            .take(line.saturating_sub(1))
            .map(str::len)
            .sum();
        let start = start.min(source.len());
        let offset: usize = source[start..]
            .chars()
            .take(column.saturating_sub(1))
            .map(char::len_utf8)
            .sum();
        let at = start + offset;
        let end = source[at..]
            .chars()
            .next()
            .map_or(at, |c| at + c.len_utf8());
        Self::at_span(path, source, at..end, message)
    }

    /// A problem on 1-based line `line` of `source` (column 1, the whole line underlined).
    pub fn at_line(path: &Path, source: &str, line: usize, message: impl Into<String>) -> Self {
        let start: usize = source
            .split_inclusive('\n')
            .take(line.saturating_sub(1))
            .map(str::len)
            .sum();
        let end = source[start.min(source.len())..]
            .find('\n')
            .map_or(source.len(), |i| start + i);
        Self::at_span(path, source, start..end, message)
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(col) = self.column {
                write!(f, ":{col}")?;
            }
        }
        write!(f, ": {}", self.message)?;
        if let Some(e) = &self.excerpt {
            write!(f, "\n{e}")?;
        }
        Ok(())
    }
}
