//! `vouch fpl diff`: what a change to a flight plan does to the aircraft's behaviour.
//!
//! Two versions of a plan are **equivalent** when, from every reachable pair of states, under
//! every environment the exploration considers (every condition answer at every evaluation,
//! every `int8_t` value of a non-literal `for` bound, and — by default — a ground-station jump
//! to any block between two calls), they produce the same observations: the same events (the
//! conditions asked with their answers, the C code run — navigation calls and variable writes
//! included — and the values read) and the same block and stage after every call and jump.
//! The walk ([`product`]) explores the product of the two state spaces breadth first to a
//! fixpoint, so the first difference it finds comes with a shortest distinguishing run.
//!
//! What is *not* observed (and why), see [`normal`]: layout and spelling of C texts, waypoint
//! and block *names* (the C sees numbers; a consistent rename keeps them), the `<header>` C
//! text, waypoint coordinates and the plan's numeric settings (data the firmware reads, not
//! behaviour of `auto_nav`; the structural summary reports them, [`structure`]), the last
//! block and stage (observed through `return` stages, which read them) and `last_wp`.
//!
//! Like the validator, this is *tested over an abstraction*, never proved: conditions are free
//! booleans, user C is recorded, not run, and time does not advance.

pub mod normal;
pub mod product;
mod render;
pub mod structure;

use serde::Serialize;

use crate::ast::FlightPlan;
use crate::passes::fp::Fp;
use crate::semantics::space::{Move, SpaceOptions};
use crate::semantics::trace::{Event, Observation};
use crate::semantics::{Interp, StepError};
use crate::span::Span;
use normal::Canon;
use product::{Parting, Side};

pub use render::{render, replay_args, summary, table};

/// The version of the JSON document (`--json`); bumped when its shape changes.
pub const FORMAT: u32 = 1;

/// What the walk covers.
#[derive(Debug, Clone)]
pub struct DiffOptions {
    /// Every ground-station jump to a block is a transition (as in `vouch fpl validate`).
    pub operator_jumps: bool,
    /// Budget of state pairs.
    pub max_states: usize,
    /// Budget of paths of one call.
    pub max_paths_per_call: usize,
}

impl Default for DiffOptions {
    fn default() -> Self {
        DiffOptions { operator_jumps: true, max_states: 1_000_000, max_paths_per_call: 100_000 }
    }
}

/// One version of the plan: the parsed plan, its FP and the name to print.
#[derive(Clone, Copy)]
pub struct Version<'a> {
    pub plan: &'a FlightPlan,
    pub fp: &'a Fp,
}

/// The verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Same observations on the whole reachable product (the walk reached its fixpoint).
    Equivalent,
    /// A distinguishing run was found.
    Different,
    /// A budget cut the walk before either was established.
    Undecided,
}

/// A place in a plan's files.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Location {
    pub file: String,
    pub line: u32,
    pub col: u32,
}

impl Location {
    pub fn of(plan: &FlightPlan, span: Span) -> Location {
        Location { file: plan.sources.path(span.file).to_string(), line: span.line, col: span.col }
    }
}

/// One side of one step of the distinguishing run.
#[derive(Debug, Clone, Serialize)]
pub struct StepSide {
    /// Block (number and name) and stage before the step.
    pub block: usize,
    pub block_name: String,
    pub stage: usize,
    pub events: Vec<Event>,
    pub after: Observation,
}

/// One step of the distinguishing run: a call with its answers, or an operator jump.
#[derive(Debug, Clone, Serialize)]
pub struct RunStep {
    /// The call number (`auto_nav` calls from the start), for calls.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub call: Option<usize>,
    /// The block jumped to, for operator jumps.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump: Option<usize>,
    /// The answers the call consumed (oracle convention: odd = true, a value `v` is `2v`).
    pub answers: Vec<i64>,
    pub old: StepSide,
    pub new: StepSide,
}

/// What differs at the end of the run.
#[derive(Debug, Clone, Serialize)]
pub struct Observed {
    /// The first differing event as printed (`None`: the call had no event there), or the
    /// block and stage reached.
    pub text: Option<String>,
    /// The stage, exception or block that produced it.
    pub location: Option<Location>,
}

