//! Admission of one frame at the trust boundary it crosses — the side of the endpoint it arrived
//! on: integrity, deduplication, the endpoint's incoming filter, signing (ground side), then the
//! inspector, exactly once. Side effects: counters, tlog, violations log, events, alerts and
//! enforce-mode answers.

use std::io::Write;
use std::sync::atomic::Ordering;
use std::time::Instant;

use serde_json::json;

use super::events::{GuardEvent, within_rate};
use super::messages::{SEVERITY_WARNING, statustext};
use super::routing::RouteMask;
use super::state::{Core, lock, unix_micros};
use crate::codec::FrameRef;
use crate::monitor::{Reply, Verdict, Violation};
use crate::side::Side;
use crate::signing::{SETUP_SIGNING_ID, timestamp_now};

/// Most STATUSTEXT alerts per second: a violation flood must not flood the pilot's link too.
const MAX_ALERTS_PER_SECOND: u64 = 5;
/// Most signing rejections written to the violations log (all are counted).
const MAX_LOGGED_SIG_REJECTS: u64 = 100;
/// MAV_AUTOPILOT_INVALID: the autopilot field of HEARTBEATs from ground stations and companions.
const AUTOPILOT_INVALID: u8 = 8;

/// What [`Core::admit`] decided for one candidate frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Admission {
    Forward,
    Drop,
    /// Corrupt: not a frame at all. Datagrams and streams resynchronise after its start marker;
    /// its bytes are then junk (forwarded only where junk passes).
    NotAFrame,
}

impl Core {
    /// Decides whether one length-cut candidate frame received on endpoint `ep` (connection
    /// route `from`) goes on. `NotAFrame` (bad checksum, unknown incompatibility flag) is
    /// counted as malformed and leaves the forwarding of its bytes to the caller (as junk).
    pub(super) fn admit(&self, ep: usize, from: usize, bytes: &[u8]) -> Admission {
        let c = &self.counters;
        let side = self.endpoints[ep].side;
        let Some(fr) = FrameRef::new(bytes) else { return Admission::NotAFrame };
        let verify = if side == Side::Gcs { self.verifier.as_ref() } else { None };
        // Integrity first when something before the inspector judges the frame (signing,
        // deduplication, incoming filter), so that a corrupt frame is resynchronised over rather
        // than counted as a forgery or a duplicate. Counted and recorded in the tlog once known
        // to be a frame: a rejected candidate's bytes are scanned again, and its good frames
        // must not appear twice.
        let early = verify.is_some() || self.dedup.is_some() || !self.endpoints[ep].inbound_open;
        if early {
            if !lock(&self.inspector).is_intact(fr) {
                return self.not_a_frame();
            }
            self.record(ep, bytes);
        }
        if let Some(d) = &self.dedup
            && lock(d).is_duplicate(bytes, Instant::now())
        {
            c.duplicates.fetch_add(1, Ordering::Relaxed);
            return Admission::Drop;
        }
        if !self.endpoints[ep].inbound.passes(fr.msgid(), fr.sysid(), fr.compid()) {
            c.endpoints[ep].filtered_in.fetch_add(1, Ordering::Relaxed);
            return Admission::Drop;
        }
        if let Some(v) = verify
            && let Err(why) = lock(v).check(&fr, timestamp_now())
        {
            let n = c.signing_rejected.fetch_add(1, Ordering::Relaxed);
            if n < MAX_LOGGED_SIG_REJECTS {
                self.log_line(json!({"t_us": unix_micros(), "from": side.as_str(),
                        "endpoint": self.endpoints[ep].name, "action": "dropped", "kind": "signing",
                        "reason": why.as_str(), "sysid": fr.sysid(), "compid": fr.compid(),
                        "msgid": fr.msgid()}));
            }
            return Admission::Drop;
        }
        if fr.is_v2() && fr.msgid() == SETUP_SIGNING_ID {
            // It carries a secret key: never forwarded, whatever the mode (MAVLink signing spec).
            c.setup_signing_dropped.fetch_add(1, Ordering::Relaxed);
            if !early {
                self.record(ep, bytes);
            }
            return Admission::Drop;
        }
        let Ok(verdict) = lock(&self.inspector).inspect(side, fr) else {
            return self.not_a_frame();
        };
        if !early {
            self.record(ep, bytes);
        }
        if fr.msgid() == 0 {
            self.note_heartbeat(ep, &fr);
        }
        match verdict {
            Verdict::Accept | Verdict::Ignore => Admission::Forward,
            Verdict::Unverifiable(_) => {
                self.counters.unverifiable.fetch_add(1, Ordering::Relaxed);
                Admission::Forward
            }
            Verdict::Violation(v) => self.on_violation(ep, from, fr, &v),
        }
    }

