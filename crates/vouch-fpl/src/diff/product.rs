//! The walk of the product of the two plans' state spaces, breadth first, to its fixpoint or
//! to the first transition on which they differ.
//!
//! A product state is a pair (old state, new state), merged by the pair of their views
//! ([`crate::semantics::space::ViewKey`]: each view keeps everything its own plan's future can
//! read). From every pair the walk takes every path of one `auto_nav` call of the old plan
//! (every condition answer, every `int8_t` value of a non-literal `for` bound) and runs the new
//! plan on the same answers, then every operator jump to a block number of either plan on both.
//! A transition agrees when both plans produce the same events (up to [`super::normal`]) and end
//! in the same block and stage. Enumerating the old plan's call tree is enough: if every path of
//! it agrees, the new plan asked the same questions in the same order on every path, so its own
//! tree is the same tree.

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;

use super::normal::Canon;
use crate::semantics::oracle::Scripted;
use crate::semantics::space::{Move, Space, SpaceOptions, ViewKey};
use crate::semantics::trace::{Event, Observation};
use crate::semantics::{Interp, State, StepError};

/// An event as the diff observes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seen {
    Cond(Arc<str>, bool),
    Code(Arc<str>),
    Value(Arc<str>, i64),
}

/// Where two runs of one transition part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parting {
    /// The events differ first at this index (one side may have ended there).
    Event(usize),
    /// Same events, another block or stage after the transition.
    State,
}

/// One plan in the walk.
pub struct Side<'p> {
    pub space: Space<'p>,
    pub interp: Interp<'p>,
    pub canon: Canon,
}

impl<'p> Side<'p> {
    pub fn new(fp: &'p crate::passes::fp::Fp, canon: Canon, opts: &SpaceOptions) -> Self {
        let opts = SpaceOptions { operator_jumps: false, record_edges: false, ..opts.clone() };
        Side { space: Space::new(fp, opts), interp: Interp::new(fp), canon }
    }

    /// The observed form of `events`.
    pub fn seen(&mut self, events: &[Event]) -> Vec<Seen> {
        events
            .iter()
            .map(|e| match e {
                Event::Cond { text, value } => Seen::Cond(self.canon.text(text), *value),
                Event::Code { text } => Seen::Code(self.canon.text(text)),
                Event::Value { text, value } => Seen::Value(self.canon.text(text), *value),
            })
            .collect()
    }

    /// One call from `from` with these answers: events, state after, answers consumed.
    pub fn call(
        &mut self,
        from: &State<'p>,
        answers: &[i64],
    ) -> Result<(Vec<Event>, Observation, usize), StepError> {
        self.interp.state = from.clone();
        let mut oracle = Scripted::new(answers.to_vec());
        let rec = self.interp.step(&mut oracle)?;
        Ok((rec.events, rec.after, oracle.consumed()))
    }

    /// An operator jump from `from`: the hooks' events and the state after.
    pub fn jump(&mut self, from: &State<'p>, block: usize) -> (Vec<Event>, Observation) {
        self.interp.state = from.clone();
        let events = self.interp.operator_goto(block);
        (events, self.interp.observe())
    }
}

/// Compares one transition on both sides.
pub fn parting(old: &[Seen], new: &[Seen], a: Observation, b: Observation) -> Option<Parting> {
    if let Some(k) = old.iter().zip(new).position(|(x, y)| x != y) {
        return Some(Parting::Event(k));
    }
    if old.len() != new.len() {
        return Some(Parting::Event(old.len().min(new.len())));
    }
    ((a.block, a.stage) != (b.block, b.stage)).then_some(Parting::State)
}

/// A product state: how it was first reached.
#[derive(Debug, Clone)]
pub struct Node {
    pub depth: usize,
    pub parent: Option<(usize, Move)>,
}

/// The outcome of the walk.
#[derive(Debug, Clone, Default)]
pub struct Walk {
    pub nodes: Vec<Node>,
    pub transitions: usize,
    /// Every reachable pair was expanded and every transition agreed.
    pub fixpoint: bool,
    /// A budget that cut the walk.
    pub cut: Option<String>,
    /// The first transition that differs: its node and move.
    pub found: Option<(usize, Move)>,
}

impl Walk {
    /// The moves from the initial pair to `node`.
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

type Key = (ViewKey, ViewKey);

/// Walks the product breadth first; stops at the first transition that differs.
pub fn walk<'a, 'b>(
    old: &mut Side<'a>,
    new: &mut Side<'b>,
    operator_jumps: bool,
) -> Result<Walk, StepError> {
    let (s1, s2) = (old.space.initial(), new.space.initial());
    let mut out = Walk::default();
    let mut index: HashMap<Key, usize> =
        HashMap::from([((old.space.key(&s1), new.space.key(&s2)), 0)]);
    out.nodes.push(Node { depth: 0, parent: None });
    let mut queue = VecDeque::from([(0usize, s1, s2)]);
    let blocks = old.interp.fp().blocks.len().max(new.interp.fp().blocks.len());
    let max_states = old.space.opts.max_states;
    while let Some((id, s1, s2)) = queue.pop_front() {
        let depth = out.nodes[id].depth;
        let mut next: Vec<(Move, State<'a>, State<'b>)> = Vec::new();
        let (paths, cut) = old.space.successors(&s1)?;
        if cut {
            out.cut =
                Some(format!("more than {} paths in one call", old.space.opts.max_paths_per_call));
        }
        for p in paths {
            out.transitions += 1;
            let Move::Call(answers) = &p.mv else { continue };
            let (events, after, consumed) = new.call(&s2, answers)?;
            let (a, b) = (old.seen(&p.events), new.seen(&events));
            if parting(&a, &b, p.after, after).is_some() || consumed != answers.len() {
                out.found = Some((id, p.mv));
                return Ok(out);
            }
            next.push((p.mv, p.state, new.interp.state.clone()));
        }
        if operator_jumps {
            for b in 0..blocks {
                out.transitions += 1;
                let (e1, a1) = old.jump(&s1, b);
                let (e2, a2) = new.jump(&s2, b);
                let (x, y) = (old.seen(&e1), new.seen(&e2));
                if parting(&x, &y, a1, a2).is_some() {
                    out.found = Some((id, Move::Jump(b)));
                    return Ok(out);
                }
                next.push((Move::Jump(b), old.interp.state.clone(), new.interp.state.clone()));
            }
        }
        for (mv, t1, t2) in next {
            let k = (old.space.key(&t1), new.space.key(&t2));
            if index.contains_key(&k) {
                continue;
            }
            if out.nodes.len() >= max_states {
                out.cut = Some(format!("more than {max_states} state pairs"));
                continue;
            }
            index.insert(k, out.nodes.len());
            out.nodes.push(Node { depth: depth + 1, parent: Some((id, mv)) });
            queue.push_back((out.nodes.len() - 1, t1, t2));
        }
    }
    out.fixpoint = out.cut.is_none();
    Ok(out)
}
