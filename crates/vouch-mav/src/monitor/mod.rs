//! The runtime monitor: feeds on decoded messages in order, keeps concurrent sessions of every
//! loaded protocol, and answers each message with Accept, Ignore, Unverifiable or Violation.
//!
//! Every message is first placed on a side of the link and checked against the trust boundary
//! ([`identity`]): vehicle state is learned only from the vehicle side, from systems that side
//! has shown to be vehicles, and a live frame from the GCS side that claims a vehicle's identity
//! is a violation of its own.
//!
//! Hot path: one table lookup tells whether any protocol mentions the message; telemetry that no
//! protocol mentions only updates the tracked vehicle state. Sessions live in a small vector and
//! are matched by participants and key fields; stepping uses a reusable scratch buffer.

// Protocol errors carry their source text for miette; they are cold, so their size is fine.
#![allow(clippy::result_large_err)]

pub mod eval;
mod explain;
pub mod identity;
pub mod offline;
mod report;
mod session;
mod spec;
pub mod step;

pub use report::{Reply, Violation, ViolationKind};
pub use session::{MAX_SESSIONS_PER_PROTOCOL, ProtocolStats, Summary};
pub use spec::{LoadError, MonitorSpec};

use std::sync::Arc;

use crate::codec::{Frame, MessageView};
use crate::dialect::Dialect;
use crate::protocol::ir::{FieldLoc, ProtocolSet};
use crate::protocol::{ProtocolError, load_protocols, stdlib};
use crate::side::Side;
use crate::vehicle_state::VehicleTracker;
use eval::Val;
use identity::Identities;
use session::Session;

/// The monitor's answer for one message.
#[derive(Debug, Clone)]
pub enum Verdict {
    /// The message advanced or opened a session.
    Accept,
    /// No protocol is concerned with this message.
    Ignore,
    /// The monitor cannot tell: the message answers a session whose opener it never saw (it
    /// started mid-exchange, or a recording holds one direction only). The protocol's policy is
    /// `unverifiable pass`: a guard forwards it. (Under `unverifiable drop` the same finding
    /// comes as a [`Verdict::Violation`] of kind [`ViolationKind::Unverifiable`].)
    Unverifiable(Box<Violation>),
    Violation(Box<Violation>),
}

impl Verdict {
    pub fn is_violation(&self) -> bool {
        matches!(self, Verdict::Violation(_))
    }

    /// The finding of a violation or of an unverifiable message.
    pub fn finding(&self) -> Option<&Violation> {
        match self {
            Verdict::Violation(v) | Verdict::Unverifiable(v) => Some(v),
            _ => None,
        }
    }
}

pub struct Monitor {
    dialect: Arc<Dialect>,
    set: ProtocolSet,
    consts: Vec<f64>,
    /// Message index → protocols whose alphabet contains it.
    by_msg: Vec<Vec<u16>>,
    /// Message index → locations of target_system / target_component.
    targets: Vec<Option<(FieldLoc, FieldLoc)>>,
    tracker: VehicleTracker,
    sessions: Vec<Session>,
    ids: Identities,
    stats: Vec<ProtocolStats>,
    messages: u64,
    relevant: u64,
    violations: u64,
    unverifiable: u64,
    forgeries: u64,
    by_side: [u64; 2],
    scratch: Vec<Val>,
    last_sweep_us: u64,
    serial: u64,
}

/// How often (µs of message time) idle sessions are looked for.
const SWEEP_US: u64 = 100_000;

impl Monitor {
    pub fn new(dialect: Arc<Dialect>, set: ProtocolSet) -> Monitor {
        let n = dialect.messages().len();
        let mut by_msg = vec![Vec::new(); n];
        for (pi, p) in set.protocols.iter().enumerate() {
            for &m in &p.alphabet {
                by_msg[usize::from(m)].push(pi as u16);
            }
        }
        let loc = |m: &crate::dialect::MessageDef, f: &str| {
            m.field(f).map(|d| FieldLoc {
                ty: d.ty,
                offset: d.offset,
                text_len: 0,
                enum_name: None,
            })
        };
        let targets = dialect
            .messages()
            .iter()
            .map(|m| Some((loc(m, "target_system")?, loc(m, "target_component")?)))
            .collect();
        let stats = set.protocols.iter().map(|p| ProtocolStats::new(&p.name)).collect();
        let consts = set.consts.iter().map(|c| c.value).collect();
        let tracker = VehicleTracker::new(&dialect, set.params.clone());
        Monitor {
            dialect,
            set,
            consts,
            by_msg,
            targets,
            tracker,
            sessions: Vec::new(),
            ids: Identities::new(),
            stats,
            messages: 0,
            relevant: 0,
            violations: 0,
            unverifiable: 0,
            forgeries: 0,
            by_side: [0; 2],
            scratch: Vec::new(),
            last_sweep_us: 0,
            serial: 0,
        }
    }

