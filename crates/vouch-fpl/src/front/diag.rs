//! Located diagnostics: every error of the front end carries a kind, a message and (almost
//! always) a span with file, line and column; rendering shows a source snippet via miette.

use serde::Serialize;

use crate::ast::{SourceMap, Span};

/// What went wrong; tests and tools match on this rather than on message texts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum ErrorKind {
    /// Reading a file failed (CLI exit code 2 when it is the main plan).
    Io,
    /// Not well-formed XML even for upstream's lenient reader (unclosed tag, ...).
    Xml,
    /// The root element is not `<flight_plan>`.
    WrongRoot,
    /// An element not allowed at that place.
    UnexpectedElement,
    /// A stage tag that does not exist (case-sensitive, as upstream).
    UnknownStage,
    /// An attribute not declared for that element.
    UnknownAttribute,
    /// A required attribute is missing.
    MissingAttribute,
    /// A required element is missing (`<waypoints>`, `<blocks>`, a `HOME` waypoint, ...).
    MissingElement,
    /// The plan has no block or no waypoint.
    EmptyPlan,
    /// Two blocks with the same name.
    DuplicateBlock,
    /// Two written waypoints with the same name (upstream silently uses the first; vouch
    /// refuses it; duplicates created by relative waypoints stay warnings, as they are upstream's
    /// own doing).
    DuplicateWaypoint,
    /// A deroute / exception / `IndexOfBlock` / forbidden deroute names no block.
    UnknownBlock,
    /// A stage or sector corner names no waypoint.
    UnknownWaypoint,
    /// A number that does not parse (`Float expected`).
    BadNumber,
    /// A number that parses but is out of its range (latitude beyond 90, negative height...).
    NumberOutOfRange,
    /// An attribute value outside its fixed set (vmode, hmode, loop, orientation, wp_frame...).
    BadValue,
    /// An expression that does not lex or parse.
    BadExpression,
    /// An included procedure file cannot be found or read.
    IncludeNotFound,
    /// An include that (directly or indirectly) includes itself.
    IncludeLoop,
    /// A procedure parameter with neither argument nor default value.
    MissingParam,
    /// A stage kind upstream refuses inside procedures (`guided`, `oval`, `path`, ...).
    ProcedureStage,
    /// Inconsistent attributes on one element (both `approaching_time` and `exceeding_time`,
    /// both `vars` and `handler`, `pitch="auto"` with `vmode="throttle"`, ...).
    Conflict,
    /// Non-fatal: something accepted the way upstream accepts it, worth knowing.
    Warning,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Severity {
    Error,
    Warning,
}

/// One finding. `file`, `line` and `col` are filled from the span for convenience.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnostic {
    pub kind: ErrorKind,
    pub severity: Severity,
    pub message: String,
    pub span: Option<Span>,
    pub file: Option<String>,
    pub line: Option<u32>,
    pub col: Option<u32>,
    /// Extra explanation (for example the upstream behaviour this mirrors).
    pub help: Option<String>,
}

impl Diagnostic {
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
        }
    }
    pub fn warning(message: impl Into<String>, span: Option<Span>) -> Self {
        Diagnostic { severity: Severity::Warning, ..Self::error(ErrorKind::Warning, message, span) }
    }
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }
    /// Fills `file`/`line`/`col` from the span.
    pub fn locate(&mut self, sources: &SourceMap) {
        if let Some(sp) = self.span {
            self.file = Some(sources.path(sp.file).to_string());
            self.line = Some(sp.line);
            self.col = Some(sp.col);
        }
    }
}

/// The errors (and warnings) of a failed parse, with the sources needed to render them.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnostics {
    pub items: Vec<Diagnostic>,
    #[serde(skip)]
    pub sources: SourceMap,
}

impl Diagnostics {
    /// Builds a report over `sources` (for example `plan.sources.clone()` in later passes),
    /// filling every item's file/line/column from its span.
    pub fn new(mut items: Vec<Diagnostic>, sources: SourceMap) -> Self {
        for d in items.iter_mut() {
            d.locate(&sources);
        }
        Diagnostics { items, sources }
    }
    pub fn errors(&self) -> impl Iterator<Item = &Diagnostic> {
        self.items.iter().filter(|d| d.severity == Severity::Error)
    }
    /// The first error (there is always at least one in a returned `Diagnostics`).
    pub fn first(&self) -> Option<&Diagnostic> {
        self.errors().next()
    }
    /// True when the failure is an I/O problem with the main plan (CLI exit code 2).
    pub fn is_io(&self) -> bool {
        self.first().is_some_and(|d| d.kind == ErrorKind::Io && d.span.is_none())
    }
    /// Renders every item as `file:line:col: error[Kind]: message` followed by a miette
    /// snippet of the source.
    pub fn render(&self, color: bool) -> String {
        let mut out = String::new();
        for d in &self.items {
            out.push_str(&super::render::render_one(d, &self.sources, color));
        }
        out
    }
}

impl std::fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.render(false))
    }
}

impl std::error::Error for Diagnostics {}
