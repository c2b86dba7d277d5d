//! The C state as the validator sees it: which registered variable is which, the C side of the
//! state view (the same parts dropped as in [`crate::semantics::space`]), the perturbed copy
//! of a state (every dropped part changed) and the rule a run from that copy must follow.

use std::collections::HashMap;

use crate::evidence::cdriver::Driver;
use crate::evidence::cstate::Kind;
use crate::passes::fp::{BlockIx, Fp, FpStage};
use crate::semantics::space::{LoopClass, Space, iterations_left, loop_class};
use crate::semantics::{Interp, Item, State};

/// One variable of the C state view.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Part {
    Bytes(Vec<u8>),
    Class(LoopClass),
    Dropped,
}

/// The C state view: one part per registered variable.
pub(super) type CKey = Vec<Part>;

/// How a dropped variable was changed in the perturbed copy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Change {
    /// Bits flipped.
    Flipped,
    /// A live counter pair of a loop with a non-literal bound, both shifted by this much (the
    /// counter alone when the loop is endless): the same number of iterations left.
    Shifted(u8),
}

/// The registered variables, classified.
pub(super) struct Vars {
    pub names: Vec<String>,
    pub kinds: Vec<Kind>,
    /// Variable ids of the runtime's block, stage, last block, last stage, last waypoint.
    pub runtime: [usize; 5],
    /// Counter variable id → (loop (block, init stage), is the bound).
    counters: HashMap<usize, ((BlockIx, usize), bool)>,
    /// Loop → (counter id, bound id).
    pairs: HashMap<(BlockIx, usize), (usize, usize)>,
    /// Every counter variable: (id, block, init stage, loop-back stage): the stages inside
    /// the loop are those after its init up to its loop-back.
    pub ranges: Vec<[usize; 4]>,
}

fn loops_of<'p>(
    interp: &Interp<'p>,
    block: BlockIx,
    stages: &'p [FpStage],
    out: &mut HashMap<(BlockIx, String), (usize, usize)>,
) {
    for s in stages {
        match s {
            FpStage::For { var, body, .. } => {
                let range =
                    (interp.item_number(&Item::Stage(s)), interp.item_number(&Item::LoopBack(s)));
                out.insert((block, var.clone()), range);
                loops_of(interp, block, body, out);
            }
            FpStage::While { body, .. } => loops_of(interp, block, body, out),
            _ => {}
        }
    }
}

impl Vars {
    /// Classifies the driver's variables against the plan; `None` names a runtime global the
    /// stub must declare and does not.
    pub fn new(driver: &Driver, fp: &Fp, interp: &Interp<'_>) -> Result<Vars, &'static str> {
        let vars = &driver.discovery.vars;
        let find = |k: Kind, name: &'static str| {
            vars.iter().find(|v| v.runtime && v.kind == k).map(|v| v.id).ok_or(name)
        };
        let runtime = [
            find(Kind::Block, "nav_block")?,
            find(Kind::Stage, "nav_stage")?,
            find(Kind::LastBlock, "last_block")?,
            find(Kind::LastStage, "last_stage")?,
            find(Kind::LastWp, "last_wp")?,
        ];
        let mut loops = HashMap::new();
        for (b, block) in fp.blocks.iter().enumerate() {
            loops_of(interp, b, &block.stages, &mut loops);
        }
        let mut counters = HashMap::new();
        let mut pairs: HashMap<(BlockIx, usize), (Option<usize>, Option<usize>)> = HashMap::new();
        let mut ranges = Vec::new();
        for v in vars {
            if let Kind::Counter { block, var, bound } = &v.kind
                && let Some(&(stage, back)) = loops.get(&(*block, var.clone()))
            {
                ranges.push([v.id, *block, stage, back]);
                counters.insert(v.id, ((*block, stage), *bound));
                let e = pairs.entry((*block, stage)).or_default();
                if *bound {
                    e.1 = Some(v.id);
                } else {
                    e.0 = Some(v.id);
                }
            }
        }
        let pairs = pairs.into_iter().filter_map(|(k, (a, b))| Some((k, (a?, b?)))).collect();
        Ok(Vars {
            names: vars.iter().map(|v| v.name.clone()).collect(),
            kinds: vars.iter().map(|v| v.kind.clone()).collect(),
            runtime,
            counters,
            pairs,
            ranges,
        })
    }

    /// The loop a counter variable belongs to, when the plan has it.
    pub fn loop_of(&self, id: usize) -> Option<(BlockIx, usize)> {
        self.counters.get(&id).map(|c| c.0)
    }

    /// The C counter pair of a loop: (counter, bound) variable ids.
    pub fn pair(&self, l: (BlockIx, usize)) -> Option<(usize, usize)> {
        self.pairs.get(&l).copied()
    }

    /// Whether the view drops variable `id` in a state whose live loops are `live`.
    fn dropped(&self, id: usize, live: &[(BlockIx, usize)], space: &Space<'_>) -> bool {
        if space.abstraction.exact {
            return false;
        }
        let has_return = space.abstraction.has_return;
        match &self.kinds[id] {
            Kind::LastWp => true,
            Kind::LastBlock | Kind::LastStage => !has_return,
            Kind::Counter { .. } => self.loop_of(id).is_some_and(|l| !live.contains(&l)),
            _ => false,
        }
    }
}

