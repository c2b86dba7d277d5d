//! Sessions: matching a message to open sessions, opening new ones, closing them, and turning
//! failed steps into violation reports.

use super::eval::{Env, Val, holds, read_loc};
use super::report::{Violation, ViolationKind};
use super::step::{StepInput, StepResult, step};
use super::{Monitor, Verdict};
use crate::codec::MessageView;
use crate::protocol::ir::{Protocol, StateId, UnverifiablePolicy};
use crate::side::Side;

/// An open session of one protocol.
#[derive(Debug, Clone)]
pub(crate) struct Session {
    pub proto: usize,
    pub state: StateId,
    /// (system id, component id) per role; 0 = not bound yet (wildcard).
    pub ids: [(u8, u8); 2],
    pub keys: Vec<Val>,
    pub vars: Vec<Val>,
    pub last_us: u64,
    pub serial: u64,
}

/// Counters of one protocol.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct ProtocolStats {
    pub name: String,
    pub started: u64,
    pub completed: u64,
    /// Ended by their timeout, or replaced by a new session, in a state that is not complete.
    pub abandoned: u64,
    /// Still open at the end of the input in a state that is not complete.
    pub unfinished: u64,
    pub violations: u64,
    /// Answers to sessions whose opener was never seen (see [`Verdict::Unverifiable`]).
    pub unverifiable: u64,
}

impl ProtocolStats {
    pub fn new(name: &str) -> Self {
        ProtocolStats { name: name.to_string(), ..Default::default() }
    }
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct Summary {
    pub messages: u64,
    /// Messages that at least one protocol mentions.
    pub relevant: u64,
    /// Violations of protocols and of the trust boundary.
    pub violations: u64,
    /// Messages the monitor could not verify (answers to openers never seen).
    pub unverifiable: u64,
    /// Of the violations: frames from the GCS side that claimed a vehicle's identity.
    pub forgeries: u64,
    /// Messages placed on the GCS side (by the link, or derived from heartbeats offline).
    pub from_gcs: u64,
    /// Messages placed on the vehicle side.
    pub from_vehicle: u64,
    pub open_sessions: u64,
    pub protocols: Vec<ProtocolStats>,
}

impl Summary {
    pub fn protocol(&self, name: &str) -> Option<&ProtocolStats> {
        self.protocols.iter().find(|p| p.name == name)
    }

