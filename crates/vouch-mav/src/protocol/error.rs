//! Located errors of the protocol language (rendered by miette with the offending source line).

use miette::{NamedSource, SourceSpan};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Span {
    pub start: usize,
    pub len: usize,
}

impl Span {
    pub fn new(start: usize, len: usize) -> Span {
        Span { start, len }
    }

    pub fn to(self, other: Span) -> Span {
        let end = (other.start + other.len).max(self.start + self.len);
        Span { start: self.start, len: end - self.start }
    }
}

/// An error in a protocol file, with its location.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("{message}")]
pub struct ProtocolError {
    pub message: String,
    #[source_code]
    pub src: NamedSource<String>,
    #[label("{label}")]
    pub span: SourceSpan,
    pub label: String,
    #[help]
    pub help: Option<String>,
    /// 1-based line and column of the span start (for plain-text output and tests).
    pub line: usize,
    pub col: usize,
}

impl ProtocolError {
    pub fn at(src: &str, span: Span, message: impl Into<String>) -> ProtocolError {
        Self::named("<protocol>", src, span, message)
    }

    pub fn named(name: &str, src: &str, span: Span, message: impl Into<String>) -> ProtocolError {
        let start = span.start.min(src.len());
        let before = &src[..start];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map(|l| l.chars().count()).unwrap_or(0) + 1;
        ProtocolError {
            message: message.into(),
            src: NamedSource::new(name, src.to_string()),
            span: SourceSpan::new(start.into(), span.len),
            label: "here".into(),
            help: None,
            line,
            col,
        }
    }

    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Re-attaches the error to a named file (errors are built before the name is known).
    pub fn in_file(self, name: &str, src: &str) -> Self {
        let span = Span::new(self.span.offset(), self.span.len());
        let help = self.help.clone();
        let mut e = Self::named(name, src, span, self.message);
        e.help = help;
        e
    }

    /// `file:line:col: message` for plain output.
    pub fn short(&self) -> String {
        format!("{}:{}:{}: {}", self.src.name(), self.line, self.col, self.message)
    }
}
