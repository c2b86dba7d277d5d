//! `vouch fpl graph`: an SVG picture of a plan's block-level control flow.
//!
//! Layout (an "arc diagram", chosen because a flight plan is a sequence): blocks are boxes
//! stacked in file order, so next-block steps are short arrows straight down; deroutes are arcs
//! on the right, returns dotted arcs further right, exceptions dashed arcs on the left; global
//! exceptions come from a box at the top. Forbidden block changes are red with a cross; an
//! arc's width grows with the distance it spans, so nested arcs do not hide each other.
//! Written by hand (a few hundred lines of SVG text) rather than through Graphviz so the picture
//! needs no external program and the layout stays predictable.

mod svg;

use std::collections::BTreeMap;

use crate::ast::{FlightPlan, Stage, StageKind};
use crate::lint::rules::{live_stages, reaches_end};

/// The kind of a block-level edge, which decides its style.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum EdgeKind {
    Next,
    Deroute,
    Exception,
    GlobalException,
    Return,
    /// A forbidden pair that no step of the plan tries.
    ForbiddenOnly,
}

/// How a forbidden declaration affects an edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Forbid {
    No,
    When,
    Always,
}

#[derive(Debug, Clone)]
pub struct GEdge {
    pub kind: EdgeKind,
    /// `None` for global exceptions (from the "any block" box).
    pub from: Option<usize>,
    pub to: usize,
    pub count: usize,
    pub forbid: Forbid,
}

#[derive(Debug, Clone)]
pub struct GNode {
    pub name: String,
    pub stages: usize,
    pub exceptions: usize,
    pub implicit: bool,
}

/// The block graph of a plan (what the picture shows).
#[derive(Debug, Clone)]
pub struct BlockGraph {
    pub title: String,
    pub nodes: Vec<GNode>,
    pub edges: Vec<GEdge>,
}

fn count_stages(stages: &[Stage]) -> usize {
    stages
        .iter()
        .map(|s| match &s.kind {
            StageKind::While(w) => 1 + count_stages(&w.body),
            StageKind::For(f) => 1 + count_stages(&f.body),
            _ => 1,
        })
        .sum()
}

fn forbid_of(plan: &FlightPlan, from: usize, to: usize) -> Forbid {
    let mut f = Forbid::No;
    for d in &plan.forbidden_deroutes {
        if d.from.id.0 == from && d.to.id.0 == to {
            f = f.max(if d.only_when.is_none() { Forbid::Always } else { Forbid::When });
        }
    }
    f
}

/// Extracts the block graph. Return edges go back to every block with a step into the
/// returning block (a static over-approximation of `last_block`).
pub fn block_graph(plan: &FlightPlan) -> BlockGraph {
    let n = plan.blocks.len();
    let mut acc: BTreeMap<(EdgeKind, Option<usize>, usize), usize> = BTreeMap::new();
    let mut add = |k: EdgeKind, f: Option<usize>, t: usize| *acc.entry((k, f, t)).or_insert(0) += 1;
    let mut has_return = vec![false; n];
    for (b, block) in plan.blocks.iter().enumerate() {
        live_stages(&block.stages, &mut |s| match &s.kind {
            StageKind::Deroute(d) => add(EdgeKind::Deroute, Some(b), d.block.id.0),
            StageKind::Return(_) => has_return[b] = true,
            _ => {}
        });
        if reaches_end(&block.stages) && b + 1 < n {
            add(EdgeKind::Next, Some(b), b + 1);
        }
        for e in &block.exceptions {
            if e.deroute.id.0 != b {
                add(EdgeKind::Exception, Some(b), e.deroute.id.0);
            }
        }
    }
    for e in &plan.exceptions {
        add(EdgeKind::GlobalException, None, e.deroute.id.0);
    }
    // Returns: to every block that steps into the returning one.
    let into: Vec<(usize, usize)> = acc
        .keys()
        .filter_map(|(k, f, t)| match (k, f) {
            (EdgeKind::GlobalException, _) => None,
            (_, Some(f)) if f != t => Some((*f, *t)),
            _ => None,
        })
        .collect();
    for (f, t) in into {
        if has_return[t] {
            acc.entry((EdgeKind::Return, Some(t), f)).or_insert(1);
        }
    }
    let mut edges: Vec<GEdge> = acc
        .into_iter()
        .filter(|((_, _, t), _)| *t < n)
        .map(|((kind, from, to), count)| {
            let forbid = match (kind, from) {
                (EdgeKind::Return, _) | (EdgeKind::GlobalException, None) => Forbid::No,
                (_, Some(f)) => forbid_of(plan, f, to),
                _ => Forbid::No,
            };
            GEdge { kind, from, to, count, forbid }
        })
        .collect();
    for d in &plan.forbidden_deroutes {
        let (f, t) = (d.from.id.0, d.to.id.0);
        let drawn =
            edges.iter().any(|e| e.from == Some(f) && e.to == t && e.kind != EdgeKind::Return);
        if !drawn && f < n && t < n && f != t {
            edges.push(GEdge {
                kind: EdgeKind::ForbiddenOnly,
                from: Some(f),
                to: t,
                count: 1,
                forbid: forbid_of(plan, f, t),
            });
        }
    }
    let nodes = plan
        .blocks
        .iter()
        .map(|b| GNode {
            name: b.name.value.clone(),
            stages: count_stages(&b.stages),
            exceptions: b.exceptions.len(),
            implicit: b.implicit,
        })
        .collect();
    BlockGraph { title: plan.name.value.clone(), nodes, edges }
}

/// The SVG text of a plan's block graph.
pub fn render_svg(plan: &FlightPlan) -> String {
    svg::render(&block_graph(plan))
}
