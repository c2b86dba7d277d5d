//! Offline checking of a recording: tlog → frames → monitor, with a summary.
//!
//! A recording has no link sides: the monitor derives them from heartbeats (see
//! `monitor::identity`). Findings are split by class: violations, and unverifiable messages
//! (answers to openers that are not in the recording), which are no evidence of a fault.

use super::{Monitor, Summary, Verdict, Violation, ViolationKind};
use crate::codec::{CodecStats, MessageView, TlogReader};
use crate::side::Side;

/// Result of checking one recording.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RecordingReport {
    pub codec: CodecStats,
    /// Records skipped while resynchronising after broken data.
    pub skipped_records: u64,
    pub summary: Summary,
    /// The only side the recording holds frames of, when it holds one direction only.
    pub one_direction: Option<Side>,
    pub violations: Vec<Violation>,
    /// Messages that could not be verified (their session's opener is not in the recording).
    pub unverifiable: Vec<Violation>,
    /// Wall-clock nanoseconds spent in decode + monitor, divided by frames.
    pub ns_per_message: f64,
}

/// Runs `monitor` over every record of a tlog held in memory, then closes open sessions.
pub fn check_tlog(data: &[u8], monitor: &mut Monitor) -> RecordingReport {
    let dialect = std::sync::Arc::clone(monitor.dialect());
    let mut reader = TlogReader::new(data, &dialect);
    let mut violations = Vec::new();
    let mut unverifiable = Vec::new();
    let start = std::time::Instant::now();
    let mut n = 0u64;
    for rec in reader.by_ref() {
        n += 1;
        let Some(view) = MessageView::of_frame(&rec.frame, &dialect) else {
            continue;
        };
        match monitor.observe(&view, rec.frame.sysid, rec.frame.compid, None, rec.time_us) {
            Verdict::Violation(v) if v.kind == ViolationKind::Unverifiable => unverifiable.push(*v),
            Verdict::Violation(v) => violations.push(*v),
            Verdict::Unverifiable(v) => unverifiable.push(*v),
            Verdict::Accept | Verdict::Ignore => {}
        }
    }
    let elapsed = start.elapsed().as_nanos() as f64;
    monitor.finish();
    let summary = monitor.summary();
    RecordingReport {
        codec: reader.stats(),
        skipped_records: reader.skipped_records,
        one_direction: summary.one_direction(),
        summary,
        violations,
        unverifiable,
        ns_per_message: if n > 0 { elapsed / n as f64 } else { 0.0 },
    }
}
