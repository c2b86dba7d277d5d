//! Translation validation of one plan: the compiled C (`auto_nav` of the generated header, run
//! by the stub runtime) against the reference interpreter, over the plan's whole reachable
//! state space.
//!
//! * **The walk.** [`crate::semantics::space::explore`] walks the reachable states breadth
//!   first to a fixpoint: every path of every call (every condition answer, every `int8_t`
//!   value of a non-literal `for` bound) and every operator jump. Beside each interpreter
//!   state runs the C state the same moves produced (module `companion`): the driver restores it,
//!   runs every path and jump, and both sides must agree on every one (answers consumed,
//!   events, block, stage, last block and stage, `last_wp`, every `for` counter, the static
//!   bound), in both directions.
//! * **The state relation.** The explored state is the pair (interpreter view, C view); the
//!   C view holds every registered static variable ([`crate::evidence::cstate`]), minus what the
//!   interpreter's view drops. The walk checks that the relation is a function: one
//!   interpreter state never meets two C states.
//! * **The dropped parts.** Every run is repeated from a copy of the C state whose dropped
//!   parts are changed (module `cview`): the C must not read them either.
//! * **Random runs.** Long seeded runs from a fresh process, compared trace against trace,
//!   without restoring or merging anything.
//!
//! Breadth-first order makes the first disagreement one with the fewest transitions; among
//! those the one with the fewest answers is reported.

mod companion;
mod cview;
mod report;

use std::time::Instant;

pub use report::{Abstracted, ConstantReading, Counterexample, Report, RunPath};

pub use super::cdriver::Target;
use super::cdriver::{Driver, DriverError, Limits};
use super::wcet;
use crate::ast::FlightPlan;
use crate::emit::{EmitOptions, Flavor, compile_plan};
use crate::passes::CompileError;
use crate::passes::fp::Fp;
use crate::semantics::explore::VALUE_RANGE;
use crate::semantics::oracle::{Scripted, seeded_sequence};
use crate::semantics::space::{self, Space, SpaceOptions};
use crate::semantics::{Interp, StepError};
use companion::{CSide, Finding};

#[derive(Debug, Clone)]
pub struct Options {
    /// A bound on the transitions from the initial state; `None` walks to the fixpoint.
    pub depth: Option<usize>,
    /// Operator jumps to every block are transitions of every state.
    pub operator_jumps: bool,
    /// Merge states that differ only in parts the plan cannot read, and repeat every run from a
    /// copy of the C state with those parts changed (`false`: exact states, nothing merged
    /// that differs).
    pub perturb: bool,
    /// Seeded random runs and their length.
    pub random_runs: usize,
    pub random_steps: usize,
    /// State budget (pairs).
    pub max_states: usize,
    /// Runs of one call (each path, or with joins each run to the end of the call or to a
    /// join point).
    pub max_paths_per_call: usize,
    /// Where the compiled C runs.
    pub target: Target,
    /// Code-generation flags replacing the target's defaults.
    pub cflags: Option<Vec<String>>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            depth: None,
            operator_jumps: true,
            perturb: true,
            random_runs: 3,
            random_steps: 500,
            max_states: 200_000,
            max_paths_per_call: 1_000_000,
            target: Target::Host,
            cflags: None,
        }
    }
}

/// `S <block> <stage> <last_block> <last_stage>`, the trace's state line.
fn state_line(o: [usize; 4]) -> String {
    format!("S {} {} {} {}", o[0], o[1], o[2], o[3])
}

