//! Located diagnostics, below every phase: every error of the front end and of the passes
//! carries a kind (with a stable code such as `fpl::E014`), a message and (almost always) a
//! span with file, line and column. [`Diagnostic`] and [`Diagnostics`] implement
//! [`miette::Diagnostic`], so a front end (the CLI) renders them with a source excerpt in the
//! format it chooses; this crate never prints them.

mod kind;
mod report;

use std::sync::Arc;

use serde::Serialize;

pub use kind::ErrorKind;
pub(crate) use report::underline;

use crate::span::{SourceFile, SourceMap, Span};

/// Whether a diagnostic stops the plan from being accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Severity {
    /// The plan is rejected.
    Error,
    /// Accepted the way upstream accepts it, worth knowing.
    Warning,
}

/// One finding. `file`, `line` and `col` are filled from the span by [`Diagnostic::locate`].
#[derive(Debug, Clone, Serialize)]
pub struct Diagnostic {
    /// What went wrong (tools match on this, not on the message).
    pub kind: ErrorKind,
    /// Error or warning.
    pub severity: Severity,
    /// One sentence for the user.
    pub message: String,
    /// Where, when the input has a position for it.
    pub span: Option<Span>,
    /// Path of the file the span is in.
    pub file: Option<String>,
    /// 1-based line of the span.
    pub line: Option<u32>,
    /// 1-based column of the span.
    pub col: Option<u32>,
    /// Extra explanation (for example the upstream behaviour this mirrors).
    pub help: Option<String>,
    /// The file the span points into, for rendering the excerpt.
    #[serde(skip)]
    source: Option<Arc<SourceFile>>,
}

impl Diagnostic {
    /// An error of `kind`, located at `span` when given.
    pub fn error(kind: ErrorKind, message: impl Into<String>, span: Option<Span>) -> Self {
        Diagnostic {
            kind,
            severity: Severity::Error,
            message: message.into(),
            span,
            file: None,
            line: None,
            col: None,
            help: None,
            source: None,
        }
    }

    /// A warning (kind [`ErrorKind::Warning`]).
    pub fn warning(message: impl Into<String>, span: Option<Span>) -> Self {
        Diagnostic { severity: Severity::Warning, ..Self::error(ErrorKind::Warning, message, span) }
    }

    /// A warning of a given kind (upstream's notices, corrections, unread attributes).
    pub fn warning_of(kind: ErrorKind, message: impl Into<String>, span: Option<Span>) -> Self {
        Diagnostic { severity: Severity::Warning, ..Self::error(kind, message, span) }
    }

    /// A correction of upstream's output, located, with the reason.
    pub fn correction(message: impl Into<String>, span: Span, why: impl Into<String>) -> Self {
        Self::warning_of(ErrorKind::Correction, message, Some(span)).with_help(why)
    }

    /// Adds an explanation.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Fills `file`/`line`/`col` from the span and keeps the file for rendering.
    pub fn locate(&mut self, sources: &SourceMap) {
        if let Some(sp) = self.span {
            self.file = Some(sources.path(sp.file).to_string());
            self.line = Some(sp.line);
            self.col = Some(sp.col);
            self.source = sources.get(sp.file).cloned();
        }
    }

    /// `file:line:col: error[fpl::E014]: message` (the location when known).
    pub fn brief(&self) -> String {
        let mut s = String::new();
        if let (Some(f), Some(l), Some(c)) = (&self.file, self.line, self.col) {
            s.push_str(&format!("{f}:{l}:{c}: "));
        }
        let sev = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        s.push_str(&format!("{sev}[{}]: {}", self.kind.code(), self.message));
        s
    }
}

/// The errors (and warnings) of a rejected plan, with the sources they point into. As a
/// [`miette::Diagnostic`] it is its first error, with every other item as related diagnostics.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnostics {
    /// Errors first, then warnings.
    pub items: Vec<Diagnostic>,
    /// The files the spans point into.
    #[serde(skip)]
    pub sources: SourceMap,
}

impl Diagnostics {
    /// Builds a report over `sources`, locating every item.
    pub fn new(mut items: Vec<Diagnostic>, sources: SourceMap) -> Self {
        for d in items.iter_mut() {
            d.locate(&sources);
        }
        Diagnostics { items, sources }
    }

    /// The errors (not the warnings).
    pub fn errors(&self) -> impl Iterator<Item = &Diagnostic> {
        self.items.iter().filter(|d| d.severity == Severity::Error)
    }

    /// The first error (there is always at least one in a returned `Diagnostics`).
    pub fn first(&self) -> Option<&Diagnostic> {
        self.errors().next()
    }

    /// True when the failure is an I/O problem with the main plan (not a property of its text).
    pub fn is_io(&self) -> bool {
        self.first().is_some_and(|d| d.kind == ErrorKind::Io && d.span.is_none())
    }

    /// Every item as a [`Diagnostic::brief`] line.
    pub fn listing(&self) -> String {
        self.items.iter().map(|d| d.brief() + "\n").collect()
    }
}

/// A word of the input quoted in a message: control characters escaped and at most 40
/// characters (a "word" of a binary or one-line file can be megabytes long; the label under the
/// message shows where it is).
pub fn quote(word: &str) -> String {
    const MAX: usize = 40;
    let head: String = word.chars().take(MAX).collect();
    let more = if head.len() < word.len() { "…" } else { "" };
    format!("{}{more}", head.escape_debug())
}
