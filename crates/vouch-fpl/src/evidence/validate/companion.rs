//! The compiled C beside the interpreter in the walk of [`crate::semantics::space`]: for every
//! state, every call path and operator jump is run on both sides and compared (events; block,
//! stage, last block and stage, `last_wp` and every `for` counter against the interpreter's;
//! the static bound), the run is repeated from a perturbed copy of the C state (every part the
//! view drops changed), and the C state after it becomes the companion state of the successor.

use std::collections::HashMap;

use super::cview::{self, CKey, Vars};
use super::{Options, ValidateError, state_line};
use crate::evidence::cdriver::{CRun, Driver, Second};
use crate::evidence::wcet::PlanBound;
use crate::semantics::State;
use crate::semantics::space::{Companion, Joined, Move, Space, Succ, Successors};

/// A disagreement, before its path is known: the node it starts from and the move that shows
/// it (none: the node itself).
#[derive(Debug, Clone)]
pub(super) struct Finding {
    pub node: usize,
    pub mv: Option<Move>,
    pub what: String,
    pub expected: Vec<String>,
    pub actual: Vec<String>,
    /// For a conflict of the state relation: the other node with the same interpreter state.
    pub other: Option<usize>,
}

/// A C state and its view.
#[derive(Debug, Clone)]
pub(super) struct CState {
    pub bytes: Vec<u8>,
    pub key: CKey,
}

pub(super) struct CSide<'d> {
    pub driver: &'d mut Driver,
    pub vars: Vars,
    pub bound: PlanBound,
    pub perturb: bool,
    pub jumps: bool,
    pub findings: Vec<Finding>,
    pub cut: Option<String>,
    /// The driver puts dead counters back at stage starts (see `Driver::join_runs`).
    pub masked: bool,
    /// Nodes whose call the C side cut.
    pub cut_nodes: Vec<usize>,
    /// Paths of those calls the C side did not run (counted by the walk all the same).
    pub not_run: u128,
    pub max_events_seen: usize,
    pub second_runs: usize,
}

const NOT_ENDING: &str = "the C call asks more questions than the static bound: it does not end";

