//! Explicit-state model checking of a plan (`vouch fpl check`).
//!
//! The abstract state is the interpreter's: (block, stage, last block, last stage), plus the
//! `for` counters, with every condition *free* (both answers explored at every question; `for`
//! bounds from [`crate::semantics::explore::VALUE_CHOICES`]). One transition is one `auto_nav`
//! call. The graph is built with the same call enumeration the validator uses, on the reference
//! semantics itself, so the model cannot drift from the interpreter.
//!
//! Forbidden deroutes are observed by rewriting each `forbidden_deroute` of a copy of the FP
//! with a marker condition (`only_when` absent: a marker answered true without branching;
//! present: a free marker), so every transition knows which block changes were refused.
//!
//! Properties: [`property`]; algorithms and counterexamples: [`check`].

pub mod check;
pub mod property;
mod report;

pub use report::{run, CheckError, CheckReport, Spec};

use std::collections::HashMap;

use serde::Serialize;

use crate::passes::fp::Fp;
use crate::semantics::explore::{
    enumerate_call, state_key, CallPath, StateKey, FORCED_SUFFIX, MARKER_PREFIX,
};
use crate::semantics::trace::Observation;
use crate::semantics::{Interp, StepError};

#[derive(Debug, Clone, Serialize)]
pub struct Edge {
    pub to: usize,
    /// Answers of the call (shortest found) that take this transition.
    pub answers: Vec<i64>,
    /// Block changes refused by a forbidden deroute during the call (from, to).
    pub blocked: Vec<(usize, usize)>,
    /// With operator jumps modelled: the block the operator jumped to instead of the call.
    pub operator: Option<usize>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Graph {
    pub block_names: Vec<String>,
    pub states: Vec<Observation>,
    /// Outgoing transitions of every state (state 0 is the initial state).
    pub edges: Vec<Vec<Edge>>,
    /// Set when the state budget stopped the construction (properties are then checked on a
    /// part of the state space only, and are reported as not established).
    pub cut: Option<String>,
    /// States some of whose transitions were dropped by the budget (their successor lists are
    /// incomplete; checks that need every successor treat them as unknown).
    pub incomplete: Vec<bool>,
}

const OPERATOR: &str = "op:";

/// Copy of the FP with forbidden deroutes observable and, when `operator` is set, one free
/// global exception per block standing for a ground-station jump to it (tested first, so at
/// any call the operator may jump anywhere; such a jump obeys forbidden deroutes like any
/// block change, and a refused jump is dropped from the graph).
fn marked(fp: &Fp, operator: bool) -> Fp {
    let mut m = fp.clone();
    if operator {
        let jumps = (0..fp.blocks.len()).map(|t| crate::passes::fp::FpException {
            cond: format!("{MARKER_PREFIX}{OPERATOR}{t}"),
            target: t,
            exec: None,
            span: crate::span::Span::default(),
        });
        let mut ex: Vec<_> = jumps.collect();
        ex.extend(m.exceptions);
        m.exceptions = ex;
    }
    for (i, f) in m.forbidden.iter_mut().enumerate() {
        f.only_when = Some(match &f.only_when {
            None => format!("{MARKER_PREFIX}{i}{FORCED_SUFFIX}"),
            Some(c) => format!("{MARKER_PREFIX}{i}:when:{c}"),
        });
    }
    m
}

fn operator_target(text: &str) -> Option<usize> {
    text.strip_prefix(MARKER_PREFIX)?.strip_prefix(OPERATOR)?.parse().ok()
}

fn marker_index(text: &str) -> Option<usize> {
    let rest = text.strip_prefix(MARKER_PREFIX)?;
    if rest.starts_with(OPERATOR) {
        return None;
    }
    let end = rest.find(':').unwrap_or(rest.len());
    rest[..end].parse().ok()
}

/// Builds the reachable state graph, at most `max_states` states; `operator` adds
/// ground-station jumps to any block at any call.
pub fn build(fp: &Fp, max_states: usize, operator: bool) -> Result<Graph, StepError> {
    let m = marked(fp, operator);
    let mut interp = Interp::new(&m);
    let init = interp.state.clone();
    let mut index: HashMap<StateKey, usize> = HashMap::new();
    index.insert(state_key(&interp, &init), 0);
    let mut states = vec![init];
    let mut graph = Graph {
        block_names: fp.blocks.iter().map(|b| b.name.clone()).collect(),
        states: Vec::new(),
        edges: Vec::new(),
        cut: None,
        incomplete: Vec::new(),
    };
    let mut next = 0;
    while next < states.len() {
        let from = states[next].clone();
        interp.state = from.clone();
        graph.states.push(interp.observe());
        let tree = enumerate_call(&mut interp, &from, 100_000)?;
        let mut incomplete = tree.cut;
        if tree.cut {
            graph.cut = Some("more than 100000 paths in one call".into());
        }
        let mut out: Vec<Edge> = Vec::new();
        for p in tree.paths {
            let op = p.markers.iter().find_map(|t| operator_target(t));
            let refused = p.markers.iter().any(|t| marker_index(t).is_some());
            if op.is_some() && refused {
                continue;
            }
            let k = state_key(&interp, &p.state);
            let to = match index.get(&k) {
                Some(&i) => i,
                None => {
                    if states.len() >= max_states {
                        graph.cut = Some(format!("more than {max_states} states"));
                        incomplete = true;
                        continue;
                    }
                    index.insert(k, states.len());
                    states.push(p.state.clone());
                    states.len() - 1
                }
            };
            let mut blocked: Vec<(usize, usize)> = p
                .markers
                .iter()
                .filter_map(|t| marker_index(t))
                .filter_map(|i| fp.forbidden.get(i).map(|f| (f.from, f.to)))
                .collect();
            blocked.sort();
            blocked.dedup();
            // Answers without the forced marker answers, so they replay on the real plan.
            let answers = strip_forced(&p.answers, &p.events_markers_forced());
            match out.iter_mut().find(|e| e.to == to && e.blocked == blocked && e.operator == op) {
                Some(e) if e.answers.len() <= answers.len() => {}
                Some(e) => e.answers = answers,
                None => out.push(Edge { to, answers, blocked, operator: op }),
            }
        }
        graph.edges.push(out);
        graph.incomplete.push(incomplete);
        next += 1;
    }
    Ok(graph)
}

fn strip_forced(answers: &[i64], forced: &[usize]) -> Vec<i64> {
    answers.iter().enumerate().filter(|(i, _)| !forced.contains(i)).map(|(_, a)| *a).collect()
}

trait ForcedPositions {
    fn events_markers_forced(&self) -> Vec<usize>;
}

impl ForcedPositions for CallPath<'_> {
    /// Positions in `answers` of the questions the real plan does not ask (forced forbidden
    /// markers, operator jumps): the questions are the condition and non-literal value events,
    /// in order.
    fn events_markers_forced(&self) -> Vec<usize> {
        use crate::semantics::oracle::literal_value;
        use crate::semantics::trace::Event;
        let mut pos = 0;
        let mut forced = Vec::new();
        for e in &self.events {
            match e {
                Event::Cond { text, .. } => {
                    let hidden = text.starts_with(MARKER_PREFIX)
                        && (text.ends_with(FORCED_SUFFIX) || operator_target(text).is_some());
                    if hidden {
                        forced.push(pos);
                    }
                    pos += 1;
                }
                Event::Value { text, .. } if literal_value(text).is_none() => pos += 1,
                _ => {}
            }
        }
        forced
    }
}

impl Graph {
    pub fn describe(&self, s: usize) -> String {
        let o = self.states[s];
        let name = |b: usize| self.block_names.get(b).cloned().unwrap_or_else(|| b.to_string());
        format!(
            "block '{}' stage {} (last: '{}' stage {})",
            name(o.block),
            o.stage,
            name(o.last_block),
            o.last_stage
        )
    }

    pub fn block_index(&self, name: &str) -> Option<usize> {
        self.block_names.iter().position(|n| n == name)
    }
}
