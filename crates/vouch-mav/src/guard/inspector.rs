//! The protocol monitor as the guard's [`Inspector`].
//!
//! The proxy cuts frames by length only; here each candidate is read again with the dialect
//! (checksum with CRC_EXTRA, incompatibility flags, length) and handed to the monitor with the
//! side it arrived on.

use std::time::{SystemTime, UNIX_EPOCH};

use super::Inspector;
use crate::codec::{parse_frame, FrameRef, InvalidKind, Parse};
use crate::monitor::{Monitor, Verdict};
use crate::side::Side;

/// Judges frames with a [`Monitor`] (built with [`MonitorSpec`](crate::monitor::MonitorSpec)).
pub struct MonitorInspector {
    monitor: Monitor,
}

impl MonitorInspector {
    /// Wraps a monitor.
    pub fn new(monitor: Monitor) -> Self {
        MonitorInspector { monitor }
    }

    /// The monitor (its protocols, counters, vehicle state).
    pub fn monitor(&self) -> &Monitor {
        &self.monitor
    }
}

fn now_us() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_micros() as u64).unwrap_or(0)
}

impl Inspector for MonitorInspector {
    fn is_intact(&mut self, frame: FrameRef<'_>) -> bool {
        matches!(parse_frame(frame.bytes, self.monitor.dialect(), true), Parse::Frame(_))
    }

    fn inspect(&mut self, from: Side, frame: FrameRef<'_>) -> Result<Verdict, InvalidKind> {
        // The candidate is exactly one length-cut frame, so what parses is all of it.
        let f = match parse_frame(frame.bytes, self.monitor.dialect(), true) {
            Parse::Frame(f) => f,
            Parse::Invalid(kind) => return Err(kind),
            Parse::Incomplete => return Err(InvalidKind::BadLength),
        };
        Ok(self.monitor.on_frame(&f, Some(from), now_us()))
    }
}
