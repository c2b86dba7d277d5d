//! Reference semantics of FPL: the executable definition that the compiled C is tested
//! against. It follows the VFPG paper's big-step rules (IR-1..IR-9) over the FP structure
//! ([`crate::passes::fp`]), extended to every stage kind, with the Paparazzi 2024-10 runtime
//! behaviour for block changes (GENERATOR_FACTS.md section 5).
//!
//! State (Definition 1): current block and *remaining stages* (a continuation: a stack of
//! [`Item`]s), last block and last remaining stages, plus the `for` counters (`int8_t` in C).
//! Trace (Definition 2): [`trace::Event`]s. Conditions and non-literal values come from an
//! [`oracle::Oracle`] (the paper's `evalc`).
//!
//! Stage numbers are computed here from the FP structure with upstream's counting rule,
//! independently of [`crate::passes::extend`], so the differential test also checks the
//! numbering the emitter uses.
//!
//! **Totality.** [`Interp::step`] runs a loop over the remaining stages. Every iteration either
//! ends the call (a *break* stage, a block change, an exception) or moves to a later stage,
//! except a loop-back (`END_WHILE`/`END_FOR`), which goes to its loop test; a loop test either
//! ends the call or jumps past its own loop-back. So each stage of the block is visited at most
//! twice per call, and the loop is bounded by `2 * stages + 2` iterations. The bound is also
//! enforced ([`StepError::Diverged`]), so `step` terminates even if that argument were wrong.
//!
//! One stage within a call (IR-5…IR-9) is in `stage.rs`; the record of the states at stage
//! starts, where the exploration of a call joins its runs, in [`explore::joins`].

pub mod explore;
pub mod oracle;
pub mod sim;
pub mod space;
mod stage;
pub mod trace;

use std::collections::HashMap;

use crate::ast::Resume;
use crate::passes::fp::{BlockIx, Code, Fp, FpStage, Reset};
pub use explore::joins::StageStart;
use oracle::Oracle;
use stage::Flow;
use trace::{Event, Observation, Run, StepRecord};

/// A position in the remaining stages of a block.
#[derive(Debug, Clone, Copy)]
pub enum Item<'p> {
    /// A source stage not started yet (for two-step navigation stages: its init step, IR-9).
    Stage(&'p FpStage),
    /// The test of a `for` loop (after its init).
    ForTest(&'p FpStage),
    /// The loop-back stage after a `while`/`for` body.
    LoopBack(&'p FpStage),
    /// The main step of a two-step navigation stage (IR-9 turned `init` to false).
    NavMain(&'p FpStage),
}

/// Why the interpreter stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error, miette::Diagnostic)]
pub enum StepError {
    /// The in-call loop exceeded its bound (a defect of the interpreter: see the module
    /// documentation); the plan itself is not at fault.
    #[error("the reference interpreter exceeded its per-call bound in block {block}")]
    #[diagnostic(
        code(fpl::E040),
        help(
            "one call visits each stage at most twice; exceeding 2 × stages + 2 iterations is a defect of the interpreter"
        )
    )]
    Diverged {
        /// The block the call ran in.
        block: usize,
    },
}

#[derive(Debug, Clone)]
pub struct State<'p> {
    pub block: BlockIx,
    /// Remaining stages, top of the stack = next to run.
    pub remaining: Vec<Item<'p>>,
    pub last_block: BlockIx,
    pub last_remaining: Vec<Item<'p>>,
    /// `for` counters (`_var_v`, `_var_v_to`) keyed by (block, init stage number).
    pub counters: HashMap<(BlockIx, usize), (i8, i8)>,
    /// The waypoint a `go` stage remembers when it is reached (the runtime's `last_wp`,
    /// `NextStageAndBreakFrom`); it steers nothing in the plan, the firmware reads it.
    pub last_wp: usize,
}

/// The interpreter of one plan.
pub struct Interp<'p> {
    fp: &'p Fp,
    /// First stage number of every stage (keyed by address: stages never move).
    first: HashMap<*const FpStage, usize>,
    /// Number of the default stage of each block.
    ends: Vec<usize>,
    pub state: State<'p>,
    calls: usize,
    /// Set while an operator block change runs (it bypasses forbidden deroutes).
    forbidden_off: bool,
    /// Where the events of the last call came from, when recorded ([`Interp::record_origins`]).
    origins: Option<Vec<Origin>>,
    /// The state at every stage start of the last call, when recorded
    /// ([`Interp::record_stage_starts`]).
    starts: Option<Vec<StageStart<'p>>>,
}