impl CSide<'_> {
    pub fn new<'d>(
        driver: &'d mut Driver,
        vars: Vars,
        bound: PlanBound,
        opts: &Options,
    ) -> CSide<'d> {
        CSide {
            driver,
            vars,
            bound,
            perturb: opts.perturb,
            jumps: opts.operator_jumps,
            findings: Vec::new(),
            cut: None,
            masked: false,
            cut_nodes: Vec::new(),
            not_run: 0,
            max_events_seen: 0,
            second_runs: 0,
        }
    }

    fn find(
        &mut self,
        node: usize,
        mv: Option<Move>,
        what: impl Into<String>,
        expected: Vec<String>,
        actual: Vec<String>,
    ) {
        self.findings.push(Finding { node, mv, what: what.into(), expected, actual, other: None });
    }

    /// The C's block, stage, last block, last stage and last waypoint in `state`.
    fn runtime(&self, state: &[u8]) -> [usize; 5] {
        self.vars.runtime.map(|id| {
            self.driver
                .var_bytes(state, id)
                .iter()
                .rev()
                .fold(0usize, |a, b| (a << 8) | usize::from(*b))
        })
    }

    /// What the interpreter's state says every compared C variable holds.
    fn expected_after(&self, s: &Succ<'_>) -> [usize; 5] {
        let a = s.after;
        [a.block, a.stage, a.last_block, a.last_stage, s.state.last_wp % 256]
    }

    /// The first counter whose C value differs from the interpreter's, as text. With
    /// `masked`, the driver put the counters of loops a stage start was outside back to their
    /// value at the start of the call (`state`): a loop not live after the call may hold that.
    fn counter_mismatch(
        &self,
        space: &Space<'_>,
        st: &State<'_>,
        state: &[u8],
        after: &[u8],
    ) -> Option<String> {
        let live = space.live_loops(st);
        for (id, kind) in self.vars.kinds.iter().enumerate() {
            let Some(l) = self.vars.loop_of(id) else { continue };
            let crate::evidence::cstate::Kind::Counter { bound, .. } = kind else { continue };
            let (v, t) = st.counters.get(&l).copied().unwrap_or((0, 0));
            let want = if *bound { t } else { v } as u8;
            let got = self.driver.var_bytes(after, id).first().copied().unwrap_or(0);
            let before = self.driver.var_bytes(state, id).first().copied().unwrap_or(0);
            let put_back = self.masked && !live.contains(&l) && got == before;
            if got != want && !put_back {
                let name = &self.vars.names[id];
                return Some(format!("{name} = {} (semantics: {})", got as i8, want as i8));
            }
        }
        None
    }

    fn lines_after(&self, events: &[String], after: &[u8]) -> Vec<String> {
        let r = self.runtime(after);
        let mut v = events.to_vec();
        v.push(state_line([r[0], r[1], r[2], r[3]]));
        v.push(format!("last_wp {}", r[4]));
        v
    }

    /// What is wrong with the run repeated from the changed copy of the state, if anything: the
    /// finding's text and that run's lines.
    fn second_differs(
        &self,
        cview::Copy { bytes: copy, changes }: &cview::Copy,
        second: &Second,
        state: &[u8],
        events: &[String],
        after: &[u8],
    ) -> Option<(String, Vec<String>)> {
        let (how, lines) = match second {
            Second::Differs(ev2) => ("its events differ".to_string(), ev2.clone()),
            Second::Met => return None,
            Second::Same(after2) => {
                let id =
                    cview::second_ok(&self.vars, self.driver, changes, state, copy, after, after2)?;
                (
                    format!("{} ends differently", self.vars.names[id]),
                    self.lines_after(events, after2),
                )
            }
        };
        let changed: Vec<&str> = changes
            .iter()
            .enumerate()
            .filter(|c| c.1.is_some())
            .map(|(i, _)| self.vars.names[i].as_str())
            .collect();
        let what = format!(
            "the C reads state the semantics says it cannot: the same run from the C state with {} changed (dead for the semantics): {how} (first: the run from the state, then: the run from the changed state)",
            changed.join(", ")
        );
        Some((what, lines))
    }

    /// Compares a run the interpreter joined to an earlier one at a stage start with the C run
    /// of the same answers: the same events before it, joined to the same point.
    fn compare_joined(&mut self, node: usize, j: &Joined, run: Option<&CRun>) {
        let want: Vec<String> = j.events.iter().map(|e| e.line()).collect();
        let mut expected = want.clone();
        expected.push(format!("(joins point {})", j.node));
        let mv = Some(Move::Call(j.answers.clone()));
        let (what, actual) = match run {
            Some(CRun::Done { joined: Some(n), events, .. }) if *n == j.node && *events == want => {
                return;
            }
            Some(CRun::Done { joined, events, .. }) => {
                let mut actual = events.clone();
                actual.push(match joined {
                    Some(n) => format!("(joins point {n})"),
                    None => "(goes on)".to_string(),
                });
                (
                    "the C and the semantics do not reach the same states within the call: at a stage start the semantics is in the state an earlier path of this call reached, the C is not or has other events",
                    actual,
                )
            }
            _ => ("the semantics allows this path, the C does not take it", vec![]),
        };
        self.find(node, mv, what, expected, actual);
    }

    /// Compares one interpreter successor with the C run of the same move.
    #[allow(clippy::too_many_arguments)]
    fn compare(
        &mut self,
        space: &Space<'_>,
        node: usize,
        from_block: usize,
        s: &Succ<'_>,
        run: Option<&CRun>,
        copies: &[cview::Copy],
        state: &[u8],
    ) -> Option<CState> {
        let want: Vec<String> = s.events.iter().map(|e| e.line()).collect();
        let mut expected = want.clone();
        let e = self.expected_after(s);
        expected.push(state_line([e[0], e[1], e[2], e[3]]));
        expected.push(format!("last_wp {}", e[4]));
        let mv = Some(s.mv.clone());
        let (events, after, seconds) = match run {
            None => {
                self.find(
                    node,
                    mv,
                    "the semantics allows this path, the C does not take it",
                    expected,
                    vec![],
                );
                return None;
            }
            Some(CRun::Done { joined: Some(n), events, .. }) => {
                let what = format!(
                    "the C stops at a stage start in a state an earlier path of this call reached (join point {n}); the semantics goes on to the end of the call"
                );
                let actual = events.clone();
                self.find(node, mv, what, expected, actual);
                return None;
            }
            Some(CRun::Done { hidden, events, .. }) if !hidden.is_empty() => {
                let what = format!(
                    "the C writes static storage the validator does not see (data segment offset {})",
                    hidden[0]
                );
                let actual = events.clone();
                self.find(node, mv, what, expected, actual);
                return None;
            }
            Some(CRun::Done { events, after, seconds, .. }) => (events, after, seconds),
            Some(CRun::TooLong { .. }) => {
                self.find(node, mv, NOT_ENDING, expected, vec![]);
                return None;
            }
            Some(CRun::Crashed { status, .. }) => {
                self.find(
                    node,
                    mv,
                    format!("the C process died (status {status})"),
                    expected,
                    vec![],
                );
                return None;
            }
        };
        self.max_events_seen = self.max_events_seen.max(events.len());
        let limit = self.bound.blocks.get(from_block).map_or(0, |b| b.events);
        let actual = self.lines_after(events, after);
        if *events != want || self.runtime(after) != e {
            self.find(node, mv, "different events or state", expected, actual);
            return None;
        }
        if let Some(m) = self.counter_mismatch(space, &s.state, state, after) {
            self.find(node, mv, format!("different loop counter: {m}"), expected, actual);
            return None;
        }
        if matches!(s.mv, Move::Call(_)) && events.len() > limit {
            self.find(
                node,
                mv,
                format!("call exceeds the static bound of {limit} events"),
                expected,
                actual,
            );
            return None;
        }
        for (copy, second) in copies.iter().zip(seconds) {
            self.second_runs += 1;
            if let Some((what, ev2)) = self.second_differs(copy, second, state, events, after) {
                self.find(node, mv, what, actual, ev2);
                return None;
            }
        }
        let key = cview::key(&self.vars, self.driver, space, &s.state, after);
        Some(CState { bytes: after.clone(), key })
    }
}