/// The first difference and the shortest run that shows it.
#[derive(Debug, Clone, Serialize)]
pub struct Divergence {
    /// The run, its last step the diverging one (empty: `auto_nav_init` differs).
    pub steps: Vec<RunStep>,
    /// `event` (the `event_index`-th event of the last step), `state` (same events, another
    /// block or stage after it) or `init`.
    pub kind: PartingKind,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub event_index: Option<usize>,
    pub old: Observed,
    pub new: Observed,
    /// Replay on either plan with `vouch fpl sim --answers … --jump CALL:BLOCK … --steps N`.
    pub answers: Vec<i64>,
    pub jumps: Vec<(usize, usize)>,
    pub calls: usize,
}

/// How the last step differs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PartingKind {
    Init,
    Event,
    State,
}

/// The JSON document of `vouch fpl diff --json`: one report per pair of plans compared.
#[derive(Debug, Clone, Serialize)]
pub struct Document<'a> {
    /// [`FORMAT`].
    pub format: u32,
    pub diffs: &'a [DiffReport],
}

/// The result of comparing one pair of plans.
#[derive(Debug, Clone, Serialize)]
pub struct DiffReport {
    pub old: String,
    pub new: String,
    pub verdict: Verdict,
    /// The environment included ground-station jumps.
    pub operator_jumps: bool,
    /// Product states explored and transitions compared.
    pub state_pairs: usize,
    pub transitions: usize,
    /// Why the walk stopped short, if a budget did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cut: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub divergence: Option<Divergence>,
    pub structure: structure::Structure,
}

/// Compares two versions of a plan (see the module documentation).
pub fn diff(
    old: Version<'_>,
    new: Version<'_>,
    opts: &DiffOptions,
) -> Result<DiffReport, StepError> {
    let space = SpaceOptions {
        max_states: opts.max_states,
        max_paths_per_call: opts.max_paths_per_call,
        ..SpaceOptions::default()
    };
    let mut a = Side::new(old.fp, Canon::of(old.plan), &space);
    let mut b = Side::new(new.fp, Canon::of(new.plan), &space);
    let structure = structure::compare(old, new, &mut a.canon, &mut b.canon);
    let name = |p: &FlightPlan| p.sources.path(crate::span::FileId(0)).to_string();
    let mut report = DiffReport {
        old: name(old.plan),
        new: name(new.plan),
        verdict: Verdict::Equivalent,
        operator_jumps: opts.operator_jumps,
        state_pairs: 0,
        transitions: 0,
        cut: None,
        divergence: None,
        structure,
    };
    let init_a = a.seen(&Interp::new(old.fp).init_events());
    let init_b = b.seen(&Interp::new(new.fp).init_events());
    if init_a != init_b {
        report.verdict = Verdict::Different;
        report.divergence = Some(init_divergence(old, new, &init_a, &init_b));
        return Ok(report);
    }
    let walk = product::walk(&mut a, &mut b, opts.operator_jumps)?;
    report.state_pairs = walk.nodes.len();
    report.transitions = walk.transitions;
    report.cut = walk.cut.clone();
    report.verdict = match (&walk.found, walk.fixpoint) {
        (Some(_), _) => Verdict::Different,
        (None, true) => Verdict::Equivalent,
        (None, false) => Verdict::Undecided,
    };
    if let Some((node, mv)) = &walk.found {
        let mut moves = walk.path_to(*node);
        moves.push(mv.clone());
        report.divergence = Some(replay(old, new, &moves)?);
    }
    Ok(report)
}

/// `auto_nav_init` differs (ABI bindings): no call is needed.
fn init_divergence(
    old: Version<'_>,
    new: Version<'_>,
    a: &[product::Seen],
    b: &[product::Seen],
) -> Divergence {
    let k = a.iter().zip(b).position(|(x, y)| x != y).unwrap_or(a.len().min(b.len()));
    let observed = |v: Version<'_>| {
        let events = Interp::new(v.fp).init_events();
        let abi = v.plan.variables.iter().filter_map(|d| match d {
            crate::ast::VariableDecl::Abi(a) => Some(a.span),
            crate::ast::VariableDecl::Var(_) => None,
        });
        Observed {
            text: events.get(k).map(Event::line),
            location: abi.clone().nth(k).map(|s| Location::of(v.plan, s)),
        }
    };
    Divergence {
        steps: Vec::new(),
        kind: PartingKind::Init,
        event_index: Some(k),
        old: observed(old),
        new: observed(new),
        answers: Vec::new(),
        jumps: Vec::new(),
        calls: 0,
    }
}

