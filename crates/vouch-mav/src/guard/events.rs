//! What the running guard reports as it happens, for its caller to print or collect. The
//! counters count everything; events are rate-limited so that a flood of violations cannot flood
//! the caller too.

use std::sync::Mutex;
use std::sync::mpsc::SyncSender;
use std::time::Instant;

use crate::side::Side;

/// Most events per second (all violations are still counted and logged).
pub const MAX_EVENTS_PER_SECOND: u64 = 20;

/// One thing the guard did.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum GuardEvent {
    /// A frame violated a protocol.
    Violation {
        /// Where it came from.
        from: Side,
        /// Whether it was dropped (enforce mode) or forwarded (monitor mode).
        dropped: bool,
        /// One line, e.g. `MISSION_ACK: curr == n (curr=60, n=100)`.
        summary: String,
        /// The endpoint it arrived on.
        endpoint: String,
    },
    /// A connection of an endpoint opened: a TCP client connected or was accepted, a UDP server
    /// heard a new peer.
    Connected {
        /// The endpoint.
        endpoint: String,
        /// The remote address.
        peer: String,
    },
    /// A connection closed, or a TCP client could not connect.
    Disconnected {
        /// The endpoint.
        endpoint: String,
        /// The connection (remote address or client number; `-` for the endpoint's only one).
        peer: String,
        /// Why.
        reason: String,
        /// Seconds until a TCP client tries again, if it does.
        reconnect_in_s: Option<f64>,
    },
    /// Something the operator should look at, e.g. autopilot heartbeats on a ground endpoint.
    Warning {
        /// The endpoint concerned.
        endpoint: String,
        /// What.
        message: String,
    },
}

/// Fixed one-second window rate limiter: true while fewer than `max` events happened in it.
pub(super) fn within_rate(window: &Mutex<(Instant, u64)>, max: u64) -> bool {
    let mut w = window.lock().unwrap_or_else(|e| e.into_inner());
    if w.0.elapsed().as_secs() >= 1 {
        *w = (Instant::now(), 0);
    }
    w.1 += 1;
    w.1 <= max
}

/// A rate-limited, never-blocking sender of events. Violations and connection events have a
/// window each, so that a flood of one kind cannot hide the other.
pub(super) struct Events {
    sink: Option<SyncSender<GuardEvent>>,
    violations: Mutex<(Instant, u64)>,
    links: Mutex<(Instant, u64)>,
}

impl Events {
    pub(super) fn new(sink: Option<SyncSender<GuardEvent>>) -> Self {
        let window = || Mutex::new((Instant::now(), 0));
        Events { sink, violations: window(), links: window() }
    }

    /// Sends a violation event unless there is no sink, the rate is exceeded or the channel is
    /// full (`make` runs only when it is sent).
    pub(super) fn violation(&self, make: impl FnOnce() -> GuardEvent) {
        self.emit(&self.violations, make);
    }

    /// Sends a connection or warning event, in its own rate window.
    pub(super) fn link(&self, make: impl FnOnce() -> GuardEvent) {
        self.emit(&self.links, make);
    }

    fn emit(&self, window: &Mutex<(Instant, u64)>, make: impl FnOnce() -> GuardEvent) {
        if let Some(sink) = &self.sink
            && within_rate(window, MAX_EVENTS_PER_SECOND)
        {
            let _ = sink.try_send(make());
        }
    }
}
