//! Offline checking of a recording: tlog → frames → monitor, with a summary.

use super::{Monitor, Summary, Verdict, Violation};
use crate::codec::{CodecStats, MessageView, TlogReader};

/// Result of checking one recording.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RecordingReport {
    pub codec: CodecStats,
    /// Records skipped while resynchronising after broken data.
    pub skipped_records: u64,
    pub summary: Summary,
    pub violations: Vec<Violation>,
    /// Wall-clock nanoseconds spent in decode + monitor, divided by frames.
    pub ns_per_message: f64,
}

/// Runs `monitor` over every record of a tlog held in memory, then closes open sessions.
pub fn check_tlog(data: &[u8], monitor: &mut Monitor) -> RecordingReport {
    let dialect = std::sync::Arc::clone(monitor.dialect());
    let mut reader = TlogReader::new(data, &dialect);
    let mut violations = Vec::new();
    let start = std::time::Instant::now();
    let mut n = 0u64;
    for rec in reader.by_ref() {
        n += 1;
        let Some(view) = MessageView::of_frame(&rec.frame, &dialect) else {
            continue;
        };
        if let Verdict::Violation(v) =
            monitor.observe(&view, rec.frame.sysid, rec.frame.compid, None, rec.time_us)
        {
            violations.push(*v);
        }
    }
    let elapsed = start.elapsed().as_nanos() as f64;
    monitor.finish();
    RecordingReport {
        codec: reader.stats(),
        skipped_records: reader.skipped_records,
        summary: monitor.summary(),
        violations,
        ns_per_message: if n > 0 { elapsed / n as f64 } else { 0.0 },
    }
}