/// Runs `moves` on both plans from the start, recording each step and locating the parting.
fn replay(old: Version<'_>, new: Version<'_>, moves: &[Move]) -> Result<Divergence, StepError> {
    let space = SpaceOptions::default();
    let mut a = Side::new(old.fp, Canon::of(old.plan), &space);
    let mut b = Side::new(new.fp, Canon::of(new.plan), &space);
    a.interp.record_origins();
    b.interp.record_origins();
    let mut d = Divergence {
        steps: Vec::new(),
        kind: PartingKind::State,
        event_index: None,
        old: Observed { text: None, location: None },
        new: Observed { text: None, location: None },
        answers: Vec::new(),
        jumps: Vec::new(),
        calls: 0,
    };
    for (i, mv) in moves.iter().enumerate() {
        let (s1, s2) = (a.interp.state.clone(), b.interp.state.clone());
        let before = |side: &Side<'_>| {
            let o = side.interp.observe();
            let name = side.interp.fp().blocks.get(o.block).map_or("?", |x| x.name.as_str());
            (o, name.to_string())
        };
        let ((o1, n1), (o2, n2)) = (before(&a), before(&b));
        let (e1, x1, e2, x2, step_answers) = match mv {
            Move::Call(answers) => {
                d.calls += 1;
                d.answers.extend(answers);
                let (e1, x1, _) = a.call(&s1, answers)?;
                let (e2, x2, _) = b.call(&s2, answers)?;
                (e1, x1, e2, x2, answers.clone())
            }
            Move::Jump(block) => {
                d.jumps.push((d.calls + 1, *block));
                let (e1, x1) = a.jump(&s1, *block);
                let (e2, x2) = b.jump(&s2, *block);
                (e1, x1, e2, x2, Vec::new())
            }
        };
        let side = |o: Observation, name: String, events: Vec<Event>, after| StepSide {
            block: o.block,
            block_name: name,
            stage: o.stage,
            events,
            after,
        };
        if i + 1 == moves.len() {
            locate(&mut d, (old, &mut a, &e1, x1), (new, &mut b, &e2, x2), mv);
            if matches!(mv, Move::Jump(_)) {
                d.calls += 1;
            }
        }
        d.steps.push(RunStep {
            call: matches!(mv, Move::Call(_)).then_some(d.calls),
            jump: match mv {
                Move::Jump(b) => Some(*b),
                Move::Call(_) => None,
            },
            answers: step_answers,
            old: side(o1, n1, e1, x1),
            new: side(o2, n2, e2, x2),
        });
    }
    Ok(d)
}

/// Fills in where and how the last step parts, on both files.
fn locate(
    d: &mut Divergence,
    (old, a, e1, x1): (Version<'_>, &mut Side<'_>, &[Event], Observation),
    (new, b, e2, x2): (Version<'_>, &mut Side<'_>, &[Event], Observation),
    mv: &Move,
) {
    let parting = product::parting(&a.seen(e1), &b.seen(e2), x1, x2);
    let at = |v: Version<'_>,
              side: &Side<'_>,
              events: &[Event],
              after: Observation,
              k: Option<usize>| {
        let span = match mv {
            Move::Jump(_) => v.fp.blocks.get(after.block).map(|b| b.span),
            Move::Call(_) => {
                let origins = side.interp.origins();
                let idx = k.unwrap_or(usize::MAX);
                origins
                    .iter()
                    .rev()
                    .find(|o| o.first_event <= idx)
                    .or(origins.last())
                    .map(|o| o.span)
            }
        };
        let text = match k {
            Some(k) => events.get(k).map(Event::line),
            None => Some(format!("block {} stage {}", after.block, after.stage)),
        };
        Observed { text, location: span.map(|s| Location::of(v.plan, s)) }
    };
    let k = match parting {
        Some(Parting::Event(k)) => Some(k),
        _ => None,
    };
    d.kind = if k.is_some() { PartingKind::Event } else { PartingKind::State };
    d.event_index = k;
    d.old = at(old, a, e1, x1, k);
    d.new = at(new, b, e2, x2, k);
}
