//! The reachable state space of a plan, explored to a fixpoint: from the initial state, every
//! path of one `auto_nav` call (every condition answer, every `int8_t` value of a non-literal
//! `for` bound) and, optionally, every operator jump (the ground station's "go to block",
//! between two calls), until no new state appears.
//!
//! States are merged by a *view* ([`ViewKey`]) that keeps everything the future of the plan
//! can depend on and drops what it cannot read:
//!
//! * the current block and its continuation (which fixes the stage number);
//! * the last block and its continuation only when the plan has a `return` stage (the only
//!   reader of `last_block`/`last_stage`); with [`SpaceOptions::keep_last_block`] the last
//!   block number is kept anyway (properties that name it);
//! * the `for` counters of the loops the continuation is inside (its loop test or loop-back is
//!   on the stack), and with a `return` stage also those the last continuation is inside: any
//!   other counter is dead, overwritten by its loop's initialisation before its test can run
//!   (a block is entered at stage 0; the continuation of a loop's body holds its loop-back);
//! * for a loop whose bound is not a literal, the counter pair only through its
//!   [`LoopClass`]: whether the next test leaves the loop, continues, or can never leave
//!   (`to = 127`: the `int8_t` counter wraps before it exceeds the bound);
//! * not `last_wp` (written by `go` stages, read only by the firmware).
//!
//! Exactness for the interpreter: [`super::Interp`] reads the last position only in `Return`,
//! the counters only in the loop tests of the current block, a counter pair only through
//! `++v > to`, and never `last_wp`. Merged states therefore behave the same for every call,
//! up to the dropped parts, which each call either keeps or overwrites with a value of its
//! own. The validator checks the same of the compiled C on every transition
//! (`crate::evidence::validate`).
//!
//! [`explore`] (in `walk.rs`) is the breadth-first walk shared by the validator (with the
//! compiled C as [`Companion`]) and the model checker (with none).

mod walk;

pub use walk::{Alone, Companion, Edge, Explored, Node, explore};

use serde::Serialize;

pub use super::explore::Joined;
use super::explore::{enumerate_call, enumerate_joined};
use super::oracle::literal_value;
use super::trace::{Event, Observation};
use super::{Interp, Item, State, StepError};
use crate::passes::fp::{BlockIx, Fp, FpStage};

/// What the walk covers and how far it may go.
#[derive(Debug, Clone)]
pub struct SpaceOptions {
    /// Every operator jump is a transition of every state.
    pub operator_jumps: bool,
    /// Stop after this many transitions from the initial state (a bounded walk, not a
    /// fixpoint).
    pub depth: Option<usize>,
    /// State budget.
    pub max_states: usize,
    /// Paths of one call budget.
    pub max_paths_per_call: usize,
    /// Keep the last block number in the view even without `return` stages.
    pub keep_last_block: bool,
    /// Keep every transition (the model checker needs the edges; the validator counts them).
    pub record_edges: bool,
    /// Merge states that differ only in parts the plan cannot read (see the module
    /// documentation); `false` keeps every counter, the last position and `last_wp` as they are.
    pub drop_dead: bool,
    /// Explore each call as a graph: runs that reach a stage start in the same state
    /// ([`Space::stage_key`]) are joined (see [`enumerate_joined`]); `max_paths_per_call`
    /// then bounds the runs. `false`: every path is run to the end of the call.
    pub join_paths: bool,
}

impl Default for SpaceOptions {
    fn default() -> Self {
        SpaceOptions {
            operator_jumps: true,
            depth: None,
            max_states: 1_000_000,
            max_paths_per_call: 100_000,
            keep_last_block: false,
            record_edges: false,
            drop_dead: true,
            join_paths: false,
        }
    }
}

/// One transition.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Move {
    /// One `auto_nav` call with these answers (oracle convention).
    Call(Vec<i64>),
    /// An operator jump to this block (`nav_goto_block`, no forbidden-deroute check).
    Jump(BlockIx),
}

/// The transitions of a state.
#[derive(Debug, Clone)]
pub struct Successors<'p> {
    /// The runs of one call that reached its end, then the operator jumps.
    pub succ: Vec<Succ<'p>>,
    /// The runs of the call joined to an earlier one at a stage start (none unless
    /// [`SpaceOptions::join_paths`]).
    pub joined: Vec<Joined>,
    /// Transitions these stand for: every path of the call, and the jumps (saturating).
    pub transitions: u128,
    /// A budget cut the call.
    pub cut: bool,
}

/// A successor of a state.
#[derive(Debug, Clone)]
pub struct Succ<'p> {
    pub mv: Move,
    pub events: Vec<Event>,
    pub state: State<'p>,
    pub after: Observation,
    /// Marker conditions answered true (model checking only).
    pub markers: Vec<String>,
}

