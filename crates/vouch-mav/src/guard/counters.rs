//! The guard's counters: updated lock-free by the reader threads, read as a snapshot — for the
//! whole router and per endpoint.

use std::sync::atomic::{AtomicU64, Ordering};

use serde::Serialize;

use super::config::side_word;
use crate::side::Side;

/// Live counters of one endpoint.
#[derive(Default)]
pub(super) struct EndpointCounters {
    pub(super) frames_in: AtomicU64,
    pub(super) frames_out: AtomicU64,
    pub(super) bytes_out: AtomicU64,
    pub(super) filtered_in: AtomicU64,
    pub(super) filtered_out: AtomicU64,
    pub(super) send_errors: AtomicU64,
    pub(super) connections: AtomicU64,
    pub(super) connects: AtomicU64,
}

/// Live counters, updated by the reader threads.
#[derive(Default)]
pub(super) struct Counters {
    pub(super) rx: [AtomicU64; 2],
    pub(super) forwarded: [AtomicU64; 2],
    pub(super) violations: AtomicU64,
    pub(super) dropped_violations: AtomicU64,
    pub(super) unverifiable: AtomicU64,
    pub(super) malformed: AtomicU64,
    pub(super) dropped_malformed: AtomicU64,
    pub(super) junk_bytes: AtomicU64,
    pub(super) signing_rejected: AtomicU64,
    pub(super) signing_state_failures: AtomicU64,
    pub(super) setup_signing_dropped: AtomicU64,
    pub(super) replies_sent: AtomicU64,
    pub(super) alerts_sent: AtomicU64,
    pub(super) alerts_suppressed: AtomicU64,
    pub(super) unrouted: AtomicU64,
    pub(super) duplicates: AtomicU64,
    pub(super) endpoints: Vec<EndpointCounters>,
}

/// One endpoint's counters at one moment.
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct EndpointSnapshot {
    /// The endpoint's name.
    pub name: String,
    /// The side its frames are trusted as: `vehicle` or `ground`.
    pub side: String,
    /// Its connection, e.g. `udpout:127.0.0.1:14550`.
    pub link: String,
    /// Intact frames received (before the incoming filter).
    pub frames_in: u64,
    /// Frames sent (counted once per endpoint, whatever number of connections got them).
    pub frames_out: u64,
    /// Bytes sent, over all its connections.
    pub bytes_out: u64,
    /// Frames the incoming filter dropped.
    pub filtered_in: u64,
    /// Frames the outgoing filter kept from it.
    pub filtered_out: u64,
    /// Sends that failed (no peer connected, socket error).
    pub send_errors: u64,
    /// Connections open now (UDP server peers, TCP clients, a connected TCP client).
    pub connections: u64,
    /// Connections opened so far.
    pub connects: u64,
}

/// Counters at one moment (e.g. at shutdown).
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct CounterSnapshot {
    /// Intact frames received on ground endpoints.
    pub frames_from_gcs: u64,
    /// Intact frames received on vehicle endpoints.
    pub frames_from_vehicle: u64,
    /// Frames sent to vehicle endpoints (once per endpoint).
    pub forwarded_to_vehicle: u64,
    /// Frames sent to ground endpoints (once per endpoint).
    pub forwarded_to_gcs: u64,
    /// Protocol violations (forwarded in monitor mode, dropped in enforce mode).
    pub violations: u64,
    /// Violating frames dropped (enforce mode).
    pub dropped_violations: u64,
    /// Frames the monitor could not verify (answers to requests it did not see) that the
    /// protocol's policy lets pass.
    pub unverifiable_forwarded: u64,
    /// Length-cut candidates that were no intact frame (a corrupt frame with start markers inside can count more than once).
    pub malformed: u64,
    /// Of those, dropped (enforce mode).
    pub dropped_malformed: u64,
    /// Bytes that were part of no frame.
    pub junk_bytes: u64,
    /// Frames from ground endpoints that failed the signing check.
    pub signing_rejected: u64,
    /// Writes of the signing state file that failed (retried every second).
    pub signing_state_write_failures: u64,
    /// SETUP_SIGNING frames dropped (never forwarded).
    pub setup_signing_dropped: u64,
    /// Answers sent in enforce mode.
    pub replies_sent: u64,
    /// STATUSTEXT alerts sent to ground endpoints.
    pub alerts_sent: u64,
    /// Alerts not sent because of the rate limit.
    pub alerts_suppressed: u64,
    /// Admitted frames no endpoint took (a target never seen, or every route filtered it).
    pub unrouted: u64,
    /// Frames dropped as copies of one received within the deduplication period.
    pub duplicates: u64,
    /// Per endpoint, in configuration order.
    pub endpoints: Vec<EndpointSnapshot>,
}

