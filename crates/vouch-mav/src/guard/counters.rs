//! The guard's counters: updated lock-free by the reader threads, read as a snapshot.

use std::sync::atomic::{AtomicU64, Ordering};

use serde::Serialize;

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
}

/// Counters at one moment (e.g. at shutdown).
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct CounterSnapshot {
    /// Intact frames received from the GCS side.
    pub frames_from_gcs: u64,
    /// Intact frames received from the vehicle side.
    pub frames_from_vehicle: u64,
    /// Frames forwarded to the vehicle.
    pub forwarded_to_vehicle: u64,
    /// Frames forwarded to the GCS side.
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
    /// Frames from the GCS side that failed the signing check.
    pub signing_rejected: u64,
    /// Writes of the signing state file that failed (retried every second).
    pub signing_state_write_failures: u64,
    /// SETUP_SIGNING frames dropped (never forwarded).
    pub setup_signing_dropped: u64,
    /// Answers sent in enforce mode.
    pub replies_sent: u64,
    /// STATUSTEXT alerts sent to the GCS side.
    pub alerts_sent: u64,
    /// Alerts not sent because of the rate limit.
    pub alerts_suppressed: u64,
}

impl CounterSnapshot {
    /// (name, value) in the order they are printed at shutdown.
    pub fn rows(&self) -> [(&'static str, u64); 16] {
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
        ]
    }
}

impl Counters {
    /// The values now.
    pub(super) fn snapshot(&self) -> CounterSnapshot {
        let c = self;
        let g = |a: &AtomicU64| a.load(Ordering::Relaxed);
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
        }
    }
}