    /// Learns the vehicle's ids (alerts are sent in its name) and warns once per ground endpoint
    /// that carries an autopilot's heartbeats: its frames are checked as the ground's.
    fn note_heartbeat(&self, ep: usize, fr: &FrameRef<'_>) {
        let autopilot = fr.payload().get(5).copied().unwrap_or(0);
        match self.endpoints[ep].side {
            Side::Vehicle => {
                if self.vehicle_ids.load(Ordering::Relaxed) == 0 {
                    let packed = (u64::from(fr.sysid()) << 8 | u64::from(fr.compid())) + 1;
                    self.vehicle_ids.store(packed, Ordering::Relaxed);
                }
            }
            Side::Gcs if autopilot != AUTOPILOT_INVALID => {
                if !self.endpoints[ep].warned.swap(true, Ordering::Relaxed) {
                    let endpoint = self.endpoints[ep].name.clone();
                    let (s, cp) = (fr.sysid(), fr.compid());
                    self.events.link(|| GuardEvent::Warning {
                        endpoint,
                        message: format!(
                            "autopilot heartbeats from {s}/{cp} on a ground endpoint: its frames are \
                             checked as coming from the ground (set Side = vehicle if this is the vehicle)"
                        ),
                    });
                }
            }
            Side::Gcs => {}
        }
    }

    /// Counts, logs, reports and (in enforce mode) answers a violation.
    fn on_violation(&self, ep: usize, from: usize, fr: FrameRef<'_>, v: &Violation) -> Admission {
        let c = &self.counters;
        let side = self.endpoints[ep].side;
        c.violations.fetch_add(1, Ordering::Relaxed);
        let summary = v.summary();
        let action = if self.enforce { "dropped" } else { "forwarded" };
        let endpoint = &self.endpoints[ep].name;
        self.log_line(json!({"t_us": unix_micros(), "from": side.as_str(), "endpoint": endpoint,
            "action": action, "kind": "violation", "summary": summary, "sysid": fr.sysid(),
            "compid": fr.compid(), "msgid": fr.msgid(), "frame": hex::encode(fr.bytes), "violation": v}));
        if self.alert_gcs {
            self.alert(&summary);
        }
        let dropped = self.enforce;
        let endpoint = endpoint.clone();
        self.events.violation(|| GuardEvent::Violation { from: side, dropped, summary, endpoint });
        if self.enforce {
            c.dropped_violations.fetch_add(1, Ordering::Relaxed);
            for r in v.replies() {
                self.send_reply(r, side, from);
            }
            Admission::Drop
        } else {
            Admission::Forward
        }
    }

    /// Counts a received frame and appends it to the tlog.
    fn record(&self, ep: usize, bytes: &[u8]) {
        let side = self.endpoints[ep].side;
        self.counters.rx[side.index()].fetch_add(1, Ordering::Relaxed);
        self.counters.endpoints[ep].frames_in.fetch_add(1, Ordering::Relaxed);
        if let Some(t) = &self.tlog {
            let mut t = lock(t);
            let _ = t.write_all(&unix_micros().to_be_bytes()).and_then(|_| t.write_all(bytes));
        }
    }

    fn not_a_frame(&self) -> Admission {
        self.counters.malformed.fetch_add(1, Ordering::Relaxed);
        if self.enforce {
            self.counters.dropped_malformed.fetch_add(1, Ordering::Relaxed);
        }
        Admission::NotAFrame
    }

    /// Sends a guard-made message. An answer to the side the violating frame came from goes back
    /// to exactly that connection; one to the other side goes where its target was seen (all of
    /// that side when nowhere).
    fn send_reply(&self, r: &Reply, from_side: Side, from: usize) {
        let mask: RouteMask = if r.to == from_side {
            1 << from
        } else {
            lock(&self.routes).toward(r.to, r.to_sys, r.to_comp)
        };
        let seq = self.own_seq.fetch_add(1, Ordering::Relaxed);
        let mut frame = r.encode_v2(seq);
        if r.to == Side::Vehicle
            && let Some(signed) = self.sign(&frame)
        {
            frame = signed;
        }
        if self.push(mask, &frame) {
            self.counters.replies_sent.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// A STATUSTEXT to every ground connection, in the vehicle's name so GCSs display it.
    fn alert(&self, summary: &str) {
        if !within_rate(&self.alert_window, MAX_ALERTS_PER_SECOND) {
            self.counters.alerts_suppressed.fetch_add(1, Ordering::Relaxed);
            return;
        }
        let packed = self.vehicle_ids.load(Ordering::Relaxed);
        let (sysid, compid) =
            if packed == 0 { (1, 1) } else { (((packed - 1) >> 8) as u8, (packed - 1) as u8) };
        let r = statustext(SEVERITY_WARNING, &format!("vouch: {summary}"), sysid, compid);
        let seq = self.own_seq.fetch_add(1, Ordering::Relaxed);
        let mask = lock(&self.routes).of_side(Side::Gcs);
        if self.push(mask, &r.encode_v2(seq)) {
            self.counters.alerts_sent.fetch_add(1, Ordering::Relaxed);
        }
    }

    pub(super) fn log_line(&self, v: serde_json::Value) {
        if let Some(l) = &self.log {
            let mut l = lock(l);
            // one complete line per record, flushed: a killed guard leaves a readable log
            let mut line = v.to_string();
            line.push('\n');
            let _ = l.write_all(line.as_bytes()).and_then(|_| l.flush());
        }
    }
}