impl CounterSnapshot {
    /// (name, value) of the router-wide counters, in the order they are printed.
    pub fn rows(&self) -> [(&'static str, u64); 18] {
        [
            ("frames from gcs", self.frames_from_gcs),
            ("forwarded to vehicle", self.forwarded_to_vehicle),
            ("frames from vehicle", self.frames_from_vehicle),
            ("forwarded to gcs", self.forwarded_to_gcs),
            ("violations", self.violations),
            ("dropped violations", self.dropped_violations),
            ("unverifiable passed", self.unverifiable_forwarded),
            ("malformed frames", self.malformed),
            ("dropped malformed", self.dropped_malformed),
            ("junk bytes", self.junk_bytes),
            ("signing rejected", self.signing_rejected),
            ("signing state failed", self.signing_state_write_failures),
            ("SETUP_SIGNING dropped", self.setup_signing_dropped),
            ("replies sent", self.replies_sent),
            ("alerts sent", self.alerts_sent),
            ("alerts rate-limited", self.alerts_suppressed),
            ("unrouted", self.unrouted),
            ("duplicates dropped", self.duplicates),
        ]
    }

    /// The counters of the endpoint named `name`.
    pub fn endpoint(&self, name: &str) -> Option<&EndpointSnapshot> {
        self.endpoints.iter().find(|e| e.name == name)
    }
}

impl Counters {
    pub(super) fn new(endpoints: usize) -> Self {
        Counters {
            endpoints: (0..endpoints).map(|_| EndpointCounters::default()).collect(),
            ..Counters::default()
        }
    }

    /// The values now; `names` gives each endpoint's (name, side, link).
    pub(super) fn snapshot(&self, names: &[(String, Side, String)]) -> CounterSnapshot {
        let c = self;
        let g = |a: &AtomicU64| a.load(Ordering::Relaxed);
        let endpoints = c
            .endpoints
            .iter()
            .zip(names)
            .map(|(e, (name, side, link))| EndpointSnapshot {
                name: name.clone(),
                side: side_word(*side).to_string(),
                link: link.clone(),
                frames_in: g(&e.frames_in),
                frames_out: g(&e.frames_out),
                bytes_out: g(&e.bytes_out),
                filtered_in: g(&e.filtered_in),
                filtered_out: g(&e.filtered_out),
                send_errors: g(&e.send_errors),
                connections: g(&e.connections),
                connects: g(&e.connects),
            })
            .collect();
        CounterSnapshot {
            frames_from_gcs: g(&c.rx[0]),
            frames_from_vehicle: g(&c.rx[1]),
            forwarded_to_vehicle: g(&c.forwarded[1]),
            forwarded_to_gcs: g(&c.forwarded[0]),
            violations: g(&c.violations),
            dropped_violations: g(&c.dropped_violations),
            unverifiable_forwarded: g(&c.unverifiable),
            malformed: g(&c.malformed),
            dropped_malformed: g(&c.dropped_malformed),
            junk_bytes: g(&c.junk_bytes),
            signing_rejected: g(&c.signing_rejected),
            signing_state_write_failures: g(&c.signing_state_failures),
            setup_signing_dropped: g(&c.setup_signing_dropped),
            replies_sent: g(&c.replies_sent),
            alerts_sent: g(&c.alerts_sent),
            alerts_suppressed: g(&c.alerts_suppressed),
            unrouted: g(&c.unrouted),
            duplicates: g(&c.duplicates),
            endpoints,
        }
    }
}