    /// The only side anything came from, when the traffic holds one direction only (e.g. a
    /// recording of the vehicle's telemetry link): `None` when both sides spoke or neither.
    pub fn one_direction(&self) -> Option<Side> {
        match (self.from_gcs, self.from_vehicle) {
            (0, n) if n > 0 => Some(Side::Vehicle),
            (n, 0) if n > 0 => Some(Side::Gcs),
            _ => None,
        }
    }
}

/// Open sessions kept per protocol (see `make_room`).
pub const MAX_SESSIONS_PER_PROTOCOL: usize = 64;

fn role_of_kind(p: &Protocol, k: Side) -> usize {
    if p.roles[0].1 == k { 0 } else { 1 }
}

/// System id of the vehicle of a session (0 = not known yet, or a broadcast).
pub(super) fn vehicle_sys(p: &Protocol, ids: &[(u8, u8); 2]) -> u8 {
    ids[role_of_kind(p, Side::Vehicle)].0
}

/// Ids of both roles of a session that `from` opens in role `role`; the other role's ids are the
/// message's target when it names one (otherwise learnt from the first answer).
pub(super) fn session_ids(role: usize, from: (u8, u8), target: Option<(u8, u8)>) -> [(u8, u8); 2] {
    let mut ids = [(0u8, 0u8); 2];
    ids[role] = from;
    if let Some(t) = target {
        ids[1 - role] = t;
    }
    ids
}

/// Values of protocol `proto`'s keys in `msg`; unknown for a key that is no field of the message.
pub(super) fn key_values(proto: &Protocol, msg: &MessageView) -> Vec<Val> {
    proto
        .keys
        .iter()
        .map(|k| {
            k.locs
                .iter()
                .find(|(m, _)| *m == msg.index)
                .map(|(_, l)| read_loc(msg.payload, l))
                .unwrap_or(Val::Unknown)
        })
        .collect()
}

/// One message as the monitor dispatches it: the sender, its role, the peer the message
/// addresses (from its target fields) and the time it was seen.
#[derive(Clone, Copy)]
pub(super) struct Arrival<'m, 'd> {
    pub msg: &'m MessageView<'d>,
    pub from: (u8, u8),
    pub kind: Side,
    pub target: Option<(u8, u8)>,
    pub time_us: u64,
}

/// What one message did to the sessions of every protocol it belongs to.
#[derive(Default)]
struct Outcome {
    accepted: bool,
    violations: Vec<Violation>,
    /// Sessions (by serial) that had no use for the message; closed if complete once another
    /// protocol accepts it. Four are enough: more only delays closing a finished session.
    mismatched: [u64; 4],
    n_mismatched: usize,
    orphan: Option<(usize, usize)>,
}

/// What the sessions of one protocol did with a message.
struct ProtocolStep {
    took: bool,
    mismatch: Option<u64>,
}

impl Monitor {
    pub(super) fn dispatch(&mut self, arrival: &Arrival) -> Verdict {
        let idx = usize::from(arrival.msg.index);
        let mut out = Outcome::default();
        for k in 0..self.by_msg[idx].len() {
            let p = usize::from(self.by_msg[idx][k]);
            let mut step = self.step_sessions(p, arrival, &mut out);
            // A start is tried when no session of this protocol took the message. Keyed protocols
            // keep one session per key: the new one replaces a session that had no use for the
            // message (e.g. MISSION_COUNT sent again). Unkeyed protocols may run several
            // sessions at once (e.g. outstanding parameter reads).
            if self.set.protocols[p].keys.is_empty() {
                step.mismatch = None;
            }
            if !step.took {
                self.start_or_orphan(p, arrival, step.mismatch, &mut out);
            }
        }
        // Sessions that had no use for a message another protocol accepted are over if their
        // state is complete (e.g. a download without the optional closing ACK).
        if out.accepted {
            for &serial in &out.mismatched[..out.n_mismatched] {
                if let Some(j) = self.sessions.iter().position(|s| s.serial == serial)
                    && self.completable(j)
                {
                    self.close(j, false);
                }
            }
        }
        if !out.violations.is_empty() {
            return self.worst_finding(out.violations);
        }
        if out.accepted {
            return Verdict::Accept;
        }
        match out.orphan {
            Some((p, si)) => self.orphan_verdict(p, si, arrival),
            None => Verdict::Ignore,
        }
    }

    /// Steps every session of protocol `p` whose participants and keys match the message.
    fn step_sessions(&mut self, p: usize, arrival: &Arrival, out: &mut Outcome) -> ProtocolStep {
        let Arrival { msg, from: (sysid, compid), kind, target, time_us } = *arrival;
        let mut step = ProtocolStep { took: false, mismatch: None };
        let mut i = 0;
        while i < self.sessions.len() {
            if self.sessions[i].proto != p {
                i += 1;
                continue;
            }
            let Some(role) = self.participant(i, sysid, compid, target, kind) else {
                i += 1;
                continue;
            };
            if !self.keys_match(i, msg) {
                i += 1;
                continue;
            }
            match self.step_session(i, role, msg) {
                StepResult::Took { next, .. } => {
                    out.accepted = true;
                    step.took = true;
                    self.learn_peers(i, role, arrival);
                    self.sessions[i].last_us = time_us;
                    match next {
                        Some(st) => self.sessions[i].state = st,
                        None => {
                            self.stats[p].completed += 1;
                            self.sessions.swap_remove(i);
                            continue;
                        }
                    }
                }
                r @ (StepResult::Refused { .. } | StepResult::Invariant { .. }) => {
                    step.took = true;
                    out.violations.push(self.session_violation(i, role, msg, r, time_us));
                }
                StepResult::Mismatch => {
                    let serial = self.sessions[i].serial;
                    step.mismatch = Some(serial);
                    if out.n_mismatched < out.mismatched.len() {
                        out.mismatched[out.n_mismatched] = serial;
                        out.n_mismatched += 1;
                    }
                }
            }
            i += 1;
        }
        step
    }

    /// Records who plays each role of session `i` once a message of `role` was taken: the
    /// sender, and the addressed peer where the session did not know it yet.
    fn learn_peers(&mut self, i: usize, role: usize, arrival: &Arrival) {
        let s = &mut self.sessions[i];
        let other = 1 - role;
        s.ids[role] = arrival.from;
        if let Some((ts, tc)) = arrival.target {
            if s.ids[other].0 == 0 && ts != 0 {
                s.ids[other].0 = ts;
            }
            if s.ids[other].1 == 0 && tc != 0 {
                s.ids[other].1 = tc;
            }
        }
    }

