//! The trace of external events (the paper's `fp_trace`: `COND (c, b) | C_CODE c`, plus the
//! integer values read by `for` bounds) and the one text format shared by the interpreter,
//! the C stub driver (`tests/stub/driver.c`) and `vouch fpl sim --trace`.
//!
//! ```text
//! init                      events of auto_nav_init()
//! X <code>
//! goto <b>                  an operator block change before the next call (optional)
//! X <code>                  its exit/enter hooks
//! step <n>                  one auto_nav() call
//! C <0|1> <condition>       a condition and the value the oracle gave it
//! X <code>                  C code executed
//! V <int> <value text>      an integer value (for-loop bounds)
//! S <block> <stage> <last_block> <last_stage>   state after the call
//! ```
//! Texts are escaped so that one event is one line (`\\`, `\n`, `\r`).

use serde::Serialize;

#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum Event {
    Cond { text: String, value: bool },
    Code { text: String },
    Value { text: String, value: i64 },
}

/// The observable flight-plan state after a call (the C runtime's `nav_block`, `nav_stage`,
/// `last_block`, `last_stage`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Observation {
    pub block: usize,
    pub stage: usize,
    pub last_block: usize,
    pub last_stage: usize,
}

/// One `auto_nav` call: where it started, what it did, where it ended.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct StepRecord {
    pub call: usize,
    /// Operator block changes (GCS "go to block") applied just before this call, in order,
    /// with the events of the exit/enter hooks each ran.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub operator_gotos: Vec<(usize, Vec<Event>)>,
    pub before: Observation,
    pub events: Vec<Event>,
    pub after: Observation,
}

/// A whole run: the events of `auto_nav_init` and every call.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Default)]
pub struct Run {
    pub init: Vec<Event>,
    pub steps: Vec<StepRecord>,
}

pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            c => out.push(c),
        }
    }
    out
}

impl Event {
    pub fn line(&self) -> String {
        match self {
            Event::Cond { text, value } => format!("C {} {}", u8::from(*value), escape(text)),
            Event::Code { text } => format!("X {}", escape(text)),
            Event::Value { text, value } => format!("V {value} {}", escape(text)),
        }
    }
}

impl Run {
    /// The shared text format (see the module documentation). Does not include `before`
    /// states, which the C driver does not print (they are the previous call's `after`).
    pub fn to_text(&self) -> String {
        let mut out = String::from("init\n");
        for e in &self.init {
            out.push_str(&e.line());
            out.push('\n');
        }
        for s in &self.steps {
            for (b, evs) in &s.operator_gotos {
                out.push_str(&format!("goto {b}\n"));
                for e in evs {
                    out.push_str(&e.line());
                    out.push('\n');
                }
            }
            out.push_str(&format!("step {}\n", s.call));
            for e in &s.events {
                out.push_str(&e.line());
                out.push('\n');
            }
            let a = s.after;
            out.push_str(&format!("S {} {} {} {}\n", a.block, a.stage, a.last_block, a.last_stage));
        }
        out
    }
}
