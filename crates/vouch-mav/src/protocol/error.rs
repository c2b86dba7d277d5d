//! Located errors of the protocol language, rendered by miette with the offending source line.

use std::fmt;

use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode};

/// A byte range of a protocol text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Span {
    /// Byte offset of the first byte.
    pub start: usize,
    /// Length in bytes.
    pub len: usize,
}

impl Span {
    /// The range `start..start + len`.
    pub fn new(start: usize, len: usize) -> Span {
        Span { start, len }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        let end = (other.start + other.len).max(self.start + self.len);
        Span { start: self.start, len: end - self.start }
    }
}

/// What kind of mistake a protocol error reports; each kind has its own diagnostic code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorKind {
    /// A character or number the lexer cannot read (`mav::P001`).
    Lex,
    /// Text that does not follow the grammar (`mav::P002`).
    Syntax,
    /// A name that resolves to nothing: message, field, role, constant, enum entry, variable
    /// (`mav::P003`).
    UnknownName,
    /// Something defined twice: protocol, constant, branch label (`mav::P004`).
    Duplicate,
    /// A type mismatch (`mav::P005`).
    Type,
    /// A protocol whose shape is wrong: roles, unreachable steps, `continue` outside its `rec`,
    /// a body that does not start with a step (`mav::P006`).
    Structure,
    /// A limit of the monitor's fixed-size buffers (`mav::P007`).
    Limit,
    /// A constant override (`--set NAME=VALUE`) naming no declared constant (`mav::P008`).
    Override,
}

impl ErrorKind {
    /// The diagnostic code.
    pub fn code(self) -> &'static str {
        match self {
            ErrorKind::Lex => "mav::P001",
            ErrorKind::Syntax => "mav::P002",
            ErrorKind::UnknownName => "mav::P003",
            ErrorKind::Duplicate => "mav::P004",
            ErrorKind::Type => "mav::P005",
            ErrorKind::Structure => "mav::P006",
            ErrorKind::Limit => "mav::P007",
            ErrorKind::Override => "mav::P008",
        }
    }
}

/// What a protocol error says: its kind, message, location and hint (the fields of
/// [`ProtocolError`], reached through `Deref`).
#[derive(Debug)]
pub struct ErrorDetails {
    /// What kind of mistake.
    pub kind: ErrorKind,
    /// One sentence saying what is wrong.
    pub message: String,
    /// The protocol text, named after its file.
    pub src: NamedSource<String>,
    /// Where in the text.
    pub span: Span,
    /// How to fix it, when there is something to say.
    pub help: Option<String>,
    /// 1-based line of the span start (for plain-text output and tests).
    pub line: usize,
    /// 1-based column (in characters) of the span start.
    pub col: usize,
}

/// An error in a protocol file, with its kind and location. The details live behind one box so
/// that `Result<_, ProtocolError>` stays a pointer wide on the compiler's many fallible paths
/// (the source text it carries for miette is large, and errors are cold).
#[derive(Debug)]
pub struct ProtocolError(Box<ErrorDetails>);

impl std::ops::Deref for ProtocolError {
    type Target = ErrorDetails;

    fn deref(&self) -> &ErrorDetails {
        &self.0
    }
}

impl ProtocolError {
    /// An error in an unnamed text (the file name is attached later by [`in_file`](Self::in_file)).
    pub fn at(kind: ErrorKind, src: &str, span: Span, message: impl Into<String>) -> ProtocolError {
        Self::named(kind, "<protocol>", src, span, message)
    }

    /// An error at `span` of the text `src` named `name`.
    pub fn named(
        kind: ErrorKind,
        name: &str,
        src: &str,
        span: Span,
        message: impl Into<String>,
    ) -> ProtocolError {
        let start = span.start.min(src.len());
        let before = &src[..start];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map(|l| l.chars().count()).unwrap_or(0) + 1;
        ProtocolError(Box::new(ErrorDetails {
            kind,
            message: message.into(),
            src: NamedSource::new(name, src.to_string()),
            span: Span::new(start, span.len.min(src.len() - start)),
            help: None,
            line,
            col,
        }))
    }

    /// Adds a hint.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.0.help = Some(help.into());
        self
    }

    /// Re-attaches the error to a named file (errors are built before the name is known).
    pub fn in_file(self, name: &str, src: &str) -> Self {
        let ErrorDetails { kind, message, span, help, .. } = *self.0;
        let mut e = Self::named(kind, name, src, span, message);
        e.0.help = help;
        e
    }

    /// `file:line:col: message` for plain output.
    pub fn short(&self) -> String {
        format!("{}:{}:{}: {}", self.src.name(), self.line, self.col, self.message)
    }
}

impl fmt::Display for ProtocolError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ProtocolError {}

impl Diagnostic for ProtocolError {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.kind.code()))
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help.as_ref().map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        Some(&self.src)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = LabeledSpan::new(Some("here".into()), self.span.start, self.span.len);
        Some(Box::new(std::iter::once(span)))
    }
}