    /// Tries to start a session of protocol `p` with the message; remembers the first strict
    /// message that neither a session nor a start could use.
    fn start_or_orphan(
        &mut self,
        p: usize,
        arrival: &Arrival,
        mismatch: Option<u64>,
        out: &mut Outcome,
    ) {
        match self.try_start(p, arrival) {
            Some(Ok(started)) => {
                out.accepted = true;
                // A new start replaces a session of the same participants and keys that
                // could not use this message (e.g. MISSION_COUNT sent again).
                if let Some(serial) = mismatch
                    && serial != started
                    && let Some(j) = self.sessions.iter().position(|s| s.serial == serial)
                {
                    self.close(j, false);
                }
            }
            Some(Err(v)) => out.violations.push(*v),
            None => {
                let proto = &self.set.protocols[p];
                let (msg, kind) = (arrival.msg, arrival.kind);
                if let Some(si) = proto
                    .strict
                    .iter()
                    .position(|s| proto.roles[s.from].1 == kind && s.msgs.contains(&msg.index))
                {
                    out.orphan.get_or_insert((p, si));
                }
            }
        }
    }

    /// The verdict on a message with findings: the worst one, carrying the others, counted in
    /// the statistics of the protocols that found them.
    fn worst_finding(&mut self, mut violations: Vec<Violation>) -> Verdict {
        // A message is what is worst about it: violations before unverifiable findings.
        violations.sort_by_key(|v| v.kind == ViolationKind::Unverifiable);
        let mut first = violations.remove(0);
        for v in violations.iter().chain(std::iter::once(&first)) {
            if let Some(p) = self.stats.iter_mut().find(|s| s.name == v.protocol) {
                if v.kind == ViolationKind::Unverifiable {
                    p.unverifiable += 1;
                } else {
                    p.violations += 1;
                }
            }
        }
        first.others = violations;
        let passes =
            first.kind == ViolationKind::Unverifiable
                && self.set.protocols.iter().any(|p| {
                    p.name == first.protocol && p.unverifiable == UnverifiablePolicy::Pass
                });
        if passes {
            Verdict::Unverifiable(Box::new(first))
        } else {
            Verdict::Violation(Box::new(first))
        }
    }

    /// The verdict on a strict message that no session of protocol `p` expected.
    fn orphan_verdict(&mut self, p: usize, si: usize, arrival: &Arrival) -> Verdict {
        let proto = &self.set.protocols[p];
        let finding = Box::new(self.orphan_violation(p, si, arrival));
        if !proto.strict[si].answer {
            self.stats[p].violations += 1;
            return Verdict::Violation(finding);
        }
        self.stats[p].unverifiable += 1;
        match proto.unverifiable {
            UnverifiablePolicy::Pass => Verdict::Unverifiable(finding),
            UnverifiablePolicy::Drop => Verdict::Violation(finding),
        }
    }

    /// Which role of session `i` sent this message, if the message belongs to its participants.
    fn participant(
        &self,
        i: usize,
        sysid: u8,
        compid: u8,
        target: Option<(u8, u8)>,
        kind: Side,
    ) -> Option<usize> {
        let s = &self.sessions[i];
        let p = &self.set.protocols[s.proto];
        (0..2).find(|&r| {
            let (ss, sc) = s.ids[r];
            let sender_ok = if ss == 0 {
                p.roles[r].1 == kind
            } else {
                ss == sysid && (sc == 0 || sc == compid)
            };
            if !sender_ok {
                return false;
            }
            let (os, oc) = s.ids[1 - r];
            match target {
                Some((ts, tc)) => {
                    (ts == 0 || os == 0 || ts == os) && (tc == 0 || oc == 0 || tc == oc)
                }
                None => true,
            }
        })
    }

    fn keys_match(&self, i: usize, msg: &MessageView) -> bool {
        let s = &self.sessions[i];
        let p = &self.set.protocols[s.proto];
        p.keys.iter().enumerate().all(|(k, key)| {
            match key.locs.iter().find(|(m, _)| *m == msg.index) {
                Some((_, loc)) => {
                    s.keys[k] == Val::Unknown || s.keys[k] == read_loc(msg.payload, loc)
                }
                None => true,
            }
        })
    }

