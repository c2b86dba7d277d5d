//! Warnings about mission-level mistakes that compile fine (`vouch fpl lint`). Each warning
//! has a [`Rule`] with a stable code, a message and a location in the XML (AST spans); see
//! `docs/fpl-evidence.md` for the table of codes.
//!
//! The rules work on the resolved AST only (no compilation needed), so they also run on plans
//! the back end rejects. They are static over-approximations of the plan's behaviour: a block
//! is "reachable" when some chain of next-block, deroute or exception edges leads to it.

mod float_width;
mod report;
pub(crate) mod rules;

use std::sync::Arc;

use serde::{Serialize, Serializer};

pub use report::{counts, render};

use crate::ast::FlightPlan;
use crate::span::{SourceFile, SourceMap, Span};

/// The lint rules, each with its stable code (`fpl::W001` ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Rule {
    /// A block no step leads to (and not an operator entry point).
    UnreachableBlock,
    /// A block change that is always forbidden.
    AlwaysForbidden,
    /// A block change forbidden under `only_when`.
    ForbiddenWhen,
    /// A `return` reachable after a deroute into its block (ping-pong).
    ReturnAfterDeroute,
    /// A `for` bound outside `int8_t`.
    ForBound,
    /// A block exception targeting its own block.
    SelfException,
    /// A waypoint nothing uses.
    UnusedWaypoint,
    /// Stages that can never run.
    DeadStage,
    /// A comparison with a constant that single precision does not hold exactly.
    FloatWidth,
}

impl Rule {
    /// Every rule, in code order.
    pub const ALL: [Rule; 9] = [
        Rule::UnreachableBlock,
        Rule::AlwaysForbidden,
        Rule::ForbiddenWhen,
        Rule::ReturnAfterDeroute,
        Rule::ForBound,
        Rule::SelfException,
        Rule::UnusedWaypoint,
        Rule::DeadStage,
        Rule::FloatWidth,
    ];

    /// The stable code.
    pub fn code(self) -> &'static str {
        match self {
            Rule::UnreachableBlock => "fpl::W001",
            Rule::AlwaysForbidden => "fpl::W002",
            Rule::ForbiddenWhen => "fpl::W003",
            Rule::ReturnAfterDeroute => "fpl::W004",
            Rule::ForBound => "fpl::W005",
            Rule::SelfException => "fpl::W006",
            Rule::UnusedWaypoint => "fpl::W007",
            Rule::DeadStage => "fpl::W008",
            Rule::FloatWidth => "fpl::W009",
        }
    }

    /// The one-line meaning (the documentation table says the same).
    pub fn meaning(self) -> &'static str {
        match self {
            Rule::UnreachableBlock => {
                "block unreachable from the first block (and not an operator entry point)"
            }
            Rule::AlwaysForbidden => {
                "block change always forbidden: the deroute, exception or next-block step can never happen"
            }
            Rule::ForbiddenWhen => {
                "block change forbidden under `only_when`: the step can block while the condition holds"
            }
            Rule::ReturnAfterDeroute => {
                "RETURN reachable after a DEROUTE into its block: the return re-runs the deroute (ping-pong)"
            }
            Rule::ForBound => "`for` bound does not fit the `int8_t` loop counter",
            Rule::SelfException => "block exception targets its own block and can never fire",
            Rule::UnusedWaypoint => "waypoint never used by the plan",
            Rule::DeadStage => "stage can never run (it follows a deroute, return or home stage)",
            Rule::FloatWidth => {
                "comparison with a constant that single precision does not hold exactly: its result depends on float width"
            }
        }
    }
}

impl Serialize for Rule {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.code())
    }
}

/// A place related to a warning (the deroute that leads to a return, a forbidding declaration).
#[derive(Debug, Clone, Serialize)]
pub struct Note {
    pub message: String,
    pub span: Span,
    #[serde(skip)]
    source: Option<Arc<SourceFile>>,
}

impl Note {
    pub(crate) fn new(message: impl Into<String>, span: Span) -> Self {
        Note { message: message.into(), span, source: None }
    }
}

/// One finding of a rule.
#[derive(Debug, Clone, Serialize)]
pub struct Warning {
    /// Serialised as its code.
    #[serde(rename = "code")]
    pub rule: Rule,
    pub message: String,
    pub span: Span,
    pub notes: Vec<Note>,
    #[serde(skip)]
    source: Option<Arc<SourceFile>>,
}

impl Warning {
    pub(crate) fn new(rule: Rule, message: String, span: Span) -> Self {
        Warning { rule, message, span, notes: Vec::new(), source: None }
    }

    /// Keeps the files the spans point into, for rendering excerpts.
    fn attach(&mut self, sources: &SourceMap) {
        self.source = sources.get(self.span.file).cloned();
        for n in &mut self.notes {
            n.source = sources.get(n.span.file).cloned();
        }
    }
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
    float_width::float_width(plan, &mut out);
    out.sort_by_key(|w| (w.span.file.0, w.span.start, w.rule));
    for w in &mut out {
        w.attach(&plan.sources);
    }
    out
}
