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

/// Result of [`enumerate_call`].
#[derive(Debug, Clone)]
pub struct CallTree<'p> {
    pub paths: Vec<CallPath<'p>>,
    /// The path budget was exhausted: `paths` is a prefix (in DFS order) of the tree.
    pub cut: bool,
}

/// Every path of one call from `from`, in depth-first order (false before true, value 0
/// before the others), at most `max_paths` of them.
pub fn enumerate_call<'p>(
    interp: &mut Interp<'p>,
    from: &State<'p>,
    max_paths: usize,
) -> Result<CallTree<'p>, StepError> {
    let mut paths = Vec::new();
    // Each pending prefix is a list of answers; the walk is depth first, false first.
    let mut pending: Vec<Vec<i64>> = vec![Vec::new()];
    while let Some(prefix) = pending.pop() {
        if paths.len() >= max_paths {
            return Ok(CallTree { paths, cut: true });
        }
        interp.state = from.clone();
        let mut oracle = PrefixOracle { prefix, taken: Vec::new(), markers_true: Vec::new() };
        let rec = interp.step(&mut oracle)?;
        let plen = oracle.prefix.len();
        // Alternatives for every question asked beyond the prefix. The shallowest is pushed
        // first so it is popped last: the walk is depth first in lexicographic answer order.
        for i in plen..oracle.taken.len() {
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
        paths.push(CallPath {
            answers: oracle.taken.iter().map(|t| t.1).collect(),
            events: rec.events,
            after: rec.after,
            state: interp.state.clone(),
            markers: oracle.markers_true,
        });
    }
    Ok(CallTree { paths, cut: false })
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
}
