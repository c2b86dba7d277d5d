//! Enumeration of every way one `auto_nav` call can go, on the reference interpreter.
//!
//! A call asks the oracle a sequence of questions (conditions, non-literal `for` bounds). The
//! answers form a tree; [`enumerate_call`] walks it depth first by re-running the call from the
//! same starting state with a longer answer prefix each time. Conditions branch on false/true;
//! integer values (the bounds of `for` loops) branch on every value of [`VALUE_RANGE`]: the C
//! stores them in `int8_t` counters, so these 256 values are every value the C can hold.
//!
//! Answers are encoded as the numbers of the shared oracle convention
//! ([`super::oracle`]): a condition is `0`/`1`, a value `v` is `2 * v`, so the same
//! answer list drives the C stub and the interpreter.
//!
//! The state-space walk of [`super::space`], hence the validator and the model checker, build
//! on this, so they explore the same tree.

pub mod joins;

use std::collections::HashMap;
use std::hash::Hash;

use joins::{End, join_points};

use super::oracle::{Oracle, literal_value};
use super::trace::{Event, Observation};
use super::{Interp, State, StepError};

/// Values tried for a non-literal integer (a `for` bound): every `int8_t` (inclusive range).
pub const VALUE_RANGE: (i64, i64) = (i8::MIN as i64, i8::MAX as i64);

/// Condition texts starting with this prefix are never shown to the user: the model checker
/// uses them to observe forbidden deroutes (see [`crate::model_check`]). They are answered
/// `true` without branching when they end with [`FORCED_SUFFIX`].
pub const MARKER_PREFIX: &str = "\u{0}vouch:";
pub const FORCED_SUFFIX: &str = ":forced";

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Asked {
    Cond,
    Value,
}

/// Answers from a prefix; beyond it, the first choice, remembering what was asked (forced
/// markers are answered without being a question).
struct PrefixOracle {
    prefix: Vec<i64>,
    taken: Vec<(Asked, i64)>,
    /// Marker conditions answered true during the call (model checking).
    markers_true: Vec<String>,
}

impl PrefixOracle {
    fn next(&mut self, kind: Asked) -> i64 {
        let n = self.prefix.get(self.taken.len()).copied().unwrap_or(0);
        self.taken.push((kind, n));
        n
    }
}

impl Oracle for PrefixOracle {
    fn cond(&mut self, text: &str) -> bool {
        let forced = text.starts_with(MARKER_PREFIX) && text.ends_with(FORCED_SUFFIX);
        let v = forced || self.next(Asked::Cond) & 1 != 0;
        if v && text.starts_with(MARKER_PREFIX) {
            self.markers_true.push(text.to_string());
        }
        v
    }
    fn value(&mut self, text: &str) -> i64 {
        match literal_value(text) {
            Some(v) => v,
            None => self.next(Asked::Value) / 2,
        }
    }
}

/// One complete path of one call.
#[derive(Debug, Clone)]
pub struct CallPath<'p> {
    /// The answer numbers consumed by the call (forced markers ask nothing).
    pub answers: Vec<i64>,
    pub events: Vec<Event>,
    pub after: Observation,
    pub state: State<'p>,
    /// Marker conditions that were true (model checking only).
    pub markers: Vec<String>,
}

/// A run of one call that reached, at the start of a stage, a state an earlier run of the same
/// call had reached there: its future is that run's, so it stops (see [`enumerate_joined`]).
#[derive(Debug, Clone)]
pub struct Joined {
    /// The answers consumed before the stage start.
    pub answers: Vec<i64>,
    /// The events before it.
    pub events: Vec<Event>,
    /// The join point: its number in the order the runs reached them.
    pub node: usize,
    /// The paths of the call it stands for: those below the join point (saturating).
    pub weight: u128,
}

/// Result of [`enumerate_call`] and [`enumerate_joined`].
#[derive(Debug, Clone)]
pub struct CallTree<'p> {
    /// The runs that reached the end of the call.
    pub paths: Vec<CallPath<'p>>,
    /// The runs that stopped at a join point.
    pub joined: Vec<Joined>,
    /// Paths of the call the runs stand for (saturating).
    pub total: u128,
    /// The run budget was exhausted: the runs are a prefix (in DFS order) of the exploration.
    pub cut: bool,
}

