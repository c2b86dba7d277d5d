//! What a validation established, and its text: the size of the walk, whether it reached the
//! fixpoint, what the states leave out, and the shortest disagreement with a way to replay it.

use serde::Serialize;

use crate::evidence::cdriver::Target;
use crate::evidence::wcet::PlanBound;
use crate::semantics::space::Move;

/// A run from the initial state: its calls' answers and the operator jumps between them.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct RunPath {
    /// Calls and operator jumps.
    pub transitions: usize,
    /// `auto_nav` calls.
    pub calls: usize,
    /// Answer numbers of the calls, in order (oracle convention: condition = odd, value = n/2).
    pub answers: Vec<i64>,
    /// Operator jumps as (call they precede, block), the format of `vouch fpl sim --jumps`.
    pub jumps: Vec<(usize, usize)>,
}

impl RunPath {
    pub fn of(moves: &[Move]) -> RunPath {
        let mut p = RunPath { transitions: moves.len(), ..RunPath::default() };
        for m in moves {
            match m {
                Move::Call(a) => {
                    p.calls += 1;
                    p.answers.extend(a);
                }
                Move::Jump(b) => p.jumps.push((p.calls + 1, *b)),
            }
        }
        p
    }

    /// Calls to replay to see the whole run (a jump after the last call shows before the next).
    pub fn replay_steps(&self) -> usize {
        self.jumps.iter().map(|j| j.0).max().unwrap_or(0).max(self.calls)
    }

    /// The `vouch fpl sim` command that replays the run on the semantics (ANSWERS and JUMPS
    /// are files holding the numbers above).
    pub fn replay(&self) -> String {
        let jumps = if self.jumps.is_empty() { "" } else { " --jumps JUMPS" };
        format!(
            "vouch fpl sim PLAN --conditions ANSWERS{jumps} --steps {} --trace",
            self.replay_steps()
        )
    }

    fn render(&self, indent: &str) -> String {
        let answers: Vec<String> = self.answers.iter().map(|x| x.to_string()).collect();
        let mut s = format!(
            "{indent}{} call(s), {} transition(s); answers: {}\n",
            self.calls,
            self.transitions,
            if answers.is_empty() { "none".to_string() } else { answers.join(" ") }
        );
        if !self.jumps.is_empty() {
            let j: Vec<String> = self.jumps.iter().map(|(c, b)| format!("{c} {b}")).collect();
            s.push_str(&format!("{indent}operator jumps (call, block): {}\n", j.join(", ")));
        }
        s
    }
}

/// A disagreement, with everything needed to replay it.
#[derive(Debug, Clone, Serialize)]
pub struct Counterexample {
    /// `auto_nav` calls of the run (the last transition shows the disagreement).
    pub calls: usize,
    /// Calls and operator jumps.
    pub transitions: usize,
    /// Answer numbers from the start.
    pub answers: Vec<i64>,
    /// Operator jumps (call they precede, block).
    pub jumps: Vec<(usize, usize)>,
    pub what: String,
    /// Events and state of the last transition according to the semantics / the compiled C
    /// (for a state-relation conflict: the C variables after the other run / this one).
    pub expected: Vec<String>,
    pub actual: Vec<String>,
    /// For a state-relation conflict: the other run that reaches the same interpreter state.
    pub other: Option<RunPath>,
    /// The command that replays the run on the semantics.
    pub replay: String,
    /// The target the compiled C ran on when it disagreed (`host`, `cortex-m4`, ...).
    pub target: String,
}

impl Counterexample {
    pub fn new(path: RunPath, what: String, expected: Vec<String>, actual: Vec<String>) -> Self {
        Counterexample {
            replay: path.replay(),
            calls: path.calls,
            transitions: path.transitions,
            answers: path.answers,
            jumps: path.jumps,
            what,
            expected,
            actual,
            other: None,
            target: String::new(),
        }
    }