/// What the next test of a `for` loop does with this counter pair (`int8_t` arithmetic, as
/// in C): `++v > to` true, false now but true within 256 tests, or never.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LoopClass {
    Exits,
    Continues,
    Endless,
}

/// Tests until the loop with counter `v` and bound `to` is left (`None`: never).
pub fn iterations_left(v: i8, to: i8) -> Option<u16> {
    let mut v = v;
    for n in 0..=256u16 {
        v = v.wrapping_add(1);
        if v > to {
            return Some(n);
        }
    }
    None
}

/// The class of a counter pair.
pub fn loop_class(v: i8, to: i8) -> LoopClass {
    match iterations_left(v, to) {
        Some(0) => LoopClass::Exits,
        Some(_) => LoopClass::Continues,
        None => LoopClass::Endless,
    }
}

/// A counter in the view.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CounterView {
    Value(i8, i8),
    Class(LoopClass),
}

/// The last position in the view.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum LastView {
    Dropped,
    Block(BlockIx),
    Full(BlockIx, Vec<usize>),
}

/// The merged state (see the module documentation).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ViewKey {
    pub block: BlockIx,
    /// Stage number of every item of the continuation.
    pub remaining: Vec<usize>,
    pub last: LastView,
    pub counters: Vec<((BlockIx, usize), CounterView)>,
    /// Only in exact views (nothing dropped).
    pub last_wp: Option<usize>,
}

/// A loop whose bound is not a literal (its counters are in the view by class).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SymbolicLoop {
    pub block: BlockIx,
    /// Number of its initialisation stage.
    pub stage: usize,
    /// The C variable (`_var_v`).
    pub var: String,
}

/// What the view drops, for the plan at hand.
#[derive(Debug, Clone, Serialize)]
pub struct Abstraction {
    /// Nothing is dropped ([`SpaceOptions::drop_dead`] off).
    pub exact: bool,
    /// The plan has a `return` stage: the last position and every counter are kept.
    pub has_return: bool,
    /// The last block is kept although there is no `return` (model checking).
    pub keeps_last_block: bool,
    pub symbolic: Vec<SymbolicLoop>,
}

/// The interpreter and what its view keeps.
pub struct Space<'p> {
    interp: Interp<'p>,
    /// Runs the calls explored with [`SpaceOptions::join_paths`] (made on first use).
    runner: Option<Interp<'p>>,
    pub abstraction: Abstraction,
    pub opts: SpaceOptions,
}

fn has_return(stages: &[FpStage]) -> bool {
    stages.iter().any(|s| match s {
        FpStage::Return { .. } => true,
        FpStage::While { body, .. } | FpStage::For { body, .. } => has_return(body),
        _ => false,
    })
}

fn symbolic_loops<'p>(
    interp: &Interp<'p>,
    block: BlockIx,
    stages: &'p [FpStage],
    out: &mut Vec<SymbolicLoop>,
) {
    for s in stages {
        match s {
            FpStage::For { var, from, to, body, .. } => {
                if literal_value(from).is_none() || literal_value(to).is_none() {
                    let stage = interp.item_number(&Item::Stage(s));
                    out.push(SymbolicLoop { block, stage, var: var.clone() });
                }
                symbolic_loops(interp, block, body, out);
            }
            FpStage::While { body, .. } => symbolic_loops(interp, block, body, out),
            _ => {}
        }
    }
}

impl<'p> Space<'p> {
    pub fn new(fp: &'p Fp, opts: SpaceOptions) -> Self {
        let interp = Interp::new(fp);
        let mut symbolic = Vec::new();
        for (b, block) in fp.blocks.iter().enumerate() {
            symbolic_loops(&interp, b, &block.stages, &mut symbolic);
        }
        let abstraction = Abstraction {
            exact: !opts.drop_dead,
            has_return: fp.blocks.iter().any(|b| has_return(&b.stages)),
            keeps_last_block: opts.keep_last_block,
            symbolic,
        };
        Space { interp, runner: None, abstraction, opts }
    }

