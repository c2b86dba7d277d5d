//! Static bound on the work of one `auto_nav` call: how many stage items it can execute and how
//! many external events (conditions evaluated, C code run, integer values read) it can produce,
//! per starting block and for the whole plan.
//!
//! Why it is finite: inside one call, control only moves *forward* through a block's stage list
//! except at a loop-back, which goes to its loop test; the test either ends the call (entering
//! the body is a `NextStageAndBreak`) or jumps *past* the loop-back. So the "continue" edges
//! form an acyclic graph, and the bound is its longest path, plus the exceptions tested before
//! the stages and the hooks run by one block change. Every quantity is an upper bound (all
//! code lines of a navigation stage are counted even where they are alternatives).

use serde::Serialize;

use crate::passes::fp::{Fp, FpStage, NavStage};

/// The bound for calls that start in one block.
#[derive(Debug, Clone, Serialize)]
pub struct BlockBound {
    pub block: usize,
    pub name: String,
    /// Stage items executed (each `Stage(k)` case entered counts one).
    pub stages: usize,
    /// External events (conditions, code, values) of one call.
    pub events: usize,
}

/// The bound of every block, and the largest ones.
#[derive(Debug, Clone, Serialize)]
pub struct PlanBound {
    pub blocks: Vec<BlockBound>,
    pub max_stages: usize,
    pub max_events: usize,
}

impl PlanBound {
    /// One line per block: number, name, stage items and events of one call.
    pub fn render(&self) -> String {
        self.blocks
            .iter()
            .map(|b| {
                format!(
                    "  {:>3} {:<30} stages <= {:>3}  events <= {:>4}\n",
                    b.block, b.name, b.stages, b.events
                )
            })
            .collect()
    }
}

/// One stage item of the flattened block, with the events it may produce and its in-call
/// successors.
#[derive(Debug, Clone)]
struct Item {
    events: usize,
    /// Successor item executed in the same call, if the item can continue.
    next: Vec<usize>,
}

struct Costs {
    /// Worst cost of a block change (forbidden checks, exit and enter hooks).
    change: usize,
    /// Worst cost of `Return` (exit + enter hooks).
    ret: usize,
}

fn nav_events(n: &NavStage) -> usize {
    let opt = |o: &Option<crate::passes::fp::Code>| usize::from(o.is_some());
    opt(&n.pre_call)
        + n.before.len()
        + usize::from(n.approach.is_some())
        + n.lines.len()
        + usize::from(n.until.is_some())
        // post_call can run in the approach branch or the until branch or at the end: once.
        + opt(&n.post_call)
}

/// Flattens a stage list; `after` is the item that follows the list (its continuation).
fn flatten(stages: &[FpStage], items: &mut Vec<Item>, c: &Costs) {
    for s in stages {
        let me = items.len();
        match s {
            FpStage::Set { .. } => items.push(Item { events: 1, next: vec![me + 1] }),
            FpStage::Call { loop_: true, until, .. } => {
                items.push(Item { events: 1 + usize::from(until.is_some()), next: vec![me + 1] })
            }
            FpStage::Call { loop_: false, .. } => {
                items.push(Item { events: 1, next: vec![me + 1] })
            }
            FpStage::Deroute { .. } => items.push(Item { events: c.change, next: vec![] }),
            FpStage::Return { .. } => items.push(Item { events: c.ret, next: vec![] }),
            FpStage::Nav(n) => {
                if let Some(init) = &n.init {
                    items.push(Item { events: init.len(), next: vec![] });
                }
                items.push(Item { events: nav_events(n), next: vec![] });
            }
            FpStage::While { body, .. } => {
                items.push(Item { events: 1, next: vec![] });
                flatten(body, items, c);
                let back = items.len();
                items.push(Item { events: 0, next: vec![me] });
                // the test continues only past its loop-back
                items[me].next = vec![back + 1];
            }
            FpStage::For { body, .. } => {
                // init (two values), then the test
                items.push(Item { events: 2, next: vec![me + 1] });
                items.push(Item { events: 0, next: vec![] });
                flatten(body, items, c);
                let back = items.len();
                items.push(Item { events: 0, next: vec![me + 1] });
                items[me + 1].next = vec![back + 1];
            }
        }
    }
}

/// Longest path (items, events) from every item; the graph is acyclic (module comment).
fn longest(items: &[Item]) -> Vec<(usize, usize)> {
    let mut memo: Vec<Option<(usize, usize)>> = vec![None; items.len()];
    fn go(
        i: usize,
        items: &[Item],
        memo: &mut Vec<Option<(usize, usize)>>,
        guard: usize,
    ) -> (usize, usize) {
        if let Some(v) = memo[i] {
            return v;
        }
        // `guard` bounds the recursion depth even if the acyclicity argument were wrong.
        let mut best = (0, 0);
        if guard > 0 {
            for &j in &items[i].next {
                if j < items.len() {
                    let (s, e) = go(j, items, memo, guard - 1);
                    best = (best.0.max(s), best.1.max(e));
                }
            }
        }
        let v = (1 + best.0, items[i].events + best.1);
        memo[i] = Some(v);
        v
    }
    (0..items.len()).map(|i| go(i, items, &mut memo, 2 * items.len() + 2)).collect()
}

/// Computes the bound of every block of `fp`.
pub fn bound(fp: &Fp) -> PlanBound {
    let max_enter = fp.blocks.iter().map(|b| usize::from(b.on_enter.is_some())).max().unwrap_or(0);
    let exc_exec = |l: &[crate::passes::fp::FpException]| {
        l.iter().map(|e| usize::from(e.exec.is_some())).max().unwrap_or(0)
    };
    let mut blocks = Vec::new();
    for (bi, b) in fp.blocks.iter().enumerate() {
        let forbidden_checks =
            fp.forbidden.iter().filter(|f| f.from == bi && f.only_when.is_some()).count();
        let exit = usize::from(b.on_exit.is_some());
        let costs = Costs { change: forbidden_checks + exit + max_enter, ret: exit + max_enter };
        let mut items = Vec::new();
        flatten(&b.stages, &mut items, &costs);
        // the default stage: NextBlock
        items.push(Item { events: costs.change, next: vec![] });
        let paths = longest(&items);
        let (stages, stage_events) = paths.iter().fold((0, 0), |a, p| (a.0.max(p.0), a.1.max(p.1)));
        // Exceptions: every condition tested, then at most one fires (exec + block change)
        // and ends the call; otherwise pre_call, the stages and post_call run.
        let conds = fp.exceptions.len() + b.exceptions.len();
        let fire = exc_exec(&fp.exceptions).max(exc_exec(&b.exceptions)) + costs.change;
        let pre = usize::from(b.pre_call.is_some());
        let post = usize::from(b.post_call.is_some());
        let events = conds + (fire.max(stage_events + post)) + pre;
        blocks.push(BlockBound { block: bi, name: b.name.clone(), stages, events });
    }
    let max_stages = blocks.iter().map(|b| b.stages).max().unwrap_or(0);
    let max_events = blocks.iter().map(|b| b.events).max().unwrap_or(0);
    PlanBound { blocks, max_stages, max_events }
}
