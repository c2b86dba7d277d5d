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

mod exhaustive;

use std::time::Instant;

use serde::Serialize;

use super::cdriver::{Driver, DriverError};
use super::wcet::{self, PlanBound};
use crate::ast::FlightPlan;
use crate::emit::{compile_plan, EmitOptions, Flavor};
use crate::passes::fp::Fp;
use crate::passes::CompileError;
use crate::semantics::oracle::{seeded_sequence, Scripted};
use crate::semantics::{Interp, StepError};

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
    /// Wall time of the whole validation, measured by this run.
    pub seconds: f64,
}

impl Report {
    /// Whether the C and the semantics agreed everywhere they were compared.
    pub fn passed(&self) -> bool {
        self.counterexample.is_none()
    }

    /// The text of `vouch fpl validate` for the plan called `name`.
    pub fn render(&self, name: &str) -> String {
        let verdict = if self.passed() { "C and semantics agree" } else { "MISMATCH" };
        let mut s = format!(
            "{name}: {verdict} ({} states, {} call paths compared exhaustively over {} calls = {:.3e} complete runs, {} random calls, {:.2} s)\n",
            self.states, self.call_paths, self.depth, self.runs_covered, self.random_calls, self.seconds
        );
        if let Some(c) = &self.cut {
            s.push_str(&format!("  exploration cut: {c} (the exhaustive part is incomplete)\n"));
        }
        s.push_str(&format!(
            "  bound per call: at most {} stages and {} external events (largest seen: {} events)\n",
            self.bound.max_stages, self.bound.max_events, self.max_events_seen
        ));
        if let Some(cx) = &self.counterexample {
            s.push_str(&cx.render());
        }
        s
    }
}

impl Counterexample {
    /// The counterexample with the answers to replay it.
    pub fn render(&self) -> String {
        let answers: Vec<String> = self.answers.iter().map(|x| x.to_string()).collect();
        let mut s = format!("  {} after {} call(s)\n", self.what, self.calls);
        s.push_str(&format!(
            "  answers (replay with `vouch fpl sim --conditions FILE`): {}\n",
            answers.join(" ")
        ));
        s.push_str("  semantics:\n");
        for l in &self.expected {
            s.push_str(&format!("    {l}\n"));
        }
        s.push_str("  compiled C:\n");
        for l in &self.actual {
            s.push_str(&format!("    {l}\n"));
        }
        s
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
        seconds: 0.0,
    };
    exhaustive::exhaustive(&mut driver, &mut interp, opts, &mut report)?;
    if report.counterexample.is_none() {
        random_runs(&mut driver, fp, opts, &mut report)?;
    }
    report.seconds = started.elapsed().as_secs_f64();
    Ok(report)
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
