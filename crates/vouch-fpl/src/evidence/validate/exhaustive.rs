//! The exhaustive part of the validation: breadth first over calls, every distinct interpreter
//! state expanded once, the C driver's paths of the next call compared with the interpreter's.

use std::collections::{HashMap, HashSet, VecDeque};

use super::{keep_shortest, state_line, Counterexample, Options, Report, ValidateError};
use crate::evidence::cdriver::{CPath, Driver, Explored};
use crate::semantics::explore::{enumerate_call, state_key, CallPath, StateKey};
use crate::semantics::{Interp, State};

/// A state to expand: reached after `depth` calls with the answers `prefix`.
struct Node<'p> {
    depth: usize,
    prefix: Vec<i64>,
    state: State<'p>,
}

impl Node<'_> {
    /// The answers from the start: the node's prefix, then those of one more call.
    fn full(&self, answers: &[i64]) -> Vec<i64> {
        self.prefix.iter().chain(answers).copied().collect()
    }
}

/// The walk's memory: states seen, the merged graph (for counting runs), the queue, and the
/// shortest counterexample of the current level.
struct Walk<'p> {
    seen: HashSet<StateKey>,
    children: HashMap<StateKey, Vec<StateKey>>,
    queue: VecDeque<Node<'p>>,
    found: Option<Counterexample>,
}

const NOT_ENDING: &str = "the C call asks more questions than the static bound: it does not end";

/// Runs the exhaustive part, filling `report` (states, paths, cut, counterexample, runs).
pub(super) fn exhaustive(
    driver: &mut Driver,
    interp: &mut Interp<'_>,
    opts: &Options,
    report: &mut Report,
) -> Result<(), ValidateError> {
    let init_state = interp.state.clone();
    let init_key = state_key(interp, &init_state);
    let mut walk = Walk {
        seen: HashSet::from([init_key.clone()]),
        children: HashMap::new(),
        queue: VecDeque::from([Node { depth: 0, prefix: Vec::new(), state: init_state }]),
        found: None,
    };
    let mut level = 0;
    while let Some(node) = walk.queue.pop_front() {
        if node.depth != level {
            if walk.found.is_some() {
                break;
            }
            level = node.depth;
        }
        if report.call_paths >= opts.max_paths {
            report.cut =
                Some(format!("path budget {} reached at call {}", opts.max_paths, node.depth + 1));
            break;
        }
        report.states += 1;
        let ex = driver.explore(node.depth, &node.prefix)?;
        if node.depth == 0 {
            if let Some(cx) = init_mismatch(interp, &ex) {
                report.counterexample = Some(cx);
                return Ok(());
            }
        }
        interp.state = node.state.clone();
        let o = interp.observe();
        let here = [o.block, o.stage, o.last_block, o.last_stage];
        if ex.replayed != Some(here) {
            let cx = Counterexample {
                calls: node.depth,
                answers: node.prefix.clone(),
                what: "state after replaying the prefix differs".into(),
                expected: vec![state_line(here)],
                actual: ex.replayed.map(|s| vec![state_line(s)]).unwrap_or_default(),
            };
            keep_shortest(&mut walk.found, cx);
            continue;
        }
        expand(&mut walk, interp, opts, report, &node, &ex, o.block)?;
    }
    report.counterexample = walk.found.take();
    if report.cut.is_none() {
        let mut memo = HashMap::new();
        report.runs_covered = runs(&init_key, opts.depth, &walk.children, &mut memo);
    }
    Ok(())
}

/// The events of `auto_nav_init()` differ.
fn init_mismatch(interp: &Interp<'_>, ex: &Explored) -> Option<Counterexample> {
    let want: Vec<String> = interp.init_events().iter().map(|e| e.line()).collect();
    (ex.init.as_ref() != Some(&want)).then(|| Counterexample {
        calls: 0,
        answers: Vec::new(),
        what: "auto_nav_init() differs".into(),
        expected: want,
        actual: ex.init.clone().unwrap_or_default(),
    })
}

