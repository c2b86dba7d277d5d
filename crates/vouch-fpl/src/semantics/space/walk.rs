//! The breadth-first walk of a [`Space`] to its fixpoint, with a [`Companion`] beside the
//! interpreter (the compiled C when validating; [`Alone`] for the model checker).

use std::collections::{HashMap, VecDeque};

use super::{Move, Space, Successors, ViewKey};
use crate::semantics::trace::Observation;
use crate::semantics::{State, StepError};

/// What runs beside the interpreter during the walk (the compiled C when validating).
pub trait Companion<'p> {
    /// The companion's state.
    type State: Clone;
    /// The part of its state that must be a function of the interpreter's view.
    type Key: PartialEq;
    type Error: From<StepError>;
    /// Its state at the start, beside the interpreter's initial state.
    fn initial(&mut self, space: &Space<'p>) -> Result<Self::State, Self::Error>;
    /// Compares the transitions of node `id` (`next`, from the interpreter state `from`) and
    /// returns the companion's state after each of `next.succ` (`None` where it disagreed:
    /// the companion keeps the finding).
    fn expand(
        &mut self,
        space: &Space<'p>,
        id: usize,
        from: &State<'p>,
        state: &Self::State,
        next: &Successors<'p>,
    ) -> Result<Vec<Option<Self::State>>, Self::Error>;
    fn key(&self, state: &Self::State) -> Self::Key;
    /// The successor `mv` of node `from` has the interpreter view of node `existing` but
    /// another companion key than `existing_key`.
    fn conflict(
        &mut self,
        existing: usize,
        existing_key: &Self::Key,
        from: usize,
        mv: &Move,
        state: &Self::State,
    );
    /// A disagreement was found: the walk finishes the current level and stops.
    fn found(&self) -> bool;
}

/// The walk without a companion (model checking).
pub struct Alone;

impl<'p> Companion<'p> for Alone {
    type State = ();
    type Key = ();
    type Error = StepError;
    fn initial(&mut self, _: &Space<'p>) -> Result<(), StepError> {
        Ok(())
    }
    fn expand(
        &mut self,
        _: &Space<'p>,
        _: usize,
        _: &State<'p>,
        _: &(),
        next: &Successors<'p>,
    ) -> Result<Vec<Option<()>>, StepError> {
        Ok(vec![Some(()); next.succ.len()])
    }
    fn key(&self, _: &()) {}
    fn conflict(&mut self, _: usize, _: &(), _: usize, _: &Move, _: &()) {}
    fn found(&self) -> bool {
        false
    }
}

/// A state of the walk: how it was first reached.
#[derive(Debug, Clone)]
pub struct Node {
    pub obs: Observation,
    /// Transitions from the initial state (breadth first: the fewest).
    pub depth: usize,
    /// The node it was first reached from, and the move.
    pub parent: Option<(usize, Move)>,
}

/// A recorded transition.
#[derive(Debug, Clone)]
pub struct Edge {
    pub from: usize,
    pub to: usize,
    pub mv: Move,
    pub markers: Vec<String>,
}

/// The outcome of the walk.
#[derive(Debug, Clone, Default)]
pub struct Explored {
    /// Node 0 is the initial state.
    pub nodes: Vec<Node>,
    /// With [`super::SpaceOptions::record_edges`].
    pub edges: Vec<Edge>,
    /// Transitions taken (compared, when validating): every path of every call and every
    /// jump, also those explored once for several paths (saturating).
    pub transitions: u128,
    /// Runs made: call runs to the end or to a join point, and jumps.
    pub runs: usize,
    /// Of the runs, those that stopped at a join point.
    pub joined: usize,
    /// Every reachable state was expanded: no budget, no depth bound and no stop on a
    /// disagreement cut the walk.
    pub fixpoint: bool,
    /// Why the walk is incomplete (a budget), if it is.
    pub cut: Option<String>,
    /// The depth bound stopped the walk with states left to expand.
    pub bounded: bool,
    /// Nodes some of whose successors were dropped by a budget.
    pub incomplete: Vec<bool>,
    /// Largest depth of an expanded node.
    pub max_depth: usize,
}

impl Explored {
    /// The moves from the initial state to `node`.
    pub fn path_to(&self, node: usize) -> Vec<Move> {
        let mut moves = Vec::new();
        let mut cur = node;
        while let Some((p, mv)) = self.nodes.get(cur).and_then(|n| n.parent.clone()) {
            moves.push(mv);
            cur = p;
        }
        moves.reverse();
        moves
    }
}

/// Walks the reachable states of `space` breadth first, beside `comp`, to a fixpoint (or a
/// budget, the depth bound, or the end of the level where `comp` found a disagreement).
pub fn explore<'p, C: Companion<'p>>(
    space: &mut Space<'p>,
    comp: &mut C,
) -> Result<Explored, C::Error> {
    let init = space.initial();
    let c0 = comp.initial(space)?;
    let mut out = Explored::default();
    let mut index: HashMap<ViewKey, usize> = HashMap::from([(space.key(&init), 0)]);
    let mut ckeys = vec![comp.key(&c0)];
    out.nodes.push(Node { obs: space.interp().observe_state(&init), depth: 0, parent: None });
    out.incomplete.push(false);
    let mut queue = VecDeque::from([(0usize, init, c0)]);
    let mut found_at: Option<usize> = None;
    let mut stopped = false;
    while let Some((id, st, cst)) = queue.pop_front() {
        let depth = out.nodes[id].depth;
        if found_at.is_some_and(|f| depth > f) {
            stopped = true;
            break;
        }
        if space.opts.depth.is_some_and(|d| depth >= d) {
            out.bounded = true;
            continue;
        }
        out.max_depth = out.max_depth.max(depth);
        let next = space.transitions(&st)?;
        if next.cut {
            let what = if space.opts.join_paths { "runs" } else { "paths" };
            out.cut =
                Some(format!("more than {} {what} in one call", space.opts.max_paths_per_call));
            out.incomplete[id] = true;
        }
        let csucc = comp.expand(space, id, &st, &cst, &next)?;
        out.transitions = out.transitions.saturating_add(next.transitions);
        out.runs += next.succ.len() + next.joined.len();
        out.joined += next.joined.len();
        for (s, c) in next.succ.into_iter().zip(csucc) {
            let Some(c) = c else { continue };
            let k = space.key(&s.state);
            let to = match index.get(&k) {
                Some(&t) => {
                    if ckeys[t] != comp.key(&c) {
                        comp.conflict(t, &ckeys[t], id, &s.mv, &c);
                    }
                    t
                }
                None => {
                    if out.nodes.len() >= space.opts.max_states {
                        out.cut = Some(format!("more than {} states", space.opts.max_states));
                        out.incomplete[id] = true;
                        continue;
                    }
                    let t = out.nodes.len();
                    index.insert(k, t);
                    ckeys.push(comp.key(&c));
                    out.nodes.push(Node {
                        obs: s.after,
                        depth: depth + 1,
                        parent: Some((id, s.mv.clone())),
                    });
                    out.incomplete.push(false);
                    queue.push_back((t, s.state, c));
                    t
                }
            };
            if space.opts.record_edges {
                out.edges.push(Edge { from: id, to, mv: s.mv, markers: s.markers });
            }
        }
        if comp.found() && found_at.is_none() {
            found_at = Some(depth);
        }
    }
    out.fixpoint = !stopped && !out.bounded && out.cut.is_none() && found_at.is_none();
    Ok(out)
}
