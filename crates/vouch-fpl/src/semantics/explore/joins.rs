//! Join points of one call: the interpreter records its state at every stage start (the C's
//! `Stage(n)` label), and [`super::enumerate_joined`] stops a run that reaches a stage start in
//! a state an earlier run of the same call reached there. The C side does the same through
//! `c/explore_join.h`, so the two graphs of a call can be compared.

use std::collections::HashMap;
use std::hash::Hash;

use super::super::trace::Event;
use super::super::{Interp, State};
use super::asks;

/// The state when a stage starts within a call (the C's `Stage(n)` label), and how many
/// events the call had produced before it.
#[derive(Debug, Clone)]
pub struct StageStart<'p> {
    pub events: usize,
    pub state: State<'p>,
}

impl<'p> Interp<'p> {
    /// From now on, remember the state at every stage start of a call (read with
    /// [`Interp::stage_starts`]); the exploration of one call joins paths there.
    pub fn record_stage_starts(&mut self) {
        self.starts = Some(Vec::new());
    }

    /// The stage starts of the last call (empty unless recorded).
    pub fn stage_starts(&self) -> &[StageStart<'p>] {
        self.starts.as_deref().unwrap_or(&[])
    }

    /// A call begins: the previous call's stage starts are forgotten.
    pub(crate) fn clear_stage_starts(&mut self) {
        if let Some(st) = &mut self.starts {
            st.clear();
        }
    }

    /// The current state starts a stage, after `events` events of the call (when recorded).
    pub(crate) fn note_stage_start(&mut self, events: usize) {
        if let Some(st) = &mut self.starts {
            st.push(StageStart { events, state: self.state.clone() });
        }
    }
}

/// Where a run ends: the end of the call, or a join point (its index in the stage starts,
/// the node, the answers consumed before it).
pub(super) enum End {
    Call,
    Join(usize, usize, usize),
}

/// The join points a run passes and where it ends (see [`super::enumerate_joined`]).
pub(super) fn join_points<'p, K: Eq + Hash>(
    interp: &Interp<'p>,
    events: &[Event],
    prefix_len: usize,
    key: &dyn Fn(&State<'p>) -> K,
    nodes: &mut HashMap<K, usize>,
) -> (Vec<usize>, End) {
    let mut passed = Vec::new();
    let (mut asked, mut seen) = (0, 0);
    for (i, start) in interp.stage_starts().iter().enumerate() {
        asked += events[seen..start.events].iter().filter(|e| asks(e)).count();
        seen = start.events;
        let k = key(&start.state);
        if asked < prefix_len {
            // replaying the prefix: an earlier run of this prefix registered the point
            passed.extend(nodes.get(&k).copied());
            continue;
        }
        if let Some(&node) = nodes.get(&k) {
            return (passed, End::Join(i, node, asked));
        }
        let node = nodes.len();
        nodes.insert(k, node);
        passed.push(node);
    }
    (passed, End::Call)
}