fn byte(driver: &Driver, state: &[u8], id: usize) -> u8 {
    driver.var_bytes(state, id).first().copied().unwrap_or(0)
}

/// The C view of `state`, beside the interpreter state `at` (whose live loops decide which
/// counters count).
pub(super) fn key(
    vars: &Vars,
    driver: &Driver,
    space: &Space<'_>,
    at: &State<'_>,
    state: &[u8],
) -> CKey {
    let live = space.live_loops(at);
    (0..vars.names.len())
        .map(|id| {
            if vars.dropped(id, &live, space) {
                return Part::Dropped;
            }
            if let Some(l) = vars.loop_of(id).filter(|l| space.is_symbolic(*l))
                && let Some((v, t)) = vars.pair(l)
            {
                let v = byte(driver, state, v) as i8;
                let t = byte(driver, state, t) as i8;
                return Part::Class(loop_class(v, t));
            }
            Part::Bytes(driver.var_bytes(state, id).to_vec())
        })
        .collect()
}

/// A copy of a C state with parts the view drops changed, and what was changed.
#[derive(Debug, Clone)]
pub(super) struct Copy {
    pub bytes: Vec<u8>,
    pub changes: Vec<Option<Change>>,
}

impl Copy {
    fn new(state: &[u8], n: usize) -> Copy {
        Copy { bytes: state.to_vec(), changes: vec![None; n] }
    }

    fn set(&mut self, driver: &Driver, id: usize, f: &dyn Fn(u8) -> u8, c: Change) {
        if let (Some(&a), Some(&b)) = (driver.offsets.get(id), driver.offsets.get(id + 1)) {
            let end = b.min(self.bytes.len());
            for x in &mut self.bytes[a.min(end)..end] {
                *x = f(*x);
            }
            self.changes[id] = Some(c);
        }
    }
}

/// The copies every run from `state` is repeated from: one with every dead part changed (bits
/// flipped), then, for each live counter pair of a loop with a non-literal bound, one per
/// shift of the pair that keeps the iterations left (the counter alone when the loop is
/// endless) and one per other bound of the same class. So within a class the C is run with
/// every value of the counter and of the bound (each varied alone).
pub(super) fn copies(
    vars: &Vars,
    driver: &Driver,
    space: &Space<'_>,
    at: &State<'_>,
    state: &[u8],
) -> Vec<Copy> {
    let live = space.live_loops(at);
    let n = vars.names.len();
    let mut out = Vec::new();
    let mut dead = Copy::new(state, n);
    for id in 0..n {
        if vars.dropped(id, &live, space) {
            dead.set(driver, id, &|x| x ^ 0x55, Change::Flipped);
        }
    }
    if dead.changes.iter().any(Option::is_some) {
        out.push(dead);
    }
    for l in live.iter().filter(|l| space.is_symbolic(**l)) {
        let Some((vi, ti)) = vars.pair(*l) else { continue };
        let (v, t) = (byte(driver, state, vi) as i8, byte(driver, state, ti) as i8);
        let left = iterations_left(v, t);
        for d in (-255i16..=255).filter(|d| *d != 0) {
            let Ok(d) = i8::try_from(d) else { continue };
            let keeps = |v2: Option<i8>, t2: Option<i8>| matches!((v2, t2), (Some(v2), Some(t2)) if iterations_left(v2, t2) == left);
            let c = Change::Shifted(d as u8);
            // the pair shifted together (an endless loop stays endless whatever its counter)
            let t2 = if left.is_none() { Some(t) } else { t.checked_add(d) };
            if keeps(v.checked_add(d), t2) {
                let mut copy = Copy::new(state, n);
                copy.set(driver, vi, &|x| x.wrapping_add(d as u8), c);
                if left.is_some() {
                    copy.set(driver, ti, &|x| x.wrapping_add(d as u8), c);
                }
                out.push(copy);
            }
            // the bound alone, in the same class
            if left.is_some()
                && t.checked_add(d).is_some_and(|t2| loop_class(v, t2) == loop_class(v, t))
            {
                let mut copy = Copy::new(state, n);
                copy.set(driver, ti, &|x| x.wrapping_add(d as u8), c);
                out.push(copy);
            }
        }
    }
    out
}

/// Checks the run from the perturbed copy against the run from the state: every variable the
/// copy did not change ends equal; a changed one ends overwritten with the same value, kept as
/// it was in each run, or (a shifted counter) still shifted. The first variable breaking
/// this, if any.
#[allow(clippy::too_many_arguments)]
pub(super) fn second_ok(
    vars: &Vars,
    driver: &Driver,
    changes: &[Option<Change>],
    state: &[u8],
    copy: &[u8],
    after: &[u8],
    after2: &[u8],
) -> Option<usize> {
    (0..vars.names.len()).find(|&id| {
        let (s, s2) = (driver.var_bytes(state, id), driver.var_bytes(copy, id));
        let (a, a2) = (driver.var_bytes(after, id), driver.var_bytes(after2, id));
        let ok = match changes[id] {
            None => a == a2,
            Some(c) => {
                let shifted = match c {
                    Change::Shifted(d) => a.iter().zip(a2).all(|(x, y)| x.wrapping_add(d) == *y),
                    Change::Flipped => false,
                };
                a == a2 || (a == s && a2 == s2) || shifted
            }
        };
        !ok
    })
}
