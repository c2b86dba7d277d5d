//! Shared state of one front-end run ([`Ctx`]): the sources read, the diagnostics collected
//! (errors are not fatal one by one, so a broken plan reports all its problems), the name
//! tables, and the typed attribute readers every builder uses.

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

use crate::ast::{BlockRef, ExprAttr, FlightPlan, Num, Text, WpRef};
use crate::diag::{Diagnostic, Diagnostics, ErrorKind, Severity};
use crate::expr::{Expr, parse};
use crate::ids::{BlockId, WpId};
use crate::span::{SourceMap, Span, line_col};

use super::Options;
use super::tree::Elem;
use super::values::{degrees, ocaml_float};

/// Shared state of one front-end run.
pub struct Ctx {
    pub sources: SourceMap,
    pub opts: Options,
    /// Include search path: the main plan's directory first.
    pub search: Vec<PathBuf>,
    pub main_path: PathBuf,
    pub errors: Vec<Diagnostic>,
    pub warnings: Vec<Diagnostic>,
    reported: HashSet<(ErrorKind, u32, u32, String)>,
    /// Block name -> index (first occurrence), known before stages are built.
    pub blocks: HashMap<String, BlockId>,
    /// Waypoint name -> index (first occurrence).
    pub waypoints: HashMap<String, WpId>,
}

impl Ctx {
    pub fn new(
        sources: SourceMap,
        opts: Options,
        search: Vec<PathBuf>,
        main_path: PathBuf,
    ) -> Self {
        Ctx {
            sources,
            opts,
            search,
            main_path,
            errors: Vec::new(),
            warnings: Vec::new(),
            reported: HashSet::new(),
            blocks: HashMap::new(),
            waypoints: HashMap::new(),
        }
    }

    pub fn push(&mut self, d: Diagnostic) {
        if d.severity == Severity::Warning {
            self.warnings.push(d);
            return;
        }
        let key = d.span.map(|s| (s.file.0, s.start)).unwrap_or((u32::MAX, 0));
        if self.reported.insert((d.kind, key.0, key.1, d.message.clone())) {
            self.errors.push(d);
        }
    }
    pub fn error(&mut self, kind: ErrorKind, msg: impl Into<String>, span: Span) {
        self.push(Diagnostic::error(kind, msg, Some(span)));
    }
    pub fn error_help(
        &mut self,
        kind: ErrorKind,
        msg: impl Into<String>,
        span: Span,
        help: impl Into<String>,
    ) {
        self.push(Diagnostic::error(kind, msg, Some(span)).with_help(help));
    }
    pub fn warn(&mut self, msg: impl Into<String>, span: Span) {
        self.push(Diagnostic::warning(msg, Some(span)));
    }

    /// Turns the run into the result: any error makes it fail.
    pub fn finish(mut self, plan: Option<FlightPlan>) -> Result<FlightPlan, Diagnostics> {
        for d in self.errors.iter_mut().chain(self.warnings.iter_mut()) {
            d.locate(&self.sources);
        }
        match plan {
            Some(mut p) if self.errors.is_empty() => {
                p.sources = self.sources;
                p.warnings = self.warnings;
                Ok(p)
            }
            _ => {
                if self.errors.is_empty() {
                    self.errors.push(Diagnostic::error(
                        ErrorKind::Xml,
                        "the plan could not be read",
                        None,
                    ));
                }
                let mut items = self.errors;
                items.extend(self.warnings);
                Err(Diagnostics { items, sources: self.sources })
            }
        }
    }

    // ----- attribute readers -------------------------------------------------------------

    pub fn text(&self, e: &Elem, name: &str) -> Option<Text> {
        e.attr(name).map(|a| Text { value: a.value.clone(), span: a.value_span })
    }

    pub fn req_text(&mut self, e: &Elem, name: &str) -> Option<Text> {
        let t = self.text(e, name);
        if t.is_none() {
            self.missing(e, name);
        }
        t
    }

    pub fn missing(&mut self, e: &Elem, name: &str) {
        self.error(
            ErrorKind::MissingAttribute,
            format!("missing attribute '{name}' on <{}>", e.tag),
            e.span,
        );
    }

    fn number(&mut self, e: &Elem, name: &str, read: fn(&str) -> Option<f64>) -> Option<Num> {
        let t = self.text(e, name)?;
        match read(&t.value) {
            Some(v) if !v.is_finite() => {
                self.error_help(
                    ErrorKind::BadNumber,
                    format!("'{name}' of <{}> is '{}', not a finite number", e.tag, t.value),
                    t.span,
                    "upstream reads nan and inf as numbers and prints them into the C header",
                );
                None
            }
            Some(v) => Some(Num { text: t, value: v }),
            None => {
                self.error(
                    ErrorKind::BadNumber,
                    format!(
                        "float expected in attribute '{name}' of <{}>, found '{}'",
                        e.tag, t.value
                    ),
                    t.span,
                );
                None
            }
        }
    }
    pub fn opt_num(&mut self, e: &Elem, name: &str) -> Option<Num> {
        self.number(e, name, ocaml_float)
    }
    pub fn req_num(&mut self, e: &Elem, name: &str) -> Option<Num> {
        if e.attr(name).is_none() {
            self.missing(e, name);
            return None;
        }
        self.opt_num(e, name)
    }
    pub fn opt_deg(&mut self, e: &Elem, name: &str, limit: f64) -> Option<Num> {
        let n = self.number(e, name, degrees)?;
        if !n.value.is_finite() || n.value.abs() > limit {
            self.error(
                ErrorKind::NumberOutOfRange,
                format!("'{name}' = {} is outside [-{limit}, {limit}] degrees", n.text.value),
                n.text.span,
            );
        }
        Some(n)
    }

