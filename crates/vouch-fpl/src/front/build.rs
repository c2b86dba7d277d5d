//! Builds the typed [`FlightPlan`] from the expanded element lists: plan attributes, header,
//! waypoints, sectors, variables, modules, exceptions, blocks (stages in [`super::stages`]),
//! the implicit `HOME` block and forbidden deroutes. Errors are collected, not fatal one by one,
//! so a broken plan reports all its problems.

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

use crate::ast::*;
use crate::expr::{parse, Expr};

use super::diag::{Diagnostic, Diagnostics, ErrorKind, Severity};
use super::expand::{expand_paths, relative_waypoints};
use super::include::{expand, Merged};
use super::schema;
use super::tree::{read_document, Elem};
use super::values::{degrees, ocaml_float};
use super::Options;

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
            if let Expr::Call(f, args) = x {
                if f == "IndexOfBlock" {
                    if let [Expr::Ident(name)] = args.as_slice() {
                        match blocks.get(name) {
                            Some(id) => *x = Expr::BlockIndex { name: name.clone(), id: *id },
                            None => unknown.push(name.clone()),
                        }
                    }
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

/// Runs the whole front end on the main file.
pub fn run(ctx: &mut Ctx, main: FileId) -> Option<FlightPlan> {
    let text = ctx.sources.files[main.0 as usize].text.clone();
    if text.trim().is_empty() {
        ctx.push(Diagnostic::error(
            ErrorKind::EmptyPlan,
            "the file is empty",
            Some(Span { file: main, line: 1, col: 1, ..Span::default() }),
        ));
        return None;
    }
    let doc = match read_document(main, &text) {
        Ok(d) => d,
        Err(d) => {
            ctx.push(d);
            return None;
        }
    };
    ctx.warnings.extend(doc.warnings);
    let root = doc.root;
    if !root.tag_is("flight_plan") {
        ctx.error_help(
            ErrorKind::WrongRoot,
            format!("the root element is <{}>, expected <flight_plan>", root.tag),
            root.span,
            "a <procedure> file can only be used through <includes>",
        );
        return None;
    }
    let validated = doc.doctype.is_some();
    check_schema(ctx, &root, validated, "flight_plan");
    check_plan_children(ctx, &root, validated);

    let mut m = expand(ctx, &root);
    for b in m.blocks.iter_mut() {
        let stages = std::mem::take(&mut b.children);
        b.children = expand_paths(ctx, stages);
    }
    relative_waypoints(&mut m.blocks, &mut m.waypoints);
    super::plan::build_plan(ctx, &root, m)
}

/// Checks attributes against the DTD lists, recursively. Only files that declare a DOCTYPE are
/// validated upstream; elsewhere an undeclared attribute is only a warning.
fn check_schema(ctx: &mut Ctx, e: &Elem, validated: bool, tag_lc: &str) {
    if let Some((declared, required)) = schema::attributes(tag_lc) {
        let extra = schema::undeclared_but_read(tag_lc);
        for a in &e.attrs.0 {
            if declared.contains(&a.name.as_str()) {
                continue;
            }
            if validated {
                ctx.error(
                    ErrorKind::UnknownAttribute,
                    format!("unexpected attribute '{}' on <{}>", a.name, e.tag),
                    a.span,
                );
            } else if !extra.contains(&a.name.as_str()) {
                ctx.warn(
                    format!("undeclared attribute '{}' on <{}> (kept, not used)", a.name, e.tag),
                    a.span,
                );
            }
        }
        if validated {
            for r in required {
                if e.attr(r).is_none() {
                    ctx.missing(e, r);
                }
            }
        }
    }
    for c in &e.children {
        let lc = c.tag.to_ascii_lowercase();
        check_schema(ctx, c, validated, &lc);
    }
}

/// Children of `<flight_plan>`: known elements only, in the DTD order (when validated).
fn check_plan_children(ctx: &mut Ctx, root: &Elem, validated: bool) {
    let mut last = 0usize;
    for c in &root.children {
        let lc = c.tag.to_ascii_lowercase();
        match schema::PLAN_ORDER.iter().position(|t| *t == lc) {
            Some(_) if lc == "forbidden_deroutes" && !ctx.opts.allow_forbidden_deroutes => {
                ctx.error(
                    ErrorKind::UnexpectedElement,
                    "<forbidden_deroutes> is a VFPG extension, disabled here",
                    c.span,
                );
            }
            Some(pos) => {
                if validated && pos < last {
                    ctx.error(
                        ErrorKind::UnexpectedElement,
                        format!(
                            "<{}> is out of order (expected: {})",
                            c.tag,
                            schema::PLAN_ORDER.join(", ")
                        ),
                        c.span,
                    );
                }
                last = last.max(pos);
            }
            None if validated => ctx.error(
                ErrorKind::UnexpectedElement,
                format!("unexpected element <{}> in <flight_plan>", c.tag),
                c.span,
            ),
            None => ctx.warn(format!("element <{}> ignored", c.tag), c.span),
        }
    }
    if root.child("waypoints").is_none() {
        ctx.error(ErrorKind::MissingElement, "the plan has no <waypoints>", root.span);
    }
    match root.child("blocks") {
        None => ctx.error(ErrorKind::EmptyPlan, "the plan has no <blocks>", root.span),
        // The DTD requires one block; unvalidated plans (dummy.xml) compile with HOME only.
        Some(b) if b.children.is_empty() && validated => ctx.error(
            ErrorKind::EmptyPlan,
            "<blocks> is empty (the DTD requires at least one block)",
            b.span,
        ),
        Some(_) => {}
    }
}

/// Keeps the first of each name in a table and reports later duplicates.
pub fn index_names(ctx: &mut Ctx, m: &Merged) {
    for (i, b) in m.blocks.iter().enumerate() {
        let Some(a) = b.attr("name") else { continue };
        if ctx.blocks.contains_key(&a.value) {
            ctx.error(
                ErrorKind::DuplicateBlock,
                format!("duplicate block name '{}'", a.value),
                a.value_span,
            );
        } else {
            ctx.blocks.insert(a.value.clone(), BlockId(i));
        }
    }
    let home = m.blocks.len();
    if ctx.blocks.contains_key("HOME") {
        if let Some(a) = m.blocks.iter().filter_map(|b| b.attr("name")).find(|a| a.value == "HOME")
        {
            ctx.error_help(
                ErrorKind::DuplicateBlock,
                "duplicate block name 'HOME'",
                a.value_span,
                "the implicit safety block appended after all blocks is named HOME",
            );
        }
    } else {
        ctx.blocks.insert("HOME".to_string(), BlockId(home));
    }
    for (i, w) in m.waypoints.iter().enumerate() {
        let Some(a) = w.attr("name") else { continue };
        if ctx.waypoints.contains_key(&a.value) {
            if w.relative.is_some() {
                ctx.warn(
                    format!(
                        "relative waypoint '{}' created twice (references use the first)",
                        a.value
                    ),
                    a.value_span,
                );
            } else {
                ctx.error_help(
                    ErrorKind::DuplicateWaypoint,
                    format!("duplicate waypoint name '{}'", a.value),
                    a.value_span,
                    "upstream would silently use the first one; procedures' waypoints are not prefixed",
                );
            }
        } else {
            ctx.waypoints.insert(a.value.clone(), WpId(i));
        }
    }
}