/// The source of a call's events from `first_event` on (until the next origin): the stage,
/// exception or block whose code produced them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Origin {
    pub first_event: usize,
    pub span: crate::span::Span,
}

/// Number of stage slots a stage uses (GENERATOR_FACTS.md section 6).
fn slots(s: &FpStage) -> usize {
    match s {
        FpStage::While { body, .. } => 1 + body.iter().map(slots).sum::<usize>() + 1,
        FpStage::For { body, .. } => 2 + body.iter().map(slots).sum::<usize>() + 1,
        FpStage::Nav(n) if n.init.is_some() => 2,
        _ => 1,
    }
}

fn number_stages(stages: &[FpStage], next: &mut usize, first: &mut HashMap<*const FpStage, usize>) {
    for s in stages {
        first.insert(s as *const FpStage, *next);
        match s {
            FpStage::While { body, .. } => {
                *next += 1;
                number_stages(body, next, first);
                *next += 1;
            }
            FpStage::For { body, .. } => {
                *next += 2;
                number_stages(body, next, first);
                *next += 1;
            }
            other => *next += slots(other),
        }
    }
}

fn push_list<'p>(stack: &mut Vec<Item<'p>>, stages: &'p [FpStage]) {
    for s in stages.iter().rev() {
        stack.push(Item::Stage(s));
    }
}

impl<'p> Interp<'p> {
    /// The initial environment `e0`: block 0, all its stages, last position (0, stage 0).
    pub fn new(fp: &'p Fp) -> Self {
        let mut first = HashMap::new();
        let mut ends = Vec::with_capacity(fp.blocks.len());
        for b in &fp.blocks {
            let mut next = 0;
            number_stages(&b.stages, &mut next, &mut first);
            ends.push(next);
        }
        let full0 = Self::full_of(fp, 0);
        let state = State {
            block: 0,
            remaining: full0.clone(),
            last_block: 0,
            last_remaining: full0,
            counters: HashMap::new(),
            last_wp: 0,
        };
        Interp {
            fp,
            first,
            ends,
            state,
            calls: 0,
            forbidden_off: false,
            origins: None,
            starts: None,
        }
    }

    fn full_of(fp: &'p Fp, block: BlockIx) -> Vec<Item<'p>> {
        let mut v = Vec::new();
        if let Some(b) = fp.blocks.get(block) {
            push_list(&mut v, &b.stages);
        }
        v
    }

    /// The plan this interpreter runs.
    pub fn fp(&self) -> &'p Fp {
        self.fp
    }

    /// From now on, remember which stage, exception or block produced each event of a call
    /// (read with [`Interp::origins`]); used to locate differences in the plan's files.
    pub fn record_origins(&mut self) {
        self.origins = Some(Vec::new());
    }

    /// The origins of the events of the last call (empty unless recorded).
    pub fn origins(&self) -> &[Origin] {
        self.origins.as_deref().unwrap_or(&[])
    }

    fn mark(&mut self, first_event: usize, span: crate::span::Span) {
        if let Some(o) = &mut self.origins {
            o.push(Origin { first_event, span });
        }
    }

    /// Events of `auto_nav_init()`.
    pub fn init_events(&self) -> Vec<Event> {
        self.fp.init.iter().map(|c| Event::Code { text: c.text.clone() }).collect()
    }

    /// The C stage number at which `item` resumes (what `nav_stage` holds when it is next).
    pub fn item_number(&self, item: &Item<'p>) -> usize {
        let key = |s: &&FpStage| *s as *const FpStage;
        match item {
            Item::Stage(s) => self.first.get(&key(s)).copied().unwrap_or(0),
            Item::ForTest(s) | Item::NavMain(s) => {
                self.first.get(&key(s)).copied().unwrap_or(0) + 1
            }
            Item::LoopBack(s) => self.first.get(&key(s)).copied().unwrap_or(0) + slots(s) - 1,
        }
    }