    pub fn interp(&self) -> &Interp<'p> {
        &self.interp
    }

    /// The initial state (before the first call).
    pub fn initial(&self) -> State<'p> {
        Interp::new(self.interp.fp()).state
    }

    /// Whether the view takes the counters of the loop (block, initialisation stage) by class
    /// (a non-literal bound, in a view that drops what the plan cannot read).
    pub fn is_symbolic(&self, key: (BlockIx, usize)) -> bool {
        !self.abstraction.exact
            && self.abstraction.symbolic.iter().any(|l| (l.block, l.stage) == key)
    }

    /// The loops (block, initialisation stage) whose counters `s` can still read (every loop
    /// with a counter in an exact view).
    pub fn live_loops(&self, s: &State<'p>) -> Vec<(BlockIx, usize)> {
        if self.abstraction.exact {
            let mut all: Vec<_> = s.counters.keys().copied().collect();
            all.sort_unstable();
            return all;
        }
        let mut live = Vec::new();
        let mut add = |block: BlockIx, stack: &[Item<'p>]| {
            for item in stack {
                if let Item::ForTest(f) | Item::LoopBack(f) = item
                    && matches!(f, FpStage::For { .. })
                {
                    live.push((block, self.interp.item_number(&Item::Stage(f))));
                }
            }
        };
        add(s.block, &s.remaining);
        if self.abstraction.has_return {
            add(s.last_block, &s.last_remaining);
        }
        live.sort_unstable();
        live.dedup();
        live
    }

    /// The view of `s`.
    pub fn key(&self, s: &State<'p>) -> ViewKey {
        let numbers =
            |stack: &[Item<'p>]| stack.iter().map(|i| self.interp.item_number(i)).collect();
        let all = self.abstraction.has_return;
        let counters: Vec<_> = self
            .live_loops(s)
            .into_iter()
            .map(|k| {
                let (v, t) = s.counters.get(&k).copied().unwrap_or((0, 0));
                let view = if self.is_symbolic(k) {
                    CounterView::Class(loop_class(v, t))
                } else {
                    CounterView::Value(v, t)
                };
                (k, view)
            })
            .collect();
        let exact = self.abstraction.exact;
        let last = if all || exact {
            LastView::Full(s.last_block, numbers(&s.last_remaining))
        } else if self.abstraction.keeps_last_block {
            LastView::Block(s.last_block)
        } else {
            LastView::Dropped
        };
        let last_wp = exact.then_some(s.last_wp);
        ViewKey { block: s.block, remaining: numbers(&s.remaining), last, counters, last_wp }
    }

    /// The view of a state at a stage start within a call, where the runs of one call are
    /// joined: [`Space::key`], except that the counters the view keeps are kept exactly (a
    /// counter pair's class is what the *next call* can read; within the call the C holds the
    /// pair itself) and, when the plan has a `return` stage or nothing is dropped, every
    /// counter is kept. The C side joins its runs by the same rule (the validator's driver).
    pub fn stage_key(&self, s: &State<'p>) -> ViewKey {
        let mut k = self.key(s);
        let counters: Vec<(BlockIx, usize)> =
            if self.abstraction.has_return || self.abstraction.exact {
                let mut all: Vec<_> = s.counters.keys().copied().collect();
                all.sort_unstable();
                all
            } else {
                k.counters.iter().map(|c| c.0).collect()
            };
        k.counters = counters
            .into_iter()
            .map(|l| {
                let (v, t) = s.counters.get(&l).copied().unwrap_or((0, 0));
                (l, CounterView::Value(v, t))
            })
            .collect();
        k
    }

    /// Every transition of `s`: the runs of one call (joined at stage starts with
    /// [`SpaceOptions::join_paths`], else every path), then, with operator jumps, a jump to
    /// every block.
    pub fn transitions(&mut self, s: &State<'p>) -> Result<Successors<'p>, StepError> {
        if !self.opts.join_paths {
            let (succ, cut) = self.successors(s)?;
            let transitions = succ.len() as u128;
            return Ok(Successors { succ, joined: Vec::new(), transitions, cut });
        }
        let max = self.opts.max_paths_per_call;
        // the runs are made by a second interpreter: the key reads this one's numbering
        let mut runner = self.runner.take();
        let runner_ref = runner.get_or_insert_with(|| Interp::new(self.interp.fp()));
        let space = &*self;
        let key = |st: &State<'p>| space.stage_key(st);
        let tree = enumerate_joined(runner_ref, s, max, &key);
        self.runner = runner;
        let tree = tree?;
        let calls = tree.paths.len();
        let succ = self.calls_and_jumps(s, tree.paths)?;
        let jumps = (succ.len() - calls) as u128;
        Ok(Successors {
            succ,
            joined: tree.joined,
            transitions: tree.total.saturating_add(jumps),
            cut: tree.cut,
        })
    }

    /// Every call path from `s`, then (with operator jumps) a jump to every block; whether the
    /// path budget cut the call.
    pub fn successors(&mut self, s: &State<'p>) -> Result<(Vec<Succ<'p>>, bool), StepError> {
        let tree = enumerate_call(&mut self.interp, s, self.opts.max_paths_per_call)?;
        let cut = tree.cut;
        Ok((self.calls_and_jumps(s, tree.paths)?, cut))
    }

    fn calls_and_jumps(
        &mut self,
        s: &State<'p>,
        paths: Vec<super::explore::CallPath<'p>>,
    ) -> Result<Vec<Succ<'p>>, StepError> {
        let mut out: Vec<Succ<'p>> = paths
            .into_iter()
            .map(|p| Succ {
                mv: Move::Call(p.answers),
                events: p.events,
                state: p.state,
                after: p.after,
                markers: p.markers,
            })
            .collect();
        if self.opts.operator_jumps {
            for b in 0..self.interp.fp().blocks.len() {
                self.interp.state = s.clone();
                let events = self.interp.operator_goto(b);
                out.push(Succ {
                    mv: Move::Jump(b),
                    events,
                    after: self.interp.observe(),
                    state: self.interp.state.clone(),
                    markers: Vec::new(),
                });
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fp(blocks: &str) -> Fp {
        let text = format!(
            r#"<flight_plan name="t" lat0="43.5" lon0="1.4" alt="250" ground_alt="150"
            security_height="30" max_dist_from_home="1000">
          <waypoints><waypoint name="HOME" x="0" y="0"/></waypoints>
          <blocks>{blocks}</blocks></flight_plan>"#
        );
        let plan = crate::front::parse_str("t.xml", &text).expect("parses");
        crate::passes::lower::lower(&plan).expect("lowers")
    }

    #[test]
    fn loop_classes_follow_int8_arithmetic() {
        assert_eq!(iterations_left(0, 10), Some(10));
        assert_eq!(iterations_left(10, 10), Some(0));
        assert_eq!(loop_class(10, 10), LoopClass::Exits);
        assert_eq!(loop_class(-1, 0), LoopClass::Continues);
        // the counter wraps from 127 to -128 before it can exceed 127
        assert_eq!(loop_class(5, 127), LoopClass::Endless);
        // from = -128: `_var = from - 1` wraps to 127, the first test sees -128
        assert_eq!(iterations_left(127, -128), Some(1));
        assert_eq!(iterations_left(127, 126), Some(255));
    }

    #[test]
    fn the_walk_reaches_its_fixpoint() {
        // B (0): exception e() to HOME, a call f() (false: next stage, the default stage goes
        // to HOME); HOME (1): its home stage stays. Two states, whatever the jumps.
        let f = fp(
            r#"<block name="B"><exception cond="e()" deroute="HOME"/><call fun="f()"/></block>"#,
        );
        for (jumps, transitions) in [(false, 4), (true, 8)] {
            let opts =
                SpaceOptions { operator_jumps: jumps, record_edges: true, ..Default::default() };
            let mut space = Space::new(&f, opts);
            let w = explore(&mut space, &mut Alone).expect("walks");
            assert!(w.fixpoint && !w.bounded && w.cut.is_none());
            assert_eq!(w.nodes.len(), 2, "B stage 0 and HOME stage 0");
            assert_eq!((w.transitions, w.edges.len()), (transitions as u128, transitions));
            let home = w.nodes.iter().position(|n| n.obs.block == 1).expect("HOME reached");
            // breadth first: HOME is one call away (the first path in answer order: e false,
            // f false), or one jump
            let path = w.path_to(home);
            assert_eq!(path.len(), 1);
        }
        let bounded = SpaceOptions { depth: Some(0), ..Default::default() };
        let w = explore(&mut Space::new(&f, bounded), &mut Alone).expect("walks");
        assert!(w.bounded && !w.fixpoint && w.transitions == 0);
    }

    #[test]
    fn dead_parts_are_dropped_and_live_counters_kept() {
        let f = fp(r#"<block name="L"><for var="i" from="1" to="3"><call_once fun="x()"/></for>
            <for var="j" from="1" to="n"><call_once fun="y()"/></for></block>"#);
        let mut space = Space::new(&f, SpaceOptions::default());
        assert_eq!(space.abstraction.symbolic.len(), 1, "the j loop has a non-literal bound");
        assert!(!space.abstraction.has_return);
        let init = space.initial();
        let k0 = space.key(&init);
        assert!(k0.counters.is_empty() && k0.last == LastView::Dropped && k0.last_wp.is_none());
        // one call: the i loop is initialised and its body entered
        let (succ, _) = space.successors(&init).expect("runs");
        let inside = succ[0].state.clone();
        let k1 = space.key(&inside);
        assert_eq!(k1.counters.len(), 1);
        assert_eq!(k1.counters[0].1, CounterView::Value(1, 3));
        // a jump back to the block: the counter is dead again (stage 0 initialises it)
        let (succ, _) = space.successors(&inside).expect("runs");
        let back = succ.iter().find(|s| s.mv == Move::Jump(0)).expect("jump");
        assert_eq!(space.key(&back.state), k0, "merged with the initial state");
        // exact views keep everything
        let exact = Space::new(&f, SpaceOptions { drop_dead: false, ..Default::default() });
        let e1 = exact.key(&inside);
        assert!(e1.last_wp.is_some() && matches!(e1.last, LastView::Full(..)));
        assert_ne!(exact.key(&back.state), exact.key(&init));
    }
}
