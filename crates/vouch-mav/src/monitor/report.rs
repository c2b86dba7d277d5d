//! Violation reports and the replies a guard may send in enforce mode.

use std::fmt;

use crate::codec::encode::frame_v2_truncated;
use crate::codec::{MessageBuilder, Value};
use crate::dialect::MessageDef;
use crate::side::Side;

/// A message sent in answer to a violation: the one a protocol asks for (`on violation reply …`),
/// or one the guard makes itself (alerts, acknowledgements). It carries its encoded payload, so
/// framing it needs no dialect.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Reply {
    /// Message name, e.g. `MISSION_ACK`.
    pub message: String,
    /// The side of the link it is sent to.
    pub to: Side,
    /// Message id.
    pub msgid: u32,
    /// CRC_EXTRA of the message.
    #[serde(skip)]
    pub crc_extra: u8,
    /// Encoded payload, possibly untruncated (framing truncates trailing zeros).
    #[serde(skip)]
    pub payload: Vec<u8>,
    /// Numeric fields as set (for reports).
    pub fields: Vec<(String, f64)>,
    /// Text fields as set (for reports).
    pub text_fields: Vec<(String, String)>,
    /// Ids to send from (the peer the reply stands in for, so that the addressee accepts it).
    pub from_sys: u8,
    /// Component id to send from.
    pub from_comp: u8,
    /// System id of the addressee.
    pub to_sys: u8,
    /// Component id of the addressee.
    pub to_comp: u8,
}

impl Reply {
    /// A reply whose fields are set by name through the dialect's definition of `def`.
    pub(super) fn build(
        def: &MessageDef,
        to: Side,
        from: (u8, u8),
        addressee: (u8, u8),
        fields: Vec<(String, f64)>,
        text_fields: Vec<(String, String)>,
    ) -> Reply {
        let mut b = MessageBuilder::for_def(def);
        for (f, v) in &fields {
            let _ = b.set_value(f, 0, Value::F(*v));
        }
        for (f, t) in &text_fields {
            if let Ok(nb) = b.clone().set_str(f, t) {
                b = nb;
            }
        }
        Reply {
            message: def.name.clone(),
            to,
            msgid: def.id,
            crc_extra: def.crc_extra,
            payload: b.payload().to_vec(),
            fields,
            // Shown in reports: text from the wire never reaches a terminal raw.
            text_fields: text_fields
                .into_iter()
                .map(|(f, t)| (f, crate::text::escape_controls(&t).into_owned()))
                .collect(),
            from_sys: from.0,
            from_comp: from.1,
            to_sys: addressee.0,
            to_comp: addressee.1,
        }
    }

    /// The reply as an unsigned MAVLink 2 frame (zero-truncated), sent as `from_sys/from_comp`.
    pub fn encode_v2(&self, seq: u8) -> Vec<u8> {
        frame_v2_truncated(
            self.msgid,
            self.crc_extra,
            &self.payload,
            seq,
            self.from_sys,
            self.from_comp,
        )
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
    /// A message that requires an open session arrived without one (`strict`), from the role
    /// that opens the protocol's sessions.
    NoSession,
    /// An answer to a session whose opener was never seen (`strict`, from the answering role):
    /// not known to be wrong, not known to be right.
    Unverifiable,
    /// A frame from the GCS side that claims a vehicle's identity (trust boundary).
    Forgery,
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
    /// The first message to send in answer (enforce mode).
    pub reply: Option<Reply>,
    /// Further answers, to the other role (e.g. cancelling toward the vehicle too, so that
    /// neither side waits for a message that was dropped).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub more_replies: Vec<Reply>,
    /// Further violations caused by the same message (other protocols).
    pub others: Vec<Violation>,
}

impl Violation {
    /// Every answer to send, in order.
    pub fn replies(&self) -> impl Iterator<Item = &Reply> {
        self.reply.iter().chain(&self.more_replies)
    }

    /// One short line, e.g. `MISSION_ACK: curr == n (curr=60, n=100)`: short enough for a
    /// STATUSTEXT's 50 bytes in the common cases (the full report is the `Display` text).
    pub fn summary(&self) -> String {
        let msg = self.message.split_whitespace().next().unwrap_or("message");
        let why = self.predicate.as_deref().unwrap_or(&self.reason);
        if self.values.is_empty() {
            format!("{msg}: {why}")
        } else {
            let vals: Vec<String> = self.values.iter().map(|(n, x)| format!("{n}={x}")).collect();
            format!("{msg}: {why} ({})", vals.join(", "))
        }
    }
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
        for r in self.replies() {
            write!(f, "\n    reply:  {} to {}/{}", r.message, r.to_sys, r.to_comp)?;
        }
        for o in &self.others {
            write!(f, "\n  and {o}")?;
        }
        Ok(())
    }
}