    /// The counterexample with the answers to replay it.
    pub fn render(&self) -> String {
        let path = RunPath {
            transitions: self.transitions,
            calls: self.calls,
            answers: self.answers.clone(),
            jumps: self.jumps.clone(),
        };
        let mut s = format!("  {}\n", self.what);
        if !self.target.is_empty() {
            s.push_str(&format!("  found on: {}\n", self.target));
        }
        s.push_str(&path.render("  run: "));
        s.push_str(&format!("  replay: {}\n", self.replay));
        let (a, b) = match &self.other {
            Some(o) => {
                s.push_str(&o.render("  first run: "));
                ("first run", "this run")
            }
            None => ("semantics", "compiled C"),
        };
        s.push_str(&format!("  {a}:\n"));
        for l in &self.expected {
            s.push_str(&format!("    {l}\n"));
        }
        s.push_str(&format!("  {b}:\n"));
        for l in &self.actual {
            s.push_str(&format!("    {l}\n"));
        }
        s
    }
}

/// What the states of the walk contain and leave out (see `docs/fpl-evidence.md`).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Abstracted {
    /// The C variables observed: every static variable of the header and every global of the
    /// stub runtime, found in their texts.
    pub c_variables: Vec<String>,
    /// Bytes of the C program's writable data segment watched for writes outside those
    /// variables (`None`: not available on this platform).
    pub watched_bytes: Option<usize>,
    /// Nothing is dropped from the states (no changed-state runs to check it).
    pub exact: bool,
    /// The last block and stage are part of the states (the plan has a `return` stage).
    pub last_position_kept: bool,
    /// Loops with a non-literal bound, whose counters are in the states by class.
    pub symbolic_loops: Vec<String>,
    /// Driver processes restarted after a crash.
    pub restarts: usize,
}

/// A decimal constant of the plan's comparisons as the host reads it (a correctly rounded
/// double, as C without special flags) and as the validated build compiled it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConstantReading {
    /// As written in the plan.
    pub text: String,
    pub host: f64,
    pub compiled: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Where the compiled C ran.
    pub target: Target,
    /// How it was built and run (compiler, flags, emulator).
    pub built: String,
    /// Every reachable (interpreter, C) state pair was explored: agreement on every call and
    /// jump from all of them holds for runs of any length (over the abstraction).
    pub fixpoint: bool,
    /// The depth bound given (`--depth`), if any: the walk is then *bounded*.
    pub depth: Option<usize>,
    /// Operator jumps were transitions.
    pub operator_jumps: bool,
    /// State pairs explored.
    pub states: usize,
    /// Transitions compared (call paths and operator jumps), counting the paths a joined run
    /// stands for (saturating at `u128::MAX`).
    pub transitions: u128,
    /// Runs the comparison made: call runs (to the end of the call or to a join point) and
    /// jumps. Without joins, equal to `transitions`.
    pub runs: usize,
    /// Of the runs, those that stopped at a join point.
    pub joined: usize,
    /// The largest number of transitions needed to reach a state.
    pub max_depth: usize,
    /// Runs repeated from a copy of the C state with its dropped parts changed.
    pub second_runs: usize,
    pub abstracted: Abstracted,
    /// Calls compared in the random runs.
    pub random_calls: usize,
    /// Why the walk is incomplete (a budget).
    pub cut: Option<String>,
    /// The states whose calls or successors the budget cut (their first paths, in answer
    /// order, were compared; the rest, and every state only they lead to, were not).
    pub cut_states: Vec<String>,
    pub bound: PlanBound,
    /// Largest number of events seen in one call.
    pub max_events_seen: usize,
    pub counterexample: Option<Counterexample>,
    /// Wall time of the whole validation, measured by this run.
    pub seconds: f64,
    /// The decimal constants of the plan's comparisons as compiled (conditions are free in
    /// the walk, so a constant the build rounds differently is reported here, not there).
    pub constants: Vec<ConstantReading>,
}

impl Report {
    /// Whether the C and the semantics agreed everywhere they were compared.
    pub fn passed(&self) -> bool {
        self.counterexample.is_none()
    }

    /// A budget cut the walk: agreement holds on the explored part only, which is less than
    /// what was asked (the CLI exits 3).
    pub fn incomplete(&self) -> bool {
        !self.fixpoint && self.cut.is_some()
    }

