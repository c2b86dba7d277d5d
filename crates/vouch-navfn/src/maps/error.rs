//! Located errors of the map and suite readers.

use std::path::{Path, PathBuf};

use miette::{NamedSource, SourceSpan};

use crate::diag::{field_span, named_source};

/// A map, suite or parameter file that cannot be used. Text files are located by line and
/// field (rendered with the offending line); binary files (images, map bytes) by file.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum MapError {
    /// The file cannot be read.
    #[error("{}: cannot read: {source}", path.display())]
    #[diagnostic(code(navfn::E010))]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A line of a text file (map YAML, suite test file, `params.txt`) that is not valid.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Syntax(Box<SyntaxError>),
    /// A file whose content is not valid as a whole (image data, a missing key, a size).
    #[error("{}: {msg}", path.display())]
    #[diagnostic(code(navfn::E012))]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
}

/// A line of a text file that is not valid, with the file's text for the rendering.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("{msg}")]
#[diagnostic(code(navfn::E011))]
pub struct SyntaxError {
    /// The file.
    pub path: PathBuf,
    /// 1-based line.
    pub line: usize,
    /// What is wrong.
    pub msg: String,
    /// The file's text.
    #[source_code]
    pub src: NamedSource<String>,
    /// The offending field (or line).
    #[label("here")]
    pub span: SourceSpan,
}

impl MapError {
    /// An error on `line` of `text` (the content of `path`), pointing at `field` on that line
    /// (the whole line when `field` is empty).
    pub fn syntax(
        path: &Path,
        text: &str,
        line: usize,
        field: &str,
        msg: impl Into<String>,
    ) -> Self {
        let span = field_span(text, line, field);
        Self::spanned(path, text, line, (span.offset(), span.len()), msg)
    }

    /// An error at a byte range `(offset, len)` of `text` on 1-based `line`.
    pub fn spanned(
        path: &Path,
        text: &str,
        line: usize,
        (offset, len): (usize, usize),
        msg: impl Into<String>,
    ) -> Self {
        MapError::Syntax(Box::new(SyntaxError {
            path: path.to_path_buf(),
            line,
            msg: msg.into(),
            src: named_source(path, text),
            span: (offset.min(text.len()), len).into(),
        }))
    }

    /// An error about the file as a whole.
    pub fn file(path: &Path, msg: impl Into<String>) -> Self {
        MapError::Invalid { path: path.to_path_buf(), msg: msg.into() }
    }

    /// A read error.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        MapError::Io { path: path.to_path_buf(), source }
    }

    /// Bytes that should be a text file (map YAML, test file, `params.txt`) but are not UTF-8:
    /// rejected content (a binary file given by mistake or on purpose), not an I/O failure.
    pub fn not_text(path: &Path, e: &std::str::Utf8Error) -> Self {
        MapError::file(path, format!("not a text file (invalid UTF-8 at byte {})", e.valid_up_to()))
    }

    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            MapError::Io { path, .. } | MapError::Invalid { path, .. } => path,
            MapError::Syntax(e) => &e.path,
        }
    }

    /// The 1-based line, for errors located in a text file.
    pub fn line(&self) -> Option<usize> {
        match self {
            MapError::Syntax(e) => Some(e.line),
            _ => None,
        }
    }

    /// Whether the file could not be read at all (an I/O problem rather than bad content).
    pub fn is_io(&self) -> bool {
        matches!(self, MapError::Io { .. })
    }

    /// `file:line: message` (or `file: message`), for logs and tests without a renderer.
    pub fn located(&self) -> String {
        match self {
            MapError::Syntax(e) => format!("{}:{}: {}", e.path.display(), e.line, e.msg),
            other => other.to_string(),
        }
    }
}

/// Reads a text file: failing reads are I/O errors, bytes that are not UTF-8 rejected content.
pub fn read_text(path: &Path) -> Result<String, MapError> {
    let bytes = std::fs::read(path).map_err(|e| MapError::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| MapError::not_text(path, &e.utf8_error()))
}