    /// Parses an expression attribute and resolves `IndexOfBlock`.
    pub fn expr_attr(&mut self, e: &Elem, name: &str) -> Option<ExprAttr> {
        let t = self.text(e, name)?;
        self.expr_text(t, &format!("attribute '{name}' of <{}>", e.tag))
    }
    pub fn req_expr(&mut self, e: &Elem, name: &str) -> Option<ExprAttr> {
        if e.attr(name).is_none() {
            self.missing(e, name);
            return None;
        }
        self.expr_attr(e, name)
    }

    /// An expression attribute upstream reads only in some contexts: parsed when `read`,
    /// else left out; an unread value that would not parse is a warning (upstream never looks
    /// at it), not an error.
    pub fn lazy_expr(&mut self, e: &Elem, name: &str, read: bool, why: &str) -> Option<ExprAttr> {
        if read {
            return self.expr_attr(e, name);
        }
        let t = self.text(e, name)?;
        if let Err(err) = parse(&t.value) {
            self.push(Diagnostic::warning_of(
                ErrorKind::Unread,
                format!(
                    "attribute '{name}' of <{}> is not read ({why}); upstream ignores it, so its value '{}' \
                     is not checked ({err})",
                    e.tag, t.value
                ),
                Some(t.span),
            ));
        }
        None
    }

    pub fn expr_text(&mut self, t: Text, what: &str) -> Option<ExprAttr> {
        match parse(&t.value) {
            Ok(mut expr) => {
                self.resolve_index_of_block(&mut expr, t.span);
                Some(ExprAttr { text: t, expr })
            }
            Err(err) => {
                // Point at the offending token when the value is still the source text.
                let src = self.sources.snippet(t.span);
                let span = if src == t.value {
                    sub_span(&self.sources, t.span, err.start, err.end)
                } else {
                    t.span
                };
                self.error(
                    ErrorKind::BadExpression,
                    format!("invalid expression in {what}: '{}': {err}", t.value),
                    span,
                );
                None
            }
        }
    }

    fn resolve_index_of_block(&mut self, expr: &mut Expr, span: Span) {
        let mut unknown = Vec::new();
        let blocks = &self.blocks;
        expr.walk_mut(&mut |x| {
            if let Expr::Call(f, args) = x
                && f == "IndexOfBlock"
                && let [Expr::Ident(name)] = args.as_slice()
            {
                match blocks.get(name) {
                    Some(id) => *x = Expr::BlockIndex { name: name.clone(), id: *id },
                    None => unknown.push(name.clone()),
                }
            }
        });
        for n in unknown {
            self.error(ErrorKind::UnknownBlock, format!("IndexOfBlock: unknown block '{n}'"), span);
        }
    }

    pub fn block_ref(&mut self, t: Text) -> Option<BlockRef> {
        match self.blocks.get(&t.value) {
            Some(id) => Some(BlockRef { name: t.value, id: *id, span: t.span }),
            None => {
                self.error(ErrorKind::UnknownBlock, format!("unknown block '{}'", t.value), t.span);
                None
            }
        }
    }

    pub fn wp_ref(&mut self, e: &Elem, name: &str) -> Option<WpRef> {
        let t = self.text(e, name)?;
        self.wp_named(t)
    }
    pub fn req_wp(&mut self, e: &Elem, name: &str) -> Option<WpRef> {
        if e.attr(name).is_none() {
            self.missing(e, name);
            return None;
        }
        self.wp_ref(e, name)
    }
    pub fn wp_named(&mut self, t: Text) -> Option<WpRef> {
        match self.waypoints.get(&t.value) {
            Some(id) => Some(WpRef { name: t.value, id: *id, span: t.span }),
            None => {
                self.error(
                    ErrorKind::UnknownWaypoint,
                    format!("unknown waypoint '{}'", t.value),
                    t.span,
                );
                None
            }
        }
    }
}

fn sub_span(sources: &SourceMap, s: Span, from: usize, to: usize) -> Span {
    let text = sources.get(s.file).map(|f| f.text.as_str()).unwrap_or("");
    let start = (s.start as usize + from).min(s.end as usize);
    let mut end = (s.start as usize + to.max(from + 1)).min(s.end as usize).max(start);
    // Keep the label on character boundaries (the value may hold multi-byte characters).
    while end < text.len() && !text.is_char_boundary(end) {
        end += 1;
    }
    let (line, col) = line_col(text, start);
    Span { file: s.file, start: start as u32, end: end as u32, line, col }
}
