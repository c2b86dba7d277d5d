//! One stage of the remaining stages run within a call: the rules IR-5…IR-9 (sets, calls,
//! deroutes, returns, `while`/`for` loops, two-step navigation stages), each saying whether
//! the call goes on to the next remaining stage or ends.

use super::oracle::Oracle;
use super::trace::Event;
use super::{Interp, Item, push_list};
use crate::passes::fp::{BlockIx, FpStage, NavStage};

/// How a stage ended within the call.
pub(super) enum Flow {
    /// Continue with the next remaining stage in the same call.
    Continue,
    /// End of the call (`break`, a block change).
    Break,
}

impl<'p> Interp<'p> {
    fn pop(&mut self) {
        self.state.remaining.pop();
    }

    pub(super) fn exec(
        &mut self,
        ev: &mut Vec<Event>,
        oracle: &mut dyn Oracle,
        b: BlockIx,
        item: Item<'p>,
    ) -> Flow {
        match item {
            Item::Stage(s) => self.exec_stage(ev, oracle, b, s),
            Item::LoopBack(s) => {
                // Goto the loop test: the while stage itself, or the for test.
                self.pop();
                match s {
                    FpStage::For { .. } => self.state.remaining.push(Item::ForTest(s)),
                    _ => self.state.remaining.push(Item::Stage(s)),
                }
                Flow::Continue
            }
            Item::ForTest(s) => {
                let FpStage::For { body, .. } = s else { return Flow::Break };
                let key = (b, self.item_number(&Item::Stage(s)));
                let (i, to) = self.state.counters.get(&key).copied().unwrap_or((0, 0));
                let i = i.wrapping_add(1);
                self.state.counters.insert(key, (i, to));
                self.pop();
                if i > to {
                    Flow::Continue
                } else {
                    self.state.remaining.push(Item::LoopBack(s));
                    push_list(&mut self.state.remaining, body);
                    Flow::Break
                }
            }
            Item::NavMain(s) => match s {
                FpStage::Nav(n) => self.exec_nav(ev, oracle, n),
                _ => Flow::Break,
            },
        }
    }

    fn exec_stage(
        &mut self,
        ev: &mut Vec<Event>,
        oracle: &mut dyn Oracle,
        b: BlockIx,
        s: &'p FpStage,
    ) -> Flow {
        match s {
            FpStage::While { cond, body, .. } => {
                self.pop();
                if Self::cond(ev, oracle, cond) {
                    // IR-6: the body, then the loop-back that re-tests.
                    self.state.remaining.push(Item::LoopBack(s));
                    push_list(&mut self.state.remaining, body);
                    Flow::Break
                } else {
                    // IR-7
                    Flow::Continue
                }
            }
            FpStage::For { var: _, from, to, .. } => {
                let vf = oracle.value(from);
                ev.push(Event::Value { text: from.clone(), value: vf });
                let vt = oracle.value(to);
                ev.push(Event::Value { text: to.clone(), value: vt });
                // C: `_var = from - 1; _var_to = to;` on int8_t (modulo 256, as gcc does).
                let i = (vf as i32).wrapping_sub(1) as i8;
                let t = vt as i32 as i8;
                let key = (b, self.item_number(&Item::Stage(s)));
                self.state.counters.insert(key, (i, t));
                self.pop();
                self.state.remaining.push(Item::ForTest(s));
                Flow::Continue
            }
            FpStage::Set { code, .. } => {
                // IR-5
                Self::code(ev, code);
                self.pop();
                Flow::Continue
            }
            FpStage::Call { fun, loop_: true, brk, until, .. } => {
                if !Self::cond(ev, oracle, fun) {
                    self.pop();
                    if *brk { Flow::Break } else { Flow::Continue }
                } else {
                    if let Some(u) = until
                        && Self::cond(ev, oracle, u)
                    {
                        self.pop();
                    }
                    Flow::Break
                }
            }
            FpStage::Call { fun, loop_: false, brk, .. } => {
                ev.push(Event::Code { text: fun.clone() });
                self.pop();
                if *brk { Flow::Break } else { Flow::Continue }
            }
            FpStage::Deroute { target, .. } => {
                // The deroute stays the current stage while saved as last (quirk 1).
                self.goto_block(ev, oracle, *target);
                Flow::Break
            }
            FpStage::Return { reset, .. } => {
                self.do_return(ev, reset);
                Flow::Break
            }
            FpStage::Nav(n) => {
                if let Some(lines) = &n.init {
                    // IR-9: the init step, then the stage continues as NAV(mode, false).
                    for c in lines {
                        Self::code(ev, c);
                    }
                    self.pop();
                    self.state.remaining.push(Item::NavMain(s));
                    Flow::Break
                } else {
                    self.exec_nav(ev, oracle, n)
                }
            }
        }
    }

    /// IR-8, with upstream's code shape: every navigation stage ends the call.
    fn exec_nav(&mut self, ev: &mut Vec<Event>, oracle: &mut dyn Oracle, n: &'p NavStage) -> Flow {
        if let Some(c) = &n.pre_call {
            Self::code(ev, c);
        }
        for c in &n.before {
            Self::code(ev, c);
        }
        let mut run_lines = true;
        if let Some((cond, wp)) = &n.approach {
            if Self::cond(ev, oracle, cond) {
                if let Some(c) = &n.post_call {
                    Self::code(ev, c);
                }
                self.state.last_wp = *wp;
                self.pop();
                return Flow::Break;
            }
            // the lines are the else branch
            for c in &n.lines {
                Self::code(ev, c);
            }
            run_lines = false;
        }
        if run_lines {
            for c in &n.lines {
                Self::code(ev, c);
            }
        }
        if let Some(u) = &n.until
            && Self::cond(ev, oracle, u)
        {
            if let Some(c) = &n.post_call {
                Self::code(ev, c);
            }
            self.pop();
            return Flow::Break;
        }
        if let Some(c) = &n.post_call {
            Self::code(ev, c);
        }
        Flow::Break
    }
}
