//! The protocol monitor as the guard's [`Inspector`]: the per-frame decision at the boundary.
//!
//! The proxy cuts frames by length only; here each candidate is verified with the dialect
//! (checksum with CRC_EXTRA, incompatibility flags, length) and handed to the monitor with the
//! side it arrived on. The monitor holds the trust boundary (frames from the GCS side that claim a
//! vehicle's identity are violations; vehicle state is learned from the vehicle side only) and
//! classifies each message: accepted, ignored, unverifiable (its protocol's policy says whether
//! it passes) or a violation (dropped and answered in enforce mode).
//!
//! A candidate whose message id the dialect does not know cannot be verified (its checksum needs
//! the message's CRC_EXTRA), so it is not a frame: the proxy rescans from the byte after its start
//! marker, exactly as after a bad checksum, and drops its bytes in enforce mode. That is also what
//! keeps a stray header from swallowing the good frames behind it. An operator may opt in to pass
//! unknown ids ([`MonitorInspector::pass_unknown_ids`]); even then a candidate is refused when a
//! frame of a known id starts inside it and either verifies there or runs past its end (which
//! cannot be checked from the candidate).

use std::time::{SystemTime, UNIX_EPOCH};

use super::Inspector;
use crate::codec::frame::{MAGIC_V2, V1_HEADER_LEN, V2_HEADER_LEN, is_magic};
use crate::codec::{Frame, FrameRef, InvalidKind, Parse, parse_frame};
use crate::dialect::Dialect;
use crate::monitor::{Monitor, Reply, Verdict, Violation};
use crate::side::Side;

/// Judges frames with a [`Monitor`] (built with [`MonitorSpec`](crate::monitor::MonitorSpec)).
pub struct MonitorInspector {
    monitor: Monitor,
    pass_unknown: bool,
}

impl MonitorInspector {
    /// Wraps a monitor. Frames of message ids the dialect does not know are refused.
    pub fn new(monitor: Monitor) -> Self {
        MonitorInspector { monitor, pass_unknown: false }
    }

    /// Lets frames of message ids the dialect does not know pass unchecked (the MAVLink routing
    /// rule), except a candidate that could hide a frame of a known id (module documentation).
    pub fn pass_unknown_ids(mut self, pass: bool) -> Self {
        self.pass_unknown = pass;
        self
    }

    /// The monitor (its protocols, counters, vehicle state).
    pub fn monitor(&self) -> &Monitor {
        &self.monitor
    }

    /// The frame, if the candidate is one: checksum, flags and length verified for a known id,
    /// or an unknown id that is let pass and hides no frame of a known id.
    fn verify<'a>(&self, frame: FrameRef<'a>) -> Result<Frame<'a>, InvalidKind> {
        let dialect = self.monitor.dialect();
        // The candidate is exactly one length-cut frame, so what parses is all of it.
        match parse_frame(frame.bytes, dialect, true) {
            Parse::Frame(f) if f.msg.is_some() => Ok(f),
            Parse::Frame(f) if self.pass_unknown && !hides_a_known_frame(f.bytes, dialect) => Ok(f),
            Parse::Frame(_) => Err(InvalidKind::UnknownId),
            Parse::Invalid(kind) => Err(kind),
            Parse::Incomplete => Err(InvalidKind::BadLength),
        }
    }
}

/// Whether a frame of a known message id starts inside `bytes` (after its first byte) and either
/// verifies there or runs past the end (so that it cannot be ruled out).
fn hides_a_known_frame(bytes: &[u8], dialect: &Dialect) -> bool {
    (1..bytes.len()).filter(|&j| is_magic(bytes[j])).any(|j| {
        let rest = &bytes[j..];
        match parse_frame(rest, dialect, false) {
            Parse::Frame(_) => true,
            // ends past the candidate: a frame of a known id cannot be ruled out
            Parse::Incomplete => known_id_header(rest, dialect),
            Parse::Invalid(_) => false,
        }
    })
}

/// Whether `rest` holds a whole header that names a message id the dialect knows.
fn known_id_header(rest: &[u8], dialect: &Dialect) -> bool {
    let id = if rest[0] == MAGIC_V2 {
        rest.get(7..V2_HEADER_LEN).map(|b| u32::from_le_bytes([b[0], b[1], b[2], 0]))
    } else {
        rest.get(V1_HEADER_LEN - 1).map(|&b| u32::from(b))
    };
    id.is_some_and(|id| dialect.index_of_id(id).is_some())
}

/// Makes every answer to the ground come from a vehicle the guard knows. A protocol's reply is
/// sent in the name of the peer the refused message addressed; a command to system 0 (broadcast)
/// or component 0 names no sender, and ground stations (MAVProxy, QGroundControl) attribute
/// messages by their source, so an answer from system 0 belongs to no vehicle and is never
/// seen. Such an answer is sent once from each vehicle the guard knows (from its autopilot's
/// component), and not at all when it knows none; one from component 0 of a vehicle comes from
/// that vehicle's autopilot.
fn address_replies(monitor: &Monitor, v: &mut Violation) {
    let vehicles: Vec<(u8, u8)> = monitor
        .vehicles()
        .states()
        .map(|(sys, st)| (sys, st.autopilot_comp.unwrap_or(AUTOPILOT_COMP)))
        .collect();
    let mut out: Vec<Reply> = Vec::new();
    for r in v.replies() {
        if r.to != Side::Gcs || (r.from_sys != 0 && r.from_comp != 0) {
            out.push(r.clone());
            continue;
        }
        let senders: Vec<(u8, u8)> = if r.from_sys == 0 {
            vehicles.clone()
        } else {
            let comp = vehicles.iter().find(|(s, _)| *s == r.from_sys).map(|(_, c)| *c);
            vec![(r.from_sys, comp.unwrap_or(AUTOPILOT_COMP))]
        };
        for (sys, comp) in senders {
            out.push(Reply { from_sys: sys, from_comp: comp, ..r.clone() });
        }
    }
    let mut replies = out.into_iter();
    v.reply = replies.next();
    v.more_replies = replies.collect();
}

/// MAV_COMP_ID_AUTOPILOT1: the autopilot's component when its heartbeat was not seen.
const AUTOPILOT_COMP: u8 = 1;

fn now_us() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_micros() as u64).unwrap_or(0)
}

impl Inspector for MonitorInspector {
    fn is_intact(&mut self, frame: FrameRef<'_>) -> bool {
        self.verify(frame).is_ok()
    }

    fn inspect(&mut self, from: Side, frame: FrameRef<'_>) -> Result<Verdict, InvalidKind> {
        let f = self.verify(frame)?;
        let mut verdict = self.monitor.on_frame(&f, Some(from), now_us());
        if let Verdict::Violation(v) = &mut verdict {
            address_replies(&self.monitor, v);
        }
        Ok(verdict)
    }
}