/// Does event `e` consume an answer?
fn asks(e: &Event) -> bool {
    match e {
        Event::Cond { text, .. } => {
            !(text.starts_with(MARKER_PREFIX) && text.ends_with(FORCED_SUFFIX))
        }
        Event::Value { text, .. } => literal_value(text).is_none(),
        Event::Code { .. } => false,
    }
}

/// Every path of one call from `from`, in depth-first order (false before true, value 0
/// before the others), at most `max_paths` of them.
pub fn enumerate_call<'p>(
    interp: &mut Interp<'p>,
    from: &State<'p>,
    max_paths: usize,
) -> Result<CallTree<'p>, StepError> {
    enumerate(interp, from, max_paths, None::<&dyn Fn(&State<'p>)>)
}

/// Every way one call from `from` can go, as a graph rather than a tree: runs are made in the
/// order of [`enumerate_call`], and a run that reaches the start of a stage (the C's
/// `Stage(n)` label) with a `key` an earlier run of this call reached there stops, *joined*
/// to it: what follows is the earlier run's future. Paths that differ only in what the rest of
/// the call cannot read (the key) are explored once from there on, so the runs grow with the
/// number of distinct states at stage starts, not with the number of paths (a chain of loops
/// each left at once for most values of its bound has exponentially many). At most
/// `max_runs` runs.
pub fn enumerate_joined<'p, K: Eq + Hash>(
    interp: &mut Interp<'p>,
    from: &State<'p>,
    max_runs: usize,
    key: &dyn Fn(&State<'p>) -> K,
) -> Result<CallTree<'p>, StepError> {
    enumerate(interp, from, max_runs, Some(key))
}

