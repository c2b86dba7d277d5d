//! Located errors and warnings of configuration files (`file:line:col`, rendered by miette with
//! the offending line). A diagnostic shares its file's text with the others of the same file
//! (`Arc`), which keeps it small enough to return by value.

use std::fmt;
use std::sync::Arc;

use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode};

/// What kind of problem a configuration diagnostic reports; each kind has its own code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ConfErrorKind {
    /// A line the INI syntax does not allow (`mav::G001`).
    Syntax,
    /// A section type that neither mavlink-router nor vouch has (`mav::G002`).
    UnknownSection,
    /// A key the section does not have (`mav::G003`).
    UnknownKey,
    /// A value of the wrong form (`mav::G004`).
    BadValue,
    /// A required key that is missing (`mav::G005`).
    MissingKey,
    /// Keys or sections that do not go together, e.g. two endpoints of one name (`mav::G006`).
    Conflict,
    /// A key vouch accepts but does not act on as mavlink-router does (`mav::G007`, a warning).
    NotImplemented,
    /// A file or directory that cannot be read (`mav::G008`).
    Io,
}

impl ConfErrorKind {
    /// The diagnostic code.
    pub fn code(self) -> &'static str {
        match self {
            ConfErrorKind::Syntax => "mav::G001",
            ConfErrorKind::UnknownSection => "mav::G002",
            ConfErrorKind::UnknownKey => "mav::G003",
            ConfErrorKind::BadValue => "mav::G004",
            ConfErrorKind::MissingKey => "mav::G005",
            ConfErrorKind::Conflict => "mav::G006",
            ConfErrorKind::NotImplemented => "mav::G007",
            ConfErrorKind::Io => "mav::G008",
        }
    }
}

/// A problem in a configuration file, with its kind and location.
#[derive(Debug)]
pub struct ConfError {
    /// What kind of problem.
    pub kind: ConfErrorKind,
    /// One sentence saying what is wrong.
    pub message: String,
    /// The file's text, named after its path (shared by every diagnostic of the file).
    pub src: Arc<NamedSource<String>>,
    /// Byte offset and length in the text.
    pub span: (usize, usize),
    /// How to fix it, when there is something to say.
    pub help: Option<String>,
}

impl ConfError {
    /// A diagnostic at `offset..offset + len` of file `name` with contents `text`.
    pub fn new(
        kind: ConfErrorKind,
        message: String,
        name: &str,
        text: &str,
        offset: usize,
        len: usize,
    ) -> ConfError {
        ConfError::in_file(kind, message, named(name, text), offset, len)
    }

    /// A diagnostic at `offset..offset + len` of a file already shared by other diagnostics.
    pub fn in_file(
        kind: ConfErrorKind,
        message: String,
        src: Arc<NamedSource<String>>,
        offset: usize,
        len: usize,
    ) -> ConfError {
        ConfError { kind, message, src, span: (offset, len), help: None }
    }

    /// A diagnostic about a whole file or directory (no position in it).
    pub fn io(name: &str, message: String) -> ConfError {
        ConfError::new(ConfErrorKind::Io, message, name, "", 0, 0)
    }

    /// The same with a hint.
    pub fn with_help(mut self, help: impl Into<String>) -> ConfError {
        self.help = Some(help.into());
        self
    }

    /// 1-based (line, column) of the start of the span.
    pub fn line_col(&self) -> (usize, usize) {
        let text = self.src.inner();
        let before = &text[..self.span.0.min(text.len())];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, col)
    }
}

/// A file's name and text as diagnostics show them.
pub fn named(name: &str, text: &str) -> Arc<NamedSource<String>> {
    Arc::new(NamedSource::new(name, text.to_string()))
}

impl fmt::Display for ConfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ConfError {}

impl Diagnostic for ConfError {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.kind.code()))
    }

    fn severity(&self) -> Option<miette::Severity> {
        (self.kind == ConfErrorKind::NotImplemented).then_some(miette::Severity::Warning)
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help.as_ref().map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        (self.kind != ConfErrorKind::Io).then_some(self.src.as_ref() as &dyn SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        if self.kind == ConfErrorKind::Io {
            return None;
        }
        let label = LabeledSpan::new(Some("here".into()), self.span.0, self.span.1.max(1));
        Some(Box::new(std::iter::once(label)))
    }
}
