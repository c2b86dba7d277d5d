//! Translation validation of one plan: the compiled C (`auto_nav` of the generated header, run
//! by the stub runtime) against the reference interpreter.
//!
//! * **Exhaustive part.** Breadth first over calls: for every distinct interpreter state reached
//!   after `d < depth` calls, the C driver replays the answer prefix that reached it and forks
//!   at every question of call `d + 1`; the interpreter enumerates the same call
//!   ([`crate::semantics::explore::enumerate_call`]). Both path sets must be equal (answers consumed,
//!   events, and the state after the call), which checks both directions: nothing the C does
//!   that the semantics does not, and the reverse. States are merged by
//!   [`crate::semantics::explore::StateKey`], so equal subtrees are explored once; this assumes the C has
//!   no hidden state beyond what the interpreter tracks (the random runs below do not merge).
//! * **Random part.** Long seeded runs compared trace against trace.
//! * **Bound.** Every compared call must stay within the static bound of [`super::wcet`].
//!
//! Breadth-first order makes the first counterexample one with the fewest calls; among those the
//! one with the fewest answers is reported.

use std::collections::{HashMap, HashSet, VecDeque};

use serde::Serialize;

use super::cdriver::{CPath, Driver};
use super::wcet::{self, PlanBound};
use crate::ast::FlightPlan;
use crate::emit::{compile_plan, EmitOptions, Flavor};
use crate::passes::fp::Fp;
use crate::semantics::explore::{enumerate_call, state_key, StateKey};
use crate::semantics::oracle::{seeded_sequence, Scripted};
use crate::semantics::{Interp, State};

#[derive(Debug, Clone)]
pub struct Options {
    /// Calls explored exhaustively.
    pub depth: usize,
    /// Seeded random runs and their length.
    pub random_runs: usize,
    pub random_steps: usize,
    /// Work budget: call paths compared in the exhaustive part.
    pub max_paths: usize,
    /// Paths of one call (per starting state).
    pub max_paths_per_call: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            depth: 8,
            random_runs: 3,
            random_steps: 500,
            max_paths: 500_000,
            max_paths_per_call: 20_000,
        }
    }
}

/// A disagreement, with everything needed to replay it (`vouch fpl sim --conditions`).
#[derive(Debug, Clone, Serialize)]
pub struct Counterexample {
    /// Number of `auto_nav` calls (the last one shows the disagreement).
    pub calls: usize,
    /// Answer numbers from the start (oracle convention: condition = odd, value = n / 2).
    pub answers: Vec<i64>,
    pub what: String,
    /// Events and state of the last call according to the semantics / the compiled C.
    pub expected: Vec<String>,
    pub actual: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub depth: usize,
    /// Distinct interpreter states expanded (each with one C request).
    pub states: usize,
    /// Call paths compared in the exhaustive part.
    pub call_paths: usize,
    /// Complete `depth`-call runs (answer sequences) the exhaustive part covers: the size of
    /// the unmerged tree, counted on the merged graph.
    pub runs_covered: f64,
    /// Calls compared in the random runs.
    pub random_calls: usize,
    /// The work budget stopped the exhaustive part before `depth`.
    pub cut: Option<String>,
    pub bound: PlanBound,
    /// Largest number of events seen in one call.
    pub max_events_seen: usize,
    pub counterexample: Option<Counterexample>,
}

impl Report {
    pub fn passed(&self) -> bool {
        self.counterexample.is_none()
    }
}

struct Node<'p> {
    depth: usize,
    prefix: Vec<i64>,
    state: State<'p>,
}

fn state_lines(o: [usize; 4]) -> String {
    format!("S {} {} {} {}", o[0], o[1], o[2], o[3])
}

/// Validates `plan`: builds the instrumented header, compiles the driver, explores.
pub fn validate(plan: &FlightPlan, opts: &Options) -> Result<Report, String> {
    let fp = crate::passes::lower::lower(plan).map_err(|e| e.to_string())?;
    let eo = EmitOptions { flavor: Flavor::Instrumented, ..EmitOptions::default() };
    let header = compile_plan(plan, &eo).map_err(|e| e.to_string())?;
    validate_header(&fp, &header, opts)
}