    /// The text of `vouch fpl validate` for the plan called `name`.
    pub fn render(&self, name: &str) -> String {
        let verdict = if self.passed() { "C and semantics agree" } else { "MISMATCH" };
        let reach = match (self.fixpoint, self.depth, &self.cut) {
            (true, _, _) => "fixpoint reached".to_string(),
            (false, _, Some(c)) => format!("exploration cut ({c}), not a fixpoint"),
            (false, Some(d), None) if self.passed() => {
                format!("bounded (depth {d}), not a fixpoint")
            }
            _ => "stopped at the first disagreement".to_string(),
        };
        let jumps =
            if self.operator_jumps { "call paths and operator jumps" } else { "call paths" };
        let mut s = format!(
            "{name}: {verdict} — {reach}: {} states, {} transitions ({jumps}) compared in both directions, {} runs repeated with the dropped state changed, {} random calls, {:.2} s\n",
            self.states, self.transitions, self.second_runs, self.random_calls, self.seconds
        );
        s.push_str(&format!("  compiled C: {}\n", self.built));
        if self.joined > 0 {
            s.push_str(&format!(
                "  paths joined: {} runs made, {} of them joined at a stage start where an earlier run of the same call was in the same state (its future stands for theirs)\n",
                self.runs, self.joined
            ));
        }
        if self.incomplete() {
            s.push_str(&format!(
                "  NOT ESTABLISHED for the whole plan: {} state(s) cut — {}; their first runs (in answer order) were compared, with the paths those stand for; their other paths and the states only those lead to were not\n",
                self.cut_states.len(),
                self.cut_states.join(", ")
            ));
        }
        let a = &self.abstracted;
        let watched = a.watched_bytes.map_or_else(
            || "the rest of static storage not watched on this platform".to_string(),
            |b| format!("the rest of static storage watched ({b} bytes)"),
        );
        s.push_str(&format!(
            "  C state: {} variables ({}); {watched}\n",
            a.c_variables.len(),
            a.c_variables.join(", ")
        ));
        if a.exact {
            s.push_str(
                "  states: exact (every counter, the last position and last_wp as they are)\n",
            );
        } else {
            let last = if a.last_position_kept {
                "kept (the plan has a return stage)"
            } else {
                "dropped (no return stage reads it)"
            };
            s.push_str(&format!(
                "  states: block, continuation, counters of the loops it is inside; last position {last}; last_wp dropped\n"
            ));
        }
        if !a.symbolic_loops.is_empty() {
            let by = if a.exact { "" } else { "; counters by class" };
            s.push_str(&format!(
                "  loops with a non-literal bound (every int8_t value tried{by}): {}\n",
                a.symbolic_loops.join(", ")
            ));
        }
        s.push_str(&format!(
            "  bound per call: at most {} stages and {} external events (largest seen: {} events)\n",
            self.bound.max_stages, self.bound.max_events, self.max_events_seen
        ));
        s.push_str(&self.render_constants());
        if let Some(cx) = &self.counterexample {
            s.push_str(&cx.render());
        }
        s
    }

    /// The constants the validated build reads differently from the host.
    pub fn constant_differences(&self) -> Vec<&ConstantReading> {
        self.constants.iter().filter(|c| c.host.to_bits() != c.compiled.to_bits()).collect()
    }

    fn render_constants(&self) -> String {
        if self.constants.is_empty() {
            return String::new();
        }
        let differ = self.constant_differences();
        if differ.is_empty() {
            let on = self.target.name();
            return format!(
                "  comparison constants: {} ({}), read by the {on} build exactly as on the host\n",
                self.constants.len(),
                self.constants.iter().map(|c| c.text.as_str()).collect::<Vec<_>>().join(", ")
            );
        }
        let mut s = format!(
            "  HOST AND {} DIFFER on {} of {} comparison constants (the walk leaves conditions free, so it agrees with the semantics either way; see fpl lint, fpl::W009):\n",
            self.target.name().to_uppercase(),
            differ.len(),
            self.constants.len()
        );
        for c in differ {
            s.push_str(&format!(
                "    {}: host {:?}, {} {:?}\n",
                c.text,
                c.host,
                self.target.name(),
                c.compiled
            ));
        }
        s
    }
}

/// The shortest of the findings' counterexamples (fewest transitions, then fewest answers).
pub(super) fn shortest(all: Vec<Counterexample>) -> Option<Counterexample> {
    all.into_iter().min_by_key(|c| (c.transitions, c.answers.len()))
}