fn enumerate<'p, K: Eq + Hash>(
    interp: &mut Interp<'p>,
    from: &State<'p>,
    max_runs: usize,
    key: Option<&dyn Fn(&State<'p>) -> K>,
) -> Result<CallTree<'p>, StepError> {
    let mut tree = CallTree { paths: Vec::new(), joined: Vec::new(), total: 0, cut: false };
    let mut nodes: HashMap<K, usize> = HashMap::new();
    // paths from each join point to the end of the call; complete when a later run joins it
    // (depth first, every run below a point comes before any run joining it)
    let mut below: Vec<u128> = Vec::new();
    if key.is_some() {
        interp.record_stage_starts();
    }
    // Each pending prefix is a list of answers; the walk is depth first, false first.
    let mut pending: Vec<Vec<i64>> = vec![Vec::new()];
    let mut runs = 0;
    while let Some(prefix) = pending.pop() {
        if runs >= max_runs {
            tree.cut = true;
            break;
        }
        runs += 1;
        interp.state = from.clone();
        let mut oracle = PrefixOracle { prefix, taken: Vec::new(), markers_true: Vec::new() };
        let rec = interp.step(&mut oracle)?;
        let plen = oracle.prefix.len();
        let (passed, end) = match key {
            Some(k) => join_points(interp, &rec.events, plen, k, &mut nodes),
            None => (Vec::new(), End::Call),
        };
        let asked = match end {
            End::Call => oracle.taken.len(),
            End::Join(.., asked) => asked,
        };
        // Alternatives for every question asked beyond the prefix (before the join point).
        // The shallowest is pushed first so it is popped last: the walk is depth first in
        // lexicographic answer order.
        for i in plen..asked {
            let base: Vec<i64> = oracle.taken[..i].iter().map(|t| t.1).collect();
            let alts: Vec<i64> = match oracle.taken[i].0 {
                Asked::Cond => vec![1],
                Asked::Value => {
                    (VALUE_RANGE.0..=VALUE_RANGE.1).filter(|v| *v != 0).map(|v| 2 * v).collect()
                }
            };
            for a in alts.iter().rev() {
                let mut p = base.clone();
                p.push(*a);
                pending.push(p);
            }
        }
        let answers: Vec<i64> = oracle.taken[..asked].iter().map(|t| t.1).collect();
        let weight = match end {
            End::Call => {
                tree.paths.push(CallPath {
                    answers,
                    events: rec.events,
                    after: rec.after,
                    state: interp.state.clone(),
                    markers: oracle.markers_true,
                });
                1
            }
            End::Join(i, node, _) => {
                let events = rec.events[..interp.stage_starts()[i].events].to_vec();
                let weight = below.get(node).copied().unwrap_or(0);
                tree.joined.push(Joined { answers, events, node, weight });
                weight
            }
        };
        below.resize(nodes.len(), 0);
        for n in passed {
            below[n] = below[n].saturating_add(weight);
        }
        tree.total = tree.total.saturating_add(weight);
    }
    Ok(tree)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PLAN: &str = r#"<flight_plan name="t" lat0="43.5" lon0="1.4" alt="250" ground_alt="150"
        security_height="30" max_dist_from_home="1000">
      <waypoints><waypoint name="HOME" x="0" y="0"/></waypoints>
      <exceptions><exception cond="e()" deroute="HOME"/></exceptions>
      <blocks><block name="B"><call fun="f()"/></block></blocks></flight_plan>"#;

    #[test]
    fn paths_of_one_call_in_lexicographic_order() {
        let plan = crate::front::parse_str("t.xml", PLAN).expect("parses");
        let fp = crate::passes::lower::lower(&plan).expect("lowers");
        let mut interp = Interp::new(&fp);
        let init = interp.state.clone();
        let tree = enumerate_call(&mut interp, &init, 100).expect("runs");
        // e() false then f() false (next block) or true (stay); e() true (exception)
        let answers: Vec<Vec<i64>> = tree.paths.iter().map(|p| p.answers.clone()).collect();
        assert_eq!(answers, vec![vec![0, 0], vec![0, 1], vec![1]]);
        assert!(!tree.cut);
        let blocks: Vec<usize> = tree.paths.iter().map(|p| p.after.block).collect();
        assert_eq!(blocks, vec![1, 0, 1], "B is block 0, HOME block 1");
        // the budget cuts and says so
        let cut = enumerate_call(&mut interp, &init, 2).expect("runs");
        assert!(cut.cut && cut.paths.len() == 2);
        // f() true stays on the call stage
        let stays = interp.observe_state(&tree.paths[1].state);
        assert_eq!(stays, interp.observe_state(&init));
    }

    #[test]
    fn runs_joined_at_stage_starts_stand_for_every_path() {
        // two loops in a row bounded by n and m: 127 values of n enter the first loop (the
        // call ends), 129 leave it at once and the call reaches the second loop, whose 256
        // values each end the call: 127 + 129 × 256 paths
        let plan = crate::front::parse_str(
            "t.xml",
            r#"<flight_plan name="t" lat0="43.5" lon0="1.4" alt="250" ground_alt="150"
            security_height="30" max_dist_from_home="1000">
          <waypoints><waypoint name="HOME" x="0" y="0"/></waypoints>
          <blocks><block name="B"><for var="i" from="1" to="n"><call_once fun="a()"/></for>
          <for var="j" from="1" to="m"><call_once fun="b()"/></for></block></blocks>
          </flight_plan>"#,
        )
        .expect("parses");
        let fp = crate::passes::lower::lower(&plan).expect("lowers");
        let space = crate::semantics::space::Space::new(&fp, Default::default());
        let mut interp = Interp::new(&fp);
        let init = interp.state.clone();
        let key = |s: &State<'_>| space.stage_key(s);
        let tree = enumerate_joined(&mut interp, &init, 10_000, &key).expect("runs");
        assert_eq!(tree.total, 127 + 129 * 256);
        // the first run that leaves the first loop goes on to the second loop's start; the
        // other 128 stop there, joined to it. Below it, likewise: 127 values of m enter the
        // second loop, the first that leaves it goes on to the block's end, the other 128
        // stop there. Runs to the end: 127 + 127 + 1.
        assert_eq!((tree.paths.len(), tree.joined.len()), (255, 256));
        for answers in [1, 2] {
            let at: Vec<usize> =
                tree.joined.iter().filter(|j| j.answers.len() == answers).map(|j| j.node).collect();
            assert_eq!(at.len(), 128);
            assert!(at.iter().all(|n| *n == at[0]));
        }
        let full = enumerate_call(&mut interp, &init, 100_000).expect("runs");
        assert_eq!(full.paths.len() as u128, tree.total);
        assert!(full.joined.is_empty() && !full.cut && !tree.cut);
    }
}