    /// A monitor running protocol sources `(file name, text)`; `overrides` sets constants.
    pub fn from_sources(
        dialect: Arc<Dialect>,
        sources: &[(String, String)],
        overrides: &[(String, f64)],
    ) -> Result<Monitor, ProtocolError> {
        let set = load_protocols(&dialect, sources, overrides)?;
        Ok(Monitor::new(dialect, set))
    }

    /// A monitor running the standard library of protocols.
    pub fn with_stdlib(
        dialect: Arc<Dialect>,
        overrides: &[(String, f64)],
    ) -> Result<Monitor, ProtocolError> {
        Self::from_sources(dialect, &stdlib::sources(), overrides)
    }

    /// A monitor with the same dialect and protocols and no state (a new recording, a new link).
    pub fn fresh(&self) -> Monitor {
        Monitor::new(Arc::clone(&self.dialect), self.set.clone())
    }

    /// The dialect the protocols were compiled against.
    pub fn dialect(&self) -> &Arc<Dialect> {
        &self.dialect
    }

    pub fn protocols(&self) -> &ProtocolSet {
        &self.set
    }

    pub fn vehicles(&self) -> &VehicleTracker {
        &self.tracker
    }

    /// Checks one frame that arrived from side `from` of the link (`None` when unknown, as in
    /// recordings: the side is then derived from heartbeats, see [`identity`]). Frames of
    /// unknown messages are ignored.
    pub fn on_frame(&mut self, frame: &Frame, from: Option<Side>, time_us: u64) -> Verdict {
        let dialect = Arc::clone(&self.dialect);
        match MessageView::of_frame(frame, &dialect) {
            Some(view) => self.observe(&view, frame.sysid, frame.compid, from, time_us),
            None => {
                self.messages += 1;
                Verdict::Ignore
            }
        }
    }

    /// Checks one decoded message sent by `sysid/compid` from side `from` at `time_us`.
    pub fn observe(
        &mut self,
        msg: &MessageView,
        sysid: u8,
        compid: u8,
        from: Option<Side>,
        time_us: u64,
    ) -> Verdict {
        self.messages += 1;
        let heartbeat = self.tracker.heartbeat_kind(msg, compid);
        let side = match self.ids.place(sysid, compid, heartbeat, from) {
            Ok(side) => side,
            Err(why) => {
                self.violations += 1;
                self.forgeries += 1;
                return Verdict::Violation(Box::new(
                    self.forgery(msg, sysid, compid, why, time_us),
                ));
            }
        };
        self.by_side[side.index()] += 1;
        if side == Side::Vehicle && self.ids.is_vehicle(sysid) {
            self.tracker.observe(sysid, compid, msg);
        }
        if time_us >= self.last_sweep_us + SWEEP_US {
            self.last_sweep_us = time_us;
            if !self.sessions.is_empty() {
                self.expire(time_us);
            }
        }
        let idx = usize::from(msg.index);
        if self.by_msg.get(idx).is_none_or(|v| v.is_empty()) {
            return Verdict::Ignore;
        }
        self.relevant += 1;
        let target = self.targets[idx].as_ref().map(|(s, c)| {
            let s = eval::read_loc(msg.payload, s);
            let c = eval::read_loc(msg.payload, c);
            let n = |v: Val| if let Val::Num(x) = v { x as u8 } else { 0 };
            (n(s), n(c))
        });
        let arrival = session::Arrival { msg, from: (sysid, compid), kind: side, target, time_us };
        let verdict = self.dispatch(&arrival);
        match &verdict {
            Verdict::Violation(v) if v.kind == ViolationKind::Unverifiable => {
                self.unverifiable += 1
            }
            Verdict::Violation(_) => self.violations += 1,
            Verdict::Unverifiable(_) => self.unverifiable += 1,
            _ => {}
        }
        verdict
    }

    /// Ends sessions idle past their protocol's timeout (completed if their state allows it).
    pub fn expire(&mut self, now_us: u64) {
        let mut i = 0;
        while i < self.sessions.len() {
            let s = &self.sessions[i];
            let p = &self.set.protocols[s.proto];
            if p.timeout_us.is_some_and(|t| now_us.saturating_sub(s.last_us) > t) {
                self.close(i, false);
            } else {
                i += 1;
            }
        }
    }

    /// Ends every open session (end of a recording). Sessions in a completable state count as
    /// completed, the others as unfinished.
    pub fn finish(&mut self) {
        while !self.sessions.is_empty() {
            self.close(self.sessions.len() - 1, true);
        }
    }

    pub fn summary(&self) -> Summary {
        Summary {
            messages: self.messages,
            relevant: self.relevant,
            violations: self.violations,
            unverifiable: self.unverifiable,
            forgeries: self.forgeries,
            from_gcs: self.by_side[Side::Gcs.index()],
            from_vehicle: self.by_side[Side::Vehicle.index()],
            open_sessions: self.sessions.len() as u64,
            protocols: self.stats.clone(),
        }
    }
}
