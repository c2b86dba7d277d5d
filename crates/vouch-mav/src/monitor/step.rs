//! One step of a session: find the branch a message takes, bind, check refinements, apply the
//! continuation (enter/continue a recursion with its invariant). No allocation on this path.

use super::eval::{Env, Val, eval, first_failing, holds, read_loc};
use crate::codec::MessageView;
use crate::protocol::ir::{Cont, MAX_CONTINUE_ASSIGNS, Protocol, StateId};
use crate::vehicle_state::VehicleState;

/// What a message did to a session (or to a would-be session, in the start state).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepResult {
    /// A branch was taken; `next` is the new state, `None` when the session ended.
    Took { next: Option<StateId>, transition: usize },
    /// A branch matched by sender, message and selector but its refinement failed.
    Refused { transition: usize, conjunct: usize },
    /// A branch was taken but the invariant of the recursion it entered failed.
    Invariant { transition: usize, rec: usize, conjunct: usize },
    /// No branch of the state is about this message.
    Mismatch,
}

/// Inputs shared by every evaluation in one step.
pub struct StepInput<'a> {
    pub msg: &'a MessageView<'a>,
    pub role: usize,
    pub consts: &'a [f64],
    pub keys: &'a [Val],
    pub vehicle: Option<&'a VehicleState>,
    /// Names of the tracked parameters (for `param[…]`).
    pub param_names: &'a [String],
}

/// Tries the transitions of `state` in order. On success `vars` holds the updated variables;
/// on failure `vars` is unchanged. `scratch` is a reusable buffer.
pub fn step(
    proto: &Protocol,
    state: StateId,
    input: &StepInput,
    vars: &mut [Val],
    scratch: &mut Vec<Val>,
) -> StepResult {
    let st = &proto.states[state];
    let mut refused = None;
    for (ti, t) in st.transitions.iter().enumerate() {
        if t.from != input.role {
            continue;
        }
        let Some(lf) = t.msgs.iter().find(|l| l.msg == input.msg.index) else {
            continue;
        };
        scratch.clear();
        scratch.extend_from_slice(vars);
        for &(slot, f) in &t.binds {
            scratch[slot] = read_loc(input.msg.payload, &lf.fields[f]);
        }
        let env = Env {
            payload: input.msg.payload,
            fields: &lf.fields,
            vars: scratch,
            consts: input.consts,
            keys: input.keys,
            vehicle: input.vehicle,
            param_names: input.param_names,
        };
        if let Some(w) = &t.when
            && !holds(w, &env)
        {
            continue;
        }
        if let Some(w) = &t.where_
            && let Some(c) = first_failing(w, &env)
        {
            refused.get_or_insert(StepResult::Refused { transition: ti, conjunct: c });
            continue;
        }
        // Taken: run the continuation on the scratch copy.
        let next = match &t.cont {
            Cont::End => None,
            Cont::Goto(s) => Some(*s),
            Cont::Enter { rec, assigns, then } => {
                for (slot, e) in assigns {
                    let v = eval(e, &Env { vars: scratch, ..env_like(input, &lf.fields) });
                    scratch[*slot] = v;
                }
                if let Some(c) = invariant_fails(proto, *rec, input, &lf.fields, scratch) {
                    return StepResult::Invariant { transition: ti, rec: *rec, conjunct: c };
                }
                Some(*then)
            }
            Cont::Continue { rec, assigns } => {
                // Simultaneous update: evaluate every new value before storing any. The checker
                // allows at most MAX_CONTINUE_ASSIGNS updates per `continue`.
                let mut new = [Val::Unknown; MAX_CONTINUE_ASSIGNS];
                for (k, (_, e)) in assigns.iter().enumerate().take(MAX_CONTINUE_ASSIGNS) {
                    new[k] = eval(e, &Env { vars: scratch, ..env_like(input, &lf.fields) });
                }
                for (k, (slot, _)) in assigns.iter().enumerate().take(MAX_CONTINUE_ASSIGNS) {
                    scratch[*slot] = new[k];
                }
                if let Some(c) = invariant_fails(proto, *rec, input, &lf.fields, scratch) {
                    return StepResult::Invariant { transition: ti, rec: *rec, conjunct: c };
                }
                Some(proto.recs[*rec].entry)
            }
        };
        vars.copy_from_slice(scratch);
        return StepResult::Took { next, transition: ti };
    }
    refused.unwrap_or(StepResult::Mismatch)
}

fn env_like<'a>(input: &'a StepInput<'a>, fields: &'a [crate::protocol::ir::FieldLoc]) -> Env<'a> {
    Env {
        payload: input.msg.payload,
        fields,
        vars: &[],
        consts: input.consts,
        keys: input.keys,
        vehicle: input.vehicle,
        param_names: input.param_names,
    }
}

fn invariant_fails(
    proto: &Protocol,
    rec: usize,
    input: &StepInput,
    fields: &[crate::protocol::ir::FieldLoc],
    vars: &[Val],
) -> Option<usize> {
    let inv = proto.recs[rec].invariant.as_ref()?;
    first_failing(inv, &Env { vars, ..env_like(input, fields) })
}