/// Why a validation could not run (a disagreement is not an error: it is in the [`Report`]).
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum ValidateError {
    /// The plan does not compile.
    #[error("the plan does not compile: {0}")]
    #[diagnostic(code(fpl::E023))]
    Plan(#[from] CompileError),
    /// The C side could not be built or driven.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Driver(#[from] DriverError),
    /// The interpreter stopped.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Interpreter(#[from] StepError),
}

/// Validates `plan`: builds the instrumented header, compiles the driver, explores.
pub fn validate(plan: &FlightPlan, opts: &Options) -> Result<Report, ValidateError> {
    let fp = crate::passes::lower::lower(plan)?;
    let eo = EmitOptions { flavor: Flavor::Instrumented, ..EmitOptions::default() };
    let header = compile_plan(plan, &eo)?;
    validate_header(&fp, &header, opts)
}

/// Validates a given instrumented header against the semantics of `fp` (mutation tests feed a
/// deliberately broken header here).
pub fn validate_header(fp: &Fp, header: &str, opts: &Options) -> Result<Report, ValidateError> {
    let started = Instant::now();
    let bound = wcet::bound(fp);
    // A correct call asks at most as many questions as it has events.
    let limits = Limits {
        leaf_budget: opts.max_paths_per_call,
        question_limit: bound.max_events + 1,
        values: VALUE_RANGE,
    };
    let mut driver = Driver::build(header, limits, opts.target, opts.cflags.as_deref())?;
    let space_opts = SpaceOptions {
        operator_jumps: opts.operator_jumps,
        depth: opts.depth,
        max_states: opts.max_states,
        max_paths_per_call: opts.max_paths_per_call,
        keep_last_block: false,
        record_edges: false,
        // parts are dropped from the states only when every run checks that the C ignores them
        drop_dead: opts.perturb,
        join_paths: true,
    };
    let mut space = Space::new(fp, space_opts);
    let vars = cview::Vars::new(&driver, fp, space.interp())
        .map_err(|name| DriverError::Protocol(format!("the stub runtime declares no '{name}'")))?;
    let names = vars.names.clone();
    // dead counters are put back at stage starts where the views drop them
    let masked = opts.perturb && !space.abstraction.has_return;
    driver.join_runs(masked, &vars.ranges)?;
    let mut side = CSide::new(&mut driver, vars, bound.clone(), opts);
    side.masked = masked;
    let mut walk = space::explore(&mut space, &mut side)?;
    // states whose call the C side cut (its memory for join points) are cut states too
    for &n in &side.cut_nodes {
        if let Some(c) = walk.incomplete.get_mut(n) {
            *c = true;
        }
    }
    // and the paths the C did not run there were not compared
    walk.transitions = walk.transitions.saturating_sub(side.not_run);
    let findings = std::mem::take(&mut side.findings);
    let (cut_c, max_events_seen, second_runs) =
        (side.cut.clone(), side.max_events_seen, side.second_runs);
    let found_on = driver.target.name().to_string();
    let cx = report::shortest(
        findings.into_iter().map(|f| counterexample(&walk, f, &found_on)).collect(),
    );
    let symbolic_loops = space
        .abstraction
        .symbolic
        .iter()
        .map(|l| format!("block {} '{}' {}", l.block, fp.blocks[l.block].name, l.var))
        .collect();
    let mut report = Report {
        target: opts.target,
        built: driver.describe(),
        fixpoint: walk.fixpoint && cut_c.is_none(),
        depth: opts.depth,
        operator_jumps: opts.operator_jumps,
        states: walk.nodes.len(),
        transitions: walk.transitions,
        runs: walk.runs,
        joined: walk.joined,
        max_depth: walk.max_depth,
        second_runs,
        abstracted: Abstracted {
            c_variables: names,
            watched_bytes: driver.watched,
            exact: space.abstraction.exact,
            last_position_kept: space.abstraction.has_return,
            symbolic_loops,
            restarts: driver.restarts,
        },
        random_calls: 0,
        cut: walk.cut.clone().or(cut_c),
        cut_states: cut_states(fp, &walk),
        bound,
        max_events_seen,
        counterexample: cx,
        seconds: 0.0,
        constants: Vec::new(),
    };
    let values = driver.constant_values()?;
    report.constants = driver
        .constants
        .iter()
        .zip(values)
        .map(|(text, compiled)| ConstantReading {
            text: text.clone(),
            host: text.parse().unwrap_or(f64::NAN),
            compiled,
        })
        .collect();
    if report.counterexample.is_none() {
        random_runs(&mut driver, fp, opts, &mut report)?;
    }
    report.seconds = started.elapsed().as_secs_f64();
    Ok(report)
}

/// The states whose transitions a budget cut, as "block 'name' stage n" (the first paths of
/// their calls, in answer order, were compared; the rest, and what they lead to, were not).
fn cut_states(fp: &Fp, walk: &space::Explored) -> Vec<String> {
    walk.incomplete
        .iter()
        .enumerate()
        .filter(|(_, cut)| **cut)
        .filter_map(|(i, _)| walk.nodes.get(i))
        .map(|n| {
            let name = fp.blocks.get(n.obs.block).map_or("?", |b| b.name.as_str());
            // a block name is the user's text: no control character reaches the terminal
            let name: String = name
                .chars()
                .map(
                    |c| if c.is_control() { c.escape_unicode().to_string() } else { c.to_string() },
                )
                .collect();
            format!("block {} '{name}' stage {}", n.obs.block, n.obs.stage)
        })
        .collect()
}

/// The counterexample of a finding: the path to its node, then its move.
fn counterexample(walk: &space::Explored, f: Finding, target: &str) -> Counterexample {
    let mut moves = walk.path_to(f.node);
    moves.extend(f.mv);
    let mut cx = Counterexample::new(RunPath::of(&moves), f.what, f.expected, f.actual);
    cx.target = target.to_string();
    cx.other = f.other.map(|o| RunPath::of(&walk.path_to(o)));
    cx
}

fn random_runs(
    driver: &mut Driver,
    fp: &Fp,
    opts: &Options,
    report: &mut Report,
) -> Result<(), ValidateError> {
    for run in 0..opts.random_runs {
        let percent = [50, 20, 80][run % 3];
        let seed = 0x5EED_0000 + run as u64;
        let numbers = seeded_sequence(seed, opts.random_steps * 64, percent);
        let (c_text, ok) = driver.walk(opts.random_steps, &numbers)?;
        let mut interp = Interp::new(fp);
        let mut oracle = Scripted::new(numbers.clone());
        let r = interp.run(&mut oracle, opts.random_steps)?;
        let want = r.to_text();
        report.random_calls += opts.random_steps;
        for s in &r.steps {
            report.max_events_seen = report.max_events_seen.max(s.events.len());
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
            let what = format!(
                "random run {run} (seed {seed:#x}, {percent}% true) differs at trace line {}",
                i + 1
            );
            let path = RunPath { transitions: step, calls: step, ..RunPath::default() };
            let mut cx = Counterexample::new(
                path,
                what,
                wl.iter().skip(i).take(5).map(|s| s.to_string()).collect(),
                cl.iter().skip(i).take(5).map(|s| s.to_string()).collect(),
            );
            cx.replay = format!(
                "vouch fpl sim PLAN --seed {seed} --percent-true {percent} --steps {step} --trace"
            );
            cx.target = driver.target.name().to_string();
            report.counterexample = Some(cx);
            return Ok(());
        }
    }
    Ok(())
}