/// Validates a given instrumented header against the semantics of `fp` (mutation tests feed a
/// deliberately broken header here).
pub fn validate_header(fp: &Fp, header: &str, opts: &Options) -> Result<Report, String> {
    let bound = wcet::bound(fp);
    // A correct call asks at most as many questions as it has events.
    let mut driver = Driver::build(header, opts.max_paths_per_call, bound.max_events + 1)?;
    let mut interp = Interp::new(fp);
    let mut report = Report {
        depth: opts.depth,
        states: 0,
        call_paths: 0,
        runs_covered: 0.0,
        random_calls: 0,
        cut: None,
        bound,
        max_events_seen: 0,
        counterexample: None,
    };
    exhaustive(&mut driver, &mut interp, opts, &mut report)?;
    if report.counterexample.is_none() {
        random_runs(&mut driver, fp, opts, &mut report)?;
    }
    Ok(report)
}

fn exhaustive<'p>(
    driver: &mut Driver,
    interp: &mut Interp<'p>,
    opts: &Options,
    report: &mut Report,
) -> Result<(), String> {
    let init_state = interp.state.clone();
    let init_key = state_key(interp, &init_state);
    let mut seen = HashSet::new();
    seen.insert(init_key.clone());
    let mut children: HashMap<StateKey, Vec<StateKey>> = HashMap::new();
    let mut queue = VecDeque::from([Node { depth: 0, prefix: Vec::new(), state: init_state }]);
    let mut level_found: Option<Counterexample> = None;
    let mut level = 0;
    while let Some(node) = queue.pop_front() {
        if node.depth != level {
            if level_found.is_some() {
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
            let want: Vec<String> = interp.init_events().iter().map(|e| e.line()).collect();
            if ex.init.as_ref() != Some(&want) {
                report.counterexample = Some(Counterexample {
                    calls: 0,
                    answers: Vec::new(),
                    what: "auto_nav_init() differs".into(),
                    expected: want,
                    actual: ex.init.unwrap_or_default(),
                });
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
                expected: vec![state_lines(here)],
                actual: ex.replayed.map(|s| vec![state_lines(s)]).unwrap_or_default(),
            };
            keep_shortest(&mut level_found, cx);
            continue;
        }
        let tree = enumerate_call(interp, &node.state, opts.max_paths_per_call)
            .map_err(|e| format!("interpreter: {e:?}"))?;
        if tree.cut || ex.cut {
            report.cut = Some(format!(
                "more than {} paths in one call at call {}",
                opts.max_paths_per_call,
                node.depth + 1
            ));
        }
        let limit = report.bound.blocks.get(o.block).map(|b| b.events).unwrap_or(0);
        let mut c_paths: Vec<&CPath> = ex.paths.iter().collect();
        let node_key = state_key(interp, &node.state);
        let kids: Vec<StateKey> = tree.paths.iter().map(|p| state_key(interp, &p.state)).collect();
        let full =
            |a: &[i64]| -> Vec<i64> { node.prefix.iter().chain(a.iter()).copied().collect() };
        for p in &tree.paths {
            report.call_paths += 1;
            let want: Vec<String> = p.events.iter().map(|e| e.line()).collect();
            let want_after = [p.after.block, p.after.stage, p.after.last_block, p.after.last_stage];
            report.max_events_seen = report.max_events_seen.max(p.events.len());
            let mut expected = want.clone();
            expected.push(state_lines(want_after));
            let pos = c_paths.iter().position(|c| match c {
                CPath::Done { answers, .. }
                | CPath::TooLong { answers }
                | CPath::Crashed { answers, .. } => *answers == p.answers,
            });
            let cx = |what: String, actual: Vec<String>| Counterexample {
                calls: node.depth + 1,
                answers: full(&p.answers),
                what,
                expected: expected.clone(),
                actual,
            };
            match pos.map(|i| c_paths.remove(i)) {
                None => keep_shortest(
                    &mut level_found,
                    cx("the semantics allows this path, the C does not take it".into(), vec![]),
                ),
                Some(CPath::Done { events, after, .. }) => {
                    if *events != want || *after != want_after {
                        let mut actual = events.clone();
                        actual.push(state_lines(*after));
                        keep_shortest(
                            &mut level_found,
                            cx("different events or state".into(), actual),
                        );
                    }
                    if events.len() > limit || p.events.len() > limit {
                        keep_shortest(
                            &mut level_found,
                            cx(
                                format!("call exceeds the static bound of {limit} events"),
                                events.clone(),
                            ),
                        );
                    }
                }
                Some(CPath::TooLong { .. }) => keep_shortest(
                    &mut level_found,
                    cx(
                        "the C call asks more questions than the static bound: it does not end"
                            .into(),
                        vec![],
                    ),
                ),
                Some(CPath::Crashed { status, .. }) => keep_shortest(
                    &mut level_found,
                    cx(format!("the C process died (status {status})"), vec![]),
                ),
            }
            if node.depth + 1 < opts.depth {
                let k = state_key(interp, &p.state);
                if seen.insert(k) {
                    queue.push_back(Node {
                        depth: node.depth + 1,
                        prefix: full(&p.answers),
                        state: p.state.clone(),
                    });
                }
            }
        }
        children.insert(node_key, kids);
        // Whatever the C did that the semantics did not: shortest such path.
        if !tree.cut && !ex.cut {
            for c in c_paths {
                let (answers, actual, what) = match c {
                    CPath::Done { answers, events, after } => {
                        let mut a = events.clone();
                        a.push(state_lines(*after));
                        (answers, a, "the C takes a path the semantics does not allow")
                    }
                    CPath::TooLong { answers } => (
                        answers,
                        vec![],
                        "the C call asks more questions than the static bound: it does not end",
                    ),
                    CPath::Crashed { answers, .. } => (answers, vec![], "the C process died"),
                };
                keep_shortest(
                    &mut level_found,
                    Counterexample {
                        calls: node.depth + 1,
                        answers: full(answers),
                        what: what.into(),
                        expected: vec![],
                        actual,
                    },
                );
            }
        }
    }
    report.counterexample = level_found;
    if report.cut.is_none() {
        let mut memo = HashMap::new();
        report.runs_covered = runs(&init_key, opts.depth, &children, &mut memo);
    }
    Ok(())
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

fn keep_shortest(slot: &mut Option<Counterexample>, cx: Counterexample) {
    let better = match slot {
        None => true,
        Some(old) => (cx.calls, cx.answers.len()) < (old.calls, old.answers.len()),
    };
    if better {
        *slot = Some(cx);
    }
}

fn random_runs(
    driver: &mut Driver,
    fp: &Fp,
    opts: &Options,
    report: &mut Report,
) -> Result<(), String> {
    for run in 0..opts.random_runs {
        let percent = [50, 20, 80][run % 3];
        let seed = 0x5EED_0000 + run as u64;
        let numbers = seeded_sequence(seed, opts.random_steps * 64, percent);
        let (c_text, ok) = driver.walk(opts.random_steps, &numbers)?;
        let mut interp = Interp::new(fp);
        let mut oracle = Scripted::new(numbers.clone());
        let r = interp
            .run(&mut oracle, opts.random_steps)
            .map_err(|e| format!("interpreter: {e:?}"))?;
        let want = r.to_text();
        report.random_calls += opts.random_steps;
        for s in &r.steps {
            report.max_events_seen = report.max_events_seen.max(s.events.len());
            let limit = report.bound.blocks.get(s.before.block).map(|b| b.events).unwrap_or(0);
            if s.events.len() > limit {
                report.counterexample = Some(Counterexample {
                    calls: s.call,
                    answers: numbers[..oracle.consumed().min(numbers.len())].to_vec(),
                    what: format!(
                        "random run {run}: call exceeds the static bound of {limit} events"
                    ),
                    expected: vec![],
                    actual: s.events.iter().map(|e| e.line()).collect(),
                });
                return Ok(());
            }
        }
        if want != c_text || !ok {
            let (wl, cl): (Vec<&str>, Vec<&str>) =
                (want.lines().collect(), c_text.lines().collect());
            let i = wl
                .iter()
                .zip(cl.iter())
                .position(|(a, b)| a != b)
                .unwrap_or(wl.len().min(cl.len()));
            let step = wl[..i.min(wl.len())].iter().filter(|l| l.starts_with("step ")).count();
            report.counterexample = Some(Counterexample {
                calls: step,
                answers: Vec::new(),
                what: format!(
                    "random run {run} (seed {seed:#x}, {percent}% true) differs at trace line {}",
                    i + 1
                ),
                expected: wl.iter().skip(i).take(5).map(|s| s.to_string()).collect(),
                actual: cl.iter().skip(i).take(5).map(|s| s.to_string()).collect(),
            });
            return Ok(());
        }
    }
    Ok(())
}
