//! Violation reports and the replies a guard may send in enforce mode.

use std::fmt;

use crate::codec::{MessageBuilder, Value};
use crate::dialect::{Dialect, MsgIndex};

/// A message the protocol file asks to send back when it is violated (`on violation reply …`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Reply {
    pub message: String,
    #[serde(skip)]
    pub msg: MsgIndex,
    /// Numeric fields; text fields are in `text_fields`.
    pub fields: Vec<(String, f64)>,
    pub text_fields: Vec<(String, String)>,
    /// Ids to send from (the peer the reply impersonates) and to (the addressed role).
    pub from_sys: u8,
    pub from_comp: u8,
    pub to_sys: u8,
    pub to_comp: u8,
}

impl Reply {
    fn builder<'d>(&self, dialect: &'d Dialect) -> MessageBuilder<'d> {
        let mut b = MessageBuilder::for_def(dialect.message(self.msg));
        for (f, v) in &self.fields {
            let _ = b.set_value(f, 0, Value::F(*v));
        }
        for (f, t) in &self.text_fields {
            if let Ok(nb) = b.clone().set_str(f, t) {
                b = nb;
            }
        }
        b
    }

    /// The reply as a MAVLink 2 frame (unsigned), sent as `from_sys/from_comp`.
    pub fn encode_v2(&self, dialect: &Dialect, seq: u8) -> Vec<u8> {
        self.builder(dialect).frame_v2(seq, self.from_sys, self.from_comp)
    }
}

/// Kind of violation, for counting and for JSON consumers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ViolationKind {
    /// A step's refinement (`where`) failed.
    Refinement,
    /// A recursion invariant failed after an update.
    Invariant,
    /// A message that requires an open session arrived without one (`strict`).
    NoSession,
}

/// A precise account of one violation.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Violation {
    pub kind: ViolationKind,
    pub protocol: String,
    /// Session description: participants and key values (or "no session").
    pub session: String,
    /// The offending message, e.g. `MISSION_ACK from 1/1 to 255/230`.
    pub message: String,
    /// Branch that was tried (`label: from -> to : MSG`) or the strict rule.
    pub step: String,
    /// What the protocol allowed in this state.
    pub expected: Vec<String>,
    /// The failed condition, as written in the protocol file.
    pub predicate: Option<String>,
    /// Values of the names in that condition.
    pub values: Vec<(String, String)>,
    pub reason: String,
    pub time_us: u64,
    pub reply: Option<Reply>,
    /// Further violations caused by the same message (other protocols).
    pub others: Vec<Violation>,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}] {} — {}: {}", self.protocol, self.session, self.message, self.reason)?;
        if let Some(p) = &self.predicate {
            write!(f, "\n    failed: {p}")?;
        }
        if !self.values.is_empty() {
            let v: Vec<String> = self.values.iter().map(|(n, v)| format!("{n} = {v}")).collect();
            write!(f, "\n    with:   {}", v.join(", "))?;
        }
        if !self.step.is_empty() {
            write!(f, "\n    step:   {}", self.step)?;
        }
        if !self.expected.is_empty() {
            write!(f, "\n    expected one of: {}", self.expected.join("; "))?;
        }
        if let Some(r) = &self.reply {
            write!(f, "\n    reply:  {} to {}/{}", r.message, r.to_sys, r.to_comp)?;
        }
        for o in &self.others {
            write!(f, "\n  and {o}")?;
        }
        Ok(())
    }
}