    fn stage_number(&self, block: BlockIx, remaining: &[Item<'p>]) -> usize {
        match remaining.last() {
            Some(top) => self.item_number(top),
            None => self.ends.get(block).copied().unwrap_or(0),
        }
    }

    /// The C-visible state: `nav_block`, `nav_stage`, `last_block`, `last_stage`.
    pub fn observe(&self) -> Observation {
        self.observe_state(&self.state)
    }

    /// The C-visible part of any state of this plan.
    pub fn observe_state(&self, s: &State<'p>) -> Observation {
        Observation {
            block: s.block,
            stage: self.stage_number(s.block, &s.remaining),
            last_block: s.last_block,
            last_stage: self.stage_number(s.last_block, &s.last_remaining),
        }
    }

    fn code(ev: &mut Vec<Event>, c: &Code) {
        ev.push(Event::Code { text: c.text.clone() });
    }

    fn cond(ev: &mut Vec<Event>, oracle: &mut dyn Oracle, text: &str) -> bool {
        let value = oracle.cond(text);
        ev.push(Event::Cond { text: text.to_string(), value });
        value
    }

    /// VFPG forbidden deroutes: the first matching entry whose `only_when` holds forbids.
    fn forbidden(
        &self,
        ev: &mut Vec<Event>,
        oracle: &mut dyn Oracle,
        from: BlockIx,
        to: BlockIx,
    ) -> bool {
        if self.forbidden_off {
            return false;
        }
        for f in &self.fp.forbidden {
            if f.from == from && f.to == to {
                match &f.only_when {
                    None => return true,
                    Some(c) => {
                        if Self::cond(ev, oracle, c) {
                            return true;
                        }
                    }
                }
            }
        }
        false
    }

    /// `goto_block` (2024-10 `nav_goto_block`): remembers the position only on a real change,
    /// runs the exit hook of the old block, then initialises the new one (stage 0, enter hook).
    fn goto_block(&mut self, ev: &mut Vec<Event>, oracle: &mut dyn Oracle, target: BlockIx) {
        if self.forbidden(ev, oracle, self.state.block, target) {
            return;
        }
        if target != self.state.block {
            self.state.last_block = self.state.block;
            self.state.last_remaining = self.state.remaining.clone();
        }
        if let Some(c) = self.fp.blocks.get(self.state.block).and_then(|b| b.on_exit.as_ref()) {
            Self::code(ev, c);
        }
        let nb = self.fp.blocks.len();
        let target = target.min(nb.saturating_sub(1));
        self.state.block = target;
        self.state.remaining = Self::full_of(self.fp, target);
        if let Some(c) = self.fp.blocks.get(target).and_then(|b| b.on_enter.as_ref()) {
            Self::code(ev, c);
        }
    }

    /// `Return(x)`: back to the last position (stage 0 when `x` is 1); last is not updated.
    fn do_return(&mut self, ev: &mut Vec<Event>, reset: &Reset) {
        if let Some(c) = self.fp.blocks.get(self.state.block).and_then(|b| b.on_exit.as_ref()) {
            Self::code(ev, c);
        }
        self.state.block = self.state.last_block;
        self.state.remaining = match reset.resume {
            Resume::FirstStage => Self::full_of(self.fp, self.state.last_block),
            Resume::SavedStage => self.state.last_remaining.clone(),
        };
        if let Some(c) = self.fp.blocks.get(self.state.block).and_then(|b| b.on_enter.as_ref()) {
            Self::code(ev, c);
        }
    }

    /// Exceptions (IR-1/IR-2): `true` when one was raised (the call ends).
    fn exceptions(
        &mut self,
        ev: &mut Vec<Event>,
        oracle: &mut dyn Oracle,
        list: &'p [crate::passes::fp::FpException],
    ) -> bool {
        for e in list {
            self.mark(ev.len(), e.span);
            if self.state.block != e.target && Self::cond(ev, oracle, &e.cond) {
                if let Some(x) = &e.exec {
                    Self::code(ev, x);
                }
                self.goto_block(ev, oracle, e.target);
                return true;
            }
        }
        false
    }

    /// One `auto_nav()` call.
    pub fn step(&mut self, oracle: &mut dyn Oracle) -> Result<StepRecord, StepError> {
        self.calls += 1;
        let before = self.observe();
        let mut ev = Vec::new();
        if let Some(o) = &mut self.origins {
            o.clear();
        }
        self.clear_stage_starts();
        let fp = self.fp;
        if !self.exceptions(&mut ev, oracle, &fp.exceptions) {
            let b = self.state.block;
            // Every lowered plan has at least the HOME block; a hand-built empty one does nothing.
            let Some(block) = fp.blocks.get(b) else {
                return Ok(StepRecord {
                    call: self.calls,
                    operator_gotos: Vec::new(),
                    before,
                    events: ev,
                    after: self.observe(),
                });
            };
            if let Some(c) = &block.pre_call {
                self.mark(ev.len(), block.span);
                Self::code(&mut ev, c);
            }
            if !self.exceptions(&mut ev, oracle, &block.exceptions) {
                self.run_stages(&mut ev, oracle, b)?;
                if let Some(c) = &block.post_call {
                    self.mark(ev.len(), block.span);
                    Self::code(&mut ev, c);
                }
            }
        }
        Ok(StepRecord {
            call: self.calls,
            operator_gotos: Vec::new(),
            before,
            events: ev,
            after: self.observe(),
        })
    }

    /// An operator block change between two calls (the ground station's "go to block", which
    /// calls the runtime's `nav_goto_block` directly: no forbidden-deroute check).
    pub fn operator_goto(&mut self, block: BlockIx) -> Vec<Event> {
        let mut ev = Vec::new();
        let saved = std::mem::take(&mut self.forbidden_off);
        self.forbidden_off = true;
        let mut none = oracle::Scripted::default();
        self.goto_block(&mut ev, &mut none, block);
        self.forbidden_off = saved;
        ev
    }

    /// Runs `n` calls; `jumps` lists (call number, block) operator block changes applied just
    /// before that call (several before one call run in their order).
    pub fn run_with_jumps(
        &mut self,
        oracle: &mut dyn Oracle,
        n: usize,
        jumps: &[(usize, usize)],
    ) -> Result<Run, StepError> {
        let mut run = Run {
            init: if self.calls == 0 { self.init_events() } else { Vec::new() },
            steps: Vec::new(),
        };
        for _ in 0..n {
            let call = self.calls + 1;
            let ops: Vec<(usize, Vec<Event>)> = jumps
                .iter()
                .filter(|(c, _)| *c == call)
                .map(|&(_, b)| (b, self.operator_goto(b)))
                .collect();
            let mut rec = self.step(oracle)?;
            rec.operator_gotos = ops;
            run.steps.push(rec);
        }
        Ok(run)
    }

    /// Runs `n` calls from the current state.
    pub fn run(&mut self, oracle: &mut dyn Oracle, n: usize) -> Result<Run, StepError> {
        let mut run = Run {
            init: if self.calls == 0 { self.init_events() } else { Vec::new() },
            steps: Vec::new(),
        };
        for _ in 0..n {
            run.steps.push(self.step(oracle)?);
        }
        Ok(run)
    }

    fn run_stages(
        &mut self,
        ev: &mut Vec<Event>,
        oracle: &mut dyn Oracle,
        b: BlockIx,
    ) -> Result<(), StepError> {
        let bound = 2 * self.ends.get(b).copied().unwrap_or(0) + 2;
        for _ in 0..bound {
            self.note_stage_start(ev.len());
            let Some(top) = self.state.remaining.last().copied() else {
                // IR-3 / IR-4: no stage left, next block (the last block re-enters itself).
                let nb = self.fp.blocks.len();
                let next = if b + 1 < nb { b + 1 } else { b };
                self.goto_block(ev, oracle, next);
                return Ok(());
            };
            let span = match top {
                Item::Stage(s) | Item::ForTest(s) | Item::LoopBack(s) | Item::NavMain(s) => {
                    s.span()
                }
            };
            self.mark(ev.len(), span);
            match self.exec(ev, oracle, b, top) {
                Flow::Continue => {}
                Flow::Break => return Ok(()),
            }
        }
        Err(StepError::Diverged { block: b })
    }
}