    fn step_session(&mut self, i: usize, role: usize, msg: &MessageView) -> StepResult {
        let Monitor { sessions, set, tracker, scratch, consts, .. } = self;
        let s = &mut sessions[i];
        let p = &set.protocols[s.proto];
        let input = StepInput {
            msg,
            role,
            consts,
            keys: &s.keys,
            vehicle: tracker.addressed(vehicle_sys(p, &s.ids)),
            param_names: &set.params.names,
        };
        step(p, s.state, &input, &mut s.vars, scratch)
    }

    /// Opens a session if the message starts protocol `p`: `Some(Ok(serial))`, `Some(Err(report))`
    /// when its refinement fails, `None` when the message starts nothing.
    fn try_start(&mut self, p: usize, arrival: &Arrival) -> Option<Result<u64, Box<Violation>>> {
        let Arrival { msg, from, kind, target, time_us } = *arrival;
        let proto = &self.set.protocols[p];
        let role = role_of_kind(proto, kind);
        let ids = session_ids(role, from, target);
        // Cheap pre-check so that most messages allocate nothing here.
        if !proto.states[0]
            .transitions
            .iter()
            .any(|t| t.from == role && t.msgs.iter().any(|l| l.msg == msg.index))
        {
            return None;
        }
        let keys = key_values(proto, msg);
        let mut vars = vec![Val::Unknown; proto.var_names.len()];
        let input = StepInput {
            msg,
            role,
            consts: &self.consts,
            keys: &keys,
            vehicle: self.tracker.addressed(vehicle_sys(proto, &ids)),
            param_names: &self.set.params.names,
        };
        let r = step(proto, 0, &input, &mut vars, &mut self.scratch);
        match r {
            StepResult::Mismatch => None,
            StepResult::Took { next, .. } => {
                self.stats[p].started += 1;
                self.serial += 1;
                match next {
                    None => self.stats[p].completed += 1,
                    Some(state) => {
                        self.make_room(p);
                        self.sessions.push(Session {
                            proto: p,
                            state,
                            ids,
                            keys,
                            vars,
                            last_us: time_us,
                            serial: self.serial,
                        })
                    }
                }
                Some(Ok(self.serial))
            }
            r => {
                let s =
                    Session { proto: p, state: 0, ids, keys, vars, last_us: time_us, serial: 0 };
                Some(Err(Box::new(self.violation_for(&s, role, msg, r, time_us, true))))
            }
        }
    }

    /// Bounds the sessions of one protocol, so that a flood of opening messages (e.g. parameter
    /// reads, which may run concurrently) cannot make every later message slow: the session idle
    /// the longest is closed first.
    fn make_room(&mut self, p: usize) {
        let mine = self.sessions.iter().filter(|s| s.proto == p).count();
        if mine < MAX_SESSIONS_PER_PROTOCOL {
            return;
        }
        let oldest = self
            .sessions
            .iter()
            .enumerate()
            .filter(|(_, s)| s.proto == p)
            .min_by_key(|(_, s)| s.last_us)
            .map(|(i, _)| i);
        if let Some(i) = oldest {
            self.close(i, false);
        }
    }

    fn completable(&self, i: usize) -> bool {
        let s = &self.sessions[i];
        let p = &self.set.protocols[s.proto];
        match &p.states[s.state].complete_when {
            None => false,
            Some(pred) => {
                let env = Env {
                    payload: &[],
                    fields: &[],
                    vars: &s.vars,
                    consts: &self.consts,
                    keys: &s.keys,
                    vehicle: self.tracker.addressed(vehicle_sys(p, &s.ids)),
                    param_names: &self.set.params.names,
                };
                holds(pred, &env)
            }
        }
    }

    /// Removes session `i`, counting it as completed (state complete), unfinished (`at_end`) or abandoned.
    pub(super) fn close(&mut self, i: usize, at_end: bool) {
        let done = self.completable(i);
        let s = self.sessions.swap_remove(i);
        let st = &mut self.stats[s.proto];
        if done {
            st.completed += 1;
        } else if at_end {
            st.unfinished += 1;
        } else {
            st.abandoned += 1;
        }
    }

    fn session_violation(
        &self,
        i: usize,
        role: usize,
        msg: &MessageView,
        r: StepResult,
        time_us: u64,
    ) -> Violation {
        self.violation_for(&self.sessions[i], role, msg, r, time_us, false)
    }
}
