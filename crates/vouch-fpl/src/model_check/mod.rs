//! Explicit-state model checking of a plan (`vouch fpl check`).
//!
//! The graph is the plan's reachable state space walked to a fixpoint by
//! [`crate::semantics::space`] — the same walk, transition relation and state view as the
//! translation validator, without the C beside it: one transition is one `auto_nav` call with
//! every condition *free* (both answers) and every `int8_t` value of a non-literal `for` bound,
//! or, with `operator`, a ground-station jump to any block between two calls (the runtime's
//! `nav_goto_block`, which does not consult forbidden deroutes). The interpreter *is* the
//! transition relation, so the model cannot drift from the semantics.
//!
//! Forbidden deroutes are observed by rewriting each `forbidden_deroute` of a copy of the FP
//! with a marker condition (`only_when` absent: a marker answered true without asking;
//! present: the same question as the real plan's), so every transition knows which block
//! changes were refused and its answers replay on the real plan.
//!
//! Properties: [`property`]; algorithms and counterexamples: [`check`].

pub mod check;
pub mod property;
mod report;

pub use report::{CheckError, CheckReport, Spec, run};

use serde::Serialize;

use crate::passes::fp::Fp;
use crate::semantics::StepError;
use crate::semantics::explore::{FORCED_SUFFIX, MARKER_PREFIX};
use crate::semantics::space::{self, Alone, Move, Space, SpaceOptions};
use crate::semantics::trace::Observation;

#[derive(Debug, Clone, Serialize)]
pub struct Edge {
    pub to: usize,
    /// Answers of the call (the first found, breadth first) that take this transition.
    pub answers: Vec<i64>,
    /// Block changes refused by a forbidden deroute during the call (from, to).
    pub blocked: Vec<(usize, usize)>,
    /// An operator jump to this block instead of a call.
    pub operator: Option<usize>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Graph {
    pub block_names: Vec<String>,
    pub states: Vec<Observation>,
    /// Outgoing transitions of every state (state 0 is the initial state).
    pub edges: Vec<Vec<Edge>>,
    /// Every reachable state was expanded (no budget cut the walk).
    pub fixpoint: bool,
    /// Set when the state budget stopped the construction (properties are then checked on a
    /// part of the state space only, and are reported as not established).
    pub cut: Option<String>,
    /// States some of whose transitions were dropped by the budget (their successor lists are
    /// incomplete; checks that need every successor treat them as unknown).
    pub incomplete: Vec<bool>,
    /// The last block is part of the states (properties naming `last_block`).
    pub last_block_kept: bool,
}

/// Copy of the FP with forbidden deroutes observable.
fn marked(fp: &Fp) -> Fp {
    let mut m = fp.clone();
    for (i, f) in m.forbidden.iter_mut().enumerate() {
        f.only_when = Some(match &f.only_when {
            None => format!("{MARKER_PREFIX}{i}{FORCED_SUFFIX}"),
            Some(c) => format!("{MARKER_PREFIX}{i}:when:{c}"),
        });
    }
    m
}

fn marker_index(text: &str) -> Option<usize> {
    let rest = text.strip_prefix(MARKER_PREFIX)?;
    let end = rest.find(':').unwrap_or(rest.len());
    rest[..end].parse().ok()
}

/// How the graph is built.
#[derive(Debug, Clone, Copy)]
pub struct BuildOptions {
    /// State budget.
    pub max_states: usize,
    /// Ground-station jumps to any block between calls.
    pub operator: bool,
    /// Keep the last block in the states (needed by `last_block(..)` atoms).
    pub last_block: bool,
}

/// Builds the reachable state graph, at most `max_states` states; `operator` adds
/// ground-station jumps to any block between calls.
pub fn build(fp: &Fp, max_states: usize, operator: bool) -> Result<Graph, StepError> {
    build_with(fp, BuildOptions { max_states, operator, last_block: false })
}

/// [`build`] with every option.
pub fn build_with(fp: &Fp, o: BuildOptions) -> Result<Graph, StepError> {
    let m = marked(fp);
    let opts = SpaceOptions {
        operator_jumps: o.operator,
        depth: None,
        max_states: o.max_states,
        max_paths_per_call: 100_000,
        keep_last_block: o.last_block,
        record_edges: true,
        drop_dead: true,
        join_paths: false,
    };
    let mut space = Space::new(&m, opts);
    let walk = space::explore(&mut space, &mut Alone)?;
    let mut edges: Vec<Vec<Edge>> = vec![Vec::new(); walk.nodes.len()];
    for e in walk.edges {
        let (answers, operator) = match e.mv {
            Move::Call(a) => (a, None),
            Move::Jump(b) => (Vec::new(), Some(b)),
        };
        let mut blocked: Vec<(usize, usize)> = e
            .markers
            .iter()
            .filter_map(|t| marker_index(t))
            .filter_map(|i| fp.forbidden.get(i).map(|f| (f.from, f.to)))
            .collect();
        blocked.sort();
        blocked.dedup();
        let out = &mut edges[e.from];
        match out
            .iter_mut()
            .find(|x| x.to == e.to && x.blocked == blocked && x.operator == operator)
        {
            Some(x) if x.answers.len() <= answers.len() => {}
            Some(x) => x.answers = answers,
            None => out.push(Edge { to: e.to, answers, blocked, operator }),
        }
    }
    Ok(Graph {
        block_names: fp.blocks.iter().map(|b| b.name.clone()).collect(),
        states: walk.nodes.iter().map(|n| n.obs).collect(),
        edges,
        fixpoint: walk.fixpoint,
        cut: walk.cut,
        incomplete: walk.incomplete,
        last_block_kept: o.last_block || space.abstraction.has_return,
    })
}

impl Graph {
    pub fn describe(&self, s: usize) -> String {
        let o = self.states[s];
        let name = |b: usize| self.block_names.get(b).cloned().unwrap_or_else(|| b.to_string());
        if self.last_block_kept {
            format!("block '{}' stage {} (last: '{}')", name(o.block), o.stage, name(o.last_block))
        } else {
            format!("block '{}' stage {}", name(o.block), o.stage)
        }
    }

    pub fn block_index(&self, name: &str) -> Option<usize> {
        self.block_names.iter().position(|n| n == name)
    }
}