impl<'p> Companion<'p> for CSide<'_> {
    type State = CState;
    type Key = CKey;
    type Error = ValidateError;

    fn initial(&mut self, space: &Space<'p>) -> Result<CState, ValidateError> {
        let init = self.driver.initial()?;
        let interp = space.interp();
        let want: Vec<String> = interp.init_events().iter().map(|e| e.line()).collect();
        if !init.hidden.is_empty() {
            let what = format!(
                "auto_nav_init() writes static storage the validator does not see (data segment offset {})",
                init.hidden[0]
            );
            self.find(0, None, what, vec![], vec![]);
        }
        if init.events != want {
            self.find(0, None, "auto_nav_init() differs", want, init.events.clone());
        }
        let st = space.initial();
        let o = interp.observe_state(&st);
        let r = self.runtime(&init.state);
        if r != [o.block, o.stage, o.last_block, o.last_stage, st.last_wp] {
            let e = vec![state_line([o.block, o.stage, o.last_block, o.last_stage])];
            self.find(
                0,
                None,
                "the initial state differs",
                e,
                vec![state_line([r[0], r[1], r[2], r[3]])],
            );
        }
        let key = cview::key(&self.vars, self.driver, space, &st, &init.state);
        Ok(CState { bytes: init.state, key })
    }

    fn expand(
        &mut self,
        space: &Space<'p>,
        id: usize,
        from: &State<'p>,
        c: &CState,
        next: &Successors<'p>,
    ) -> Result<Vec<Option<CState>>, ValidateError> {
        let succ = &next.succ;
        let copies = if self.perturb {
            cview::copies(&self.vars, self.driver, space, from, &c.bytes)
        } else {
            Vec::new()
        };
        let bytes: Vec<Vec<u8>> = copies.iter().map(|c| c.bytes.clone()).collect();
        // the runs from copies that shift live counters may stop where those are put back
        let shifted = |c: &cview::Copy| {
            c.changes.iter().any(|x| matches!(x, Some(cview::Change::Shifted(_))))
        };
        let stoppable = copies.iter().position(shifted).unwrap_or(copies.len());
        let ex = self.driver.expand(&c.bytes, &bytes, stoppable, self.jumps)?;
        if ex.memory {
            self.cut_nodes.push(id);
            self.cut = Some("the C side had no memory left for the join points of one call".into());
        } else if ex.cut {
            self.cut = Some("the C side's run budget of one call ran out".into());
        }
        // the process died: the runs after it were never made; the crash is the finding
        if let Some(CRun::Crashed { status, answers, jump }) =
            ex.runs.iter().find(|r| matches!(r, CRun::Crashed { .. }))
        {
            let what = format!("the C process died (status {status}) during this transition");
            let mv = jump.map_or_else(|| Move::Call(answers.clone()), Move::Jump);
            self.find(id, Some(mv), what, vec![], vec![]);
            return Ok(vec![None; succ.len()]);
        }
        let mut calls: HashMap<&[i64], &CRun> = HashMap::new();
        let mut jumps: HashMap<usize, &CRun> = HashMap::new();
        for r in &ex.runs {
            match r {
                CRun::Done { jump: Some(b), .. } => {
                    jumps.insert(*b, r);
                }
                _ => {
                    calls.insert(r.answers(), r);
                }
            }
        }
        let mut out = Vec::with_capacity(succ.len());
        for s in succ {
            let run = match &s.mv {
                Move::Call(a) => calls.remove(a.as_slice()),
                Move::Jump(b) => jumps.remove(b),
            };
            if run.is_none() && ex.memory {
                // not run: the C side's exploration of the call was cut
                if matches!(s.mv, Move::Call(_)) {
                    self.not_run = self.not_run.saturating_add(1);
                }
                out.push(None);
                continue;
            }
            out.push(self.compare(space, id, from.block, s, run, &copies, &c.bytes));
        }
        for j in &next.joined {
            let run = calls.remove(j.answers.as_slice());
            if run.is_some() || !ex.memory {
                self.compare_joined(id, j, run);
            } else {
                self.not_run = self.not_run.saturating_add(j.weight);
            }
        }
        // whatever the C did that the semantics did not (only meaningful on complete trees)
        if !ex.cut {
            for r in calls.into_values().chain(jumps.into_values()) {
                let mv = match r {
                    CRun::Done { jump: Some(b), .. } => Move::Jump(*b),
                    _ => Move::Call(r.answers().to_vec()),
                };
                let (what, actual) = match r {
                    CRun::Done { events, after, .. } => (
                        "the C takes a path the semantics does not allow".to_string(),
                        self.lines_after(events, after),
                    ),
                    CRun::TooLong { .. } => (NOT_ENDING.to_string(), vec![]),
                    CRun::Crashed { status, .. } => {
                        (format!("the C process died (status {status})"), vec![])
                    }
                };
                self.find(id, Some(mv), what, vec![], actual);
            }
        }
        Ok(out)
    }

    fn key(&self, state: &CState) -> CKey {
        state.key.clone()
    }

    fn conflict(
        &mut self,
        existing: usize,
        existing_key: &CKey,
        from: usize,
        mv: &Move,
        state: &CState,
    ) {
        let show = |p: &cview::Part| match p {
            cview::Part::Bytes(b) => format!("{b:?}"),
            cview::Part::Class(c) => format!("{c:?}"),
            cview::Part::Dropped => "-".into(),
        };
        let (mut first, mut second) = (Vec::new(), Vec::new());
        for (i, (a, b)) in existing_key.iter().zip(&state.key).enumerate() {
            if a != b {
                first.push(format!("{} = {}", self.vars.names[i], show(a)));
                second.push(format!("{} = {}", self.vars.names[i], show(b)));
            }
        }
        let what = "the C keeps state the semantics does not: the interpreter reaches the same state on another run (first run below), the C does not (bytes of the variables, little end first)";
        self.findings.push(Finding {
            node: from,
            mv: Some(mv.clone()),
            what: what.into(),
            expected: first,
            actual: second,
            other: Some(existing),
        });
    }

    fn found(&self) -> bool {
        !self.findings.is_empty()
    }
}
