//! Warnings about mission-level mistakes that compile fine (`vouch fpl lint`). Each warning
//! has a stable code, a message and a location in the XML (AST spans); see
//! `docs/fpl-evidence.md` for the table of codes.
//!
//! The rules work on the resolved AST only (no compilation needed), so they also run on plans
//! the back end rejects. They are static over-approximations of the plan's behaviour: a block
//! is "reachable" when some chain of next-block, deroute or exception edges leads to it.

pub(crate) mod rules;

use serde::Serialize;

use crate::ast::FlightPlan;
use crate::span::Span;

/// Every warning code with its one-line meaning (the documentation table is generated from
/// the same words).
pub const CODES: &[(&str, &str)] = &[
    ("FPL-W001", "block unreachable from the first block (and not an operator entry point)"),
    ("FPL-W002", "block change always forbidden: the deroute, exception or next-block step can never happen"),
    ("FPL-W003", "block change forbidden under `only_when`: the step can block while the condition holds"),
    ("FPL-W004", "RETURN reachable after a DEROUTE into its block: the return re-runs the deroute (ping-pong)"),
    ("FPL-W005", "`for` bound does not fit the `int8_t` loop counter"),
    ("FPL-W006", "block exception targets its own block and can never fire"),
    ("FPL-W007", "waypoint never used by the plan"),
    ("FPL-W008", "stage can never run (it follows a deroute, return or home stage)"),
];

#[derive(Debug, Clone, Serialize)]
pub struct Note {
    pub message: String,
    pub span: Span,
}

#[derive(Debug, Clone, Serialize)]
pub struct Warning {
    pub code: &'static str,
    pub message: String,
    pub span: Span,
    pub notes: Vec<Note>,
}

/// All warnings of `plan`, sorted by file position.
pub fn lint(plan: &FlightPlan) -> Vec<Warning> {
    let mut out = Vec::new();
    rules::unreachable_blocks(plan, &mut out);
    rules::forbidden_steps(plan, &mut out);
    rules::return_after_deroute(plan, &mut out);
    rules::for_bounds(plan, &mut out);
    rules::self_exceptions(plan, &mut out);
    rules::unused_waypoints(plan, &mut out);
    rules::dead_stages(plan, &mut out);
    out.sort_by_key(|w| (w.span.file.0, w.span.start, w.code));
    out
}

fn source_line(plan: &FlightPlan, span: Span) -> Option<&str> {
    let f = plan.sources.get(span.file)?;
    f.text.lines().nth(span.line.checked_sub(1)? as usize)
}

fn locate(plan: &FlightPlan, span: Span) -> String {
    format!("{}:{}:{}", plan.sources.path(span.file), span.line, span.col)
}

/// `file:line:col: warning[CODE]: message`, the source line with a caret, and the notes.
pub fn render(plan: &FlightPlan, warnings: &[Warning]) -> String {
    let mut s = String::new();
    for w in warnings {
        s.push_str(&format!("{}: warning[{}]: {}\n", locate(plan, w.span), w.code, w.message));
        if let Some(line) = source_line(plan, w.span) {
            s.push_str(&format!("  {:>5} | {}\n", w.span.line, line.trim_end()));
            let pad = (w.span.col as usize).saturating_sub(1);
            s.push_str(&format!("        | {}^\n", " ".repeat(pad)));
        }
        for n in &w.notes {
            s.push_str(&format!("  note: {} ({})\n", n.message, locate(plan, n.span)));
        }
    }
    s
}

/// Warnings per code, in code order (for summaries).
pub fn counts(warnings: &[Warning]) -> Vec<(&'static str, usize)> {
    CODES.iter().map(|(c, _)| (*c, warnings.iter().filter(|w| w.code == *c).count())).collect()
}
