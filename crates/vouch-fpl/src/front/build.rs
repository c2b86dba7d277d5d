//! Runs the front end on the main file: reads the document, checks the root and the schema,
//! expands includes, paths and relative waypoints, then builds the typed [`FlightPlan`]
//! ([`super::plan`], stages in [`super::stages`]).

use crate::ast::FlightPlan;
use crate::diag::{Diagnostic, ErrorKind};
use crate::span::{FileId, Span};

use super::ctx::Ctx;
use super::expand::{expand_paths, relative_waypoints};
use super::include::expand;
use super::schema;
use super::tree::{Elem, read_document};

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
            ctx.push(*d);
            return None;
        }
    };
    ctx.warnings.extend(doc.warnings);
    let validated = doc.doctype.is_some();
    let mut root = doc.root;
    if validated {
        super::expanded::sort_validated(&mut root);
    }
    if let Some((file, span)) = &doc.dtd_file {
        let dir = ctx.main_path.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
        // Only for plans read from a file (a text parsed on its own has no directory).
        if ctx.main_path.is_file() && !dir.join(file).is_file() {
            ctx.error_help(
                ErrorKind::Xml,
                format!("the DTD '{file}' named by the DOCTYPE does not exist"),
                *span,
                "upstream validates every plan that declares a DOCTYPE and stops when its DTD is missing",
            );
            return None;
        }
    }
    if root.tag != "flight_plan" {
        ctx.error_help(
            ErrorKind::WrongRoot,
            format!("the root element is <{}>, expected <flight_plan>", root.tag),
            root.span,
            "a <procedure> file can only be used through <includes>",
        );
        return None;
    }
    check_schema(ctx, &root, validated, "flight_plan");
    check_plan_children(ctx, &root, validated);

    let mut m = expand(ctx, &root, validated);
    for b in m.blocks.iter_mut() {
        let stages = std::mem::take(&mut b.children);
        b.children = expand_paths(ctx, stages);
    }
    relative_waypoints(&mut m.blocks, &mut m.waypoints);
    let had_includes = root.child("includes").is_some_and(|i| !i.children.is_empty());
    let expanded = super::expanded::build(&root, &m, had_includes);
    let mut plan = super::plan::build_plan(ctx, &root, m)?;
    plan.expanded = Some(std::sync::Arc::new(expanded));
    Some(plan)
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