/// Compares every path of the call from `node` on both sides and queues the new states.
fn expand<'p>(
    walk: &mut Walk<'p>,
    interp: &mut Interp<'p>,
    opts: &Options,
    report: &mut Report,
    node: &Node<'p>,
    ex: &Explored,
    block: usize,
) -> Result<(), ValidateError> {
    let tree = enumerate_call(interp, &node.state, opts.max_paths_per_call)?;
    if tree.cut || ex.cut {
        report.cut = Some(format!(
            "more than {} paths in one call at call {}",
            opts.max_paths_per_call,
            node.depth + 1
        ));
    }
    let limit = report.bound.blocks.get(block).map(|b| b.events).unwrap_or(0);
    let mut c_paths: Vec<&CPath> = ex.paths.iter().collect();
    let node_key = state_key(interp, &node.state);
    let mut kids = Vec::with_capacity(tree.paths.len());
    for p in &tree.paths {
        report.call_paths += 1;
        report.max_events_seen = report.max_events_seen.max(p.events.len());
        if let Some(cx) = compare(node, p, &mut c_paths, limit) {
            keep_shortest(&mut walk.found, cx);
        }
        let k = state_key(interp, &p.state);
        kids.push(k.clone());
        if node.depth + 1 < opts.depth && walk.seen.insert(k) {
            walk.queue.push_back(Node {
                depth: node.depth + 1,
                prefix: node.full(&p.answers),
                state: p.state.clone(),
            });
        }
    }
    walk.children.insert(node_key, kids);
    // Whatever the C did that the semantics did not (only meaningful on complete trees).
    if !tree.cut && !ex.cut {
        for c in c_paths {
            keep_shortest(&mut walk.found, c_only(node, c));
        }
    }
    Ok(())
}

/// Compares one interpreter path with the C path of the same answers (removed from `c_paths`).
fn compare(
    node: &Node<'_>,
    p: &CallPath<'_>,
    c_paths: &mut Vec<&CPath>,
    limit: usize,
) -> Option<Counterexample> {
    let want: Vec<String> = p.events.iter().map(|e| e.line()).collect();
    let want_after = [p.after.block, p.after.stage, p.after.last_block, p.after.last_stage];
    let mut expected = want.clone();
    expected.push(state_line(want_after));
    let cx = |what: String, actual: Vec<String>| Counterexample {
        calls: node.depth + 1,
        answers: node.full(&p.answers),
        what,
        expected: expected.clone(),
        actual,
    };
    let pos = c_paths.iter().position(|c| c.answers() == p.answers.as_slice());
    match pos.map(|i| c_paths.remove(i)) {
        None => Some(cx("the semantics allows this path, the C does not take it".into(), vec![])),
        Some(CPath::Done { events, after, .. }) => {
            if *events != want || *after != want_after {
                let mut actual = events.clone();
                actual.push(state_line(*after));
                Some(cx("different events or state".into(), actual))
            } else if events.len() > limit || p.events.len() > limit {
                let what = format!("call exceeds the static bound of {limit} events");
                Some(cx(what, events.clone()))
            } else {
                None
            }
        }
        Some(CPath::TooLong { .. }) => Some(cx(NOT_ENDING.into(), vec![])),
        Some(CPath::Crashed { status, .. }) => {
            Some(cx(format!("the C process died (status {status})"), vec![]))
        }
    }
}

/// A path the C took that the semantics does not have.
fn c_only(node: &Node<'_>, c: &CPath) -> Counterexample {
    let (actual, what) = match c {
        CPath::Done { events, after, .. } => {
            let mut a = events.clone();
            a.push(state_line(*after));
            (a, "the C takes a path the semantics does not allow")
        }
        CPath::TooLong { .. } => (vec![], NOT_ENDING),
        CPath::Crashed { .. } => (vec![], "the C process died"),
    };
    Counterexample {
        calls: node.depth + 1,
        answers: node.full(c.answers()),
        what: what.into(),
        expected: vec![],
        actual,
    }
}

/// Number of complete answer sequences of `r` calls from a state (1 when `r` is 0).
fn runs(
    k: &StateKey,
    r: usize,
    children: &HashMap<StateKey, Vec<StateKey>>,
    memo: &mut HashMap<(StateKey, usize), f64>,
) -> f64 {
    if r == 0 {
        return 1.0;
    }
    if let Some(v) = memo.get(&(k.clone(), r)) {
        return *v;
    }
    let v = children
        .get(k)
        .map_or(1.0, |kids| kids.iter().map(|c| runs(c, r - 1, children, memo)).sum());
    memo.insert((k.clone(), r), v);
    v
}
