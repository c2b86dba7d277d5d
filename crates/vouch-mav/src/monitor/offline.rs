//! Offline checking of a recording: tlog → frames → monitor, with a summary.
//!
//! A recording has no link sides: the monitor derives them from heartbeats (see
//! `monitor::identity`). Findings are split by class: violations, and unverifiable messages
//! (answers to openers that are not in the recording), which are no evidence of a fault.
//! A file that holds no frame at all is no recording: [`check_file`] rejects it, so that a
//! checker never passes what it could not read.

use std::path::Path;

use super::{Monitor, Summary, Verdict, Violation, ViolationKind};
use crate::codec::{CodecStats, MessageView, TlogReader};
use crate::side::Side;
use crate::text::escape_controls;

/// Above this share of a file's bytes outside any frame record, a report warns (`mav::T003`):
/// radio links lose a little (the 3DR-radio recording of the reference set: 1.7 %), a wrong or
/// damaged file loses far more.
pub const UNREAD_WARNING_FRACTION: f64 = 0.05;

/// Result of checking one recording.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RecordingReport {
    pub codec: CodecStats,
    /// Records skipped while resynchronising after broken data.
    pub skipped_records: u64,
    /// Size of the recording in bytes.
    pub bytes: u64,
    /// Bytes that were not part of a frame record (skipped garbage, broken frames, a truncated
    /// tail).
    pub unread_bytes: u64,
    pub summary: Summary,
    /// The only side the recording holds frames of, when it holds one direction only.
    pub one_direction: Option<Side>,
    pub violations: Vec<Violation>,
    /// Messages that could not be verified (their session's opener is not in the recording).
    pub unverifiable: Vec<Violation>,
    /// Wall-clock nanoseconds spent in decode + monitor, divided by frames.
    pub ns_per_message: f64,
}

impl RecordingReport {
    /// The share of the file's bytes that were not frame records (0 for an empty file).
    pub fn unread_fraction(&self) -> f64 {
        if self.bytes == 0 { 0.0 } else { self.unread_bytes as f64 / self.bytes as f64 }
    }

    /// A warning when more than [`UNREAD_WARNING_FRACTION`] of the file was not frames.
    pub fn unread_warning(&self, path: &Path) -> Option<RecordingWarning> {
        (self.unread_fraction() > UNREAD_WARNING_FRACTION).then(|| RecordingWarning::Unread {
            path: escape_controls(&path.display().to_string()).into_owned(),
            unread: self.unread_bytes,
            bytes: self.bytes,
            percent: 100.0 * self.unread_fraction(),
        })
    }
}

/// Why a file could not be checked.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum RecordingError {
    /// The file cannot be read (missing, a directory, no permission).
    #[error("cannot read recording {path}: {source}")]
    #[diagnostic(code(mav::T001))]
    Read {
        /// The file, control characters escaped.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The file holds no valid frame record: empty, another format, or damaged throughout.
    #[error(
        "{path}: no valid MAVLink frame in {bytes} bytes ({unread} bytes are not frame records)"
    )]
    #[diagnostic(
        code(mav::T002),
        help(
            "a recording is a sequence of 8-byte big-endian µs timestamps, each followed by one MAVLink 1 or 2 frame"
        )
    )]
    NoFrame {
        /// The file, control characters escaped.
        path: String,
        /// Its size.
        bytes: u64,
        /// Bytes outside any frame record.
        unread: u64,
    },
}

impl RecordingError {
    /// Whether the file could not be read (an I/O problem, not rejected content).
    pub fn is_io(&self) -> bool {
        matches!(self, RecordingError::Read { .. })
    }
}

/// What a readable recording may deserve a word about.
#[derive(Debug, Clone, thiserror::Error, miette::Diagnostic)]
pub enum RecordingWarning {
    /// A large share of the file was not frames.
    #[error("{path}: {unread} of {bytes} bytes ({percent:.1} %) are not frame records")]
    #[diagnostic(code(mav::T003), severity(Warning))]
    Unread {
        /// The file, control characters escaped.
        path: String,
        /// Bytes outside any frame record.
        unread: u64,
        /// The file's size.
        bytes: u64,
        /// `unread` as a percentage of `bytes`.
        percent: f64,
    },
}

/// Reads a recording and checks it; a file without a single valid frame is rejected.
pub fn check_file(path: &Path, monitor: &mut Monitor) -> Result<RecordingReport, RecordingError> {
    let shown = || escape_controls(&path.display().to_string()).into_owned();
    let data =
        std::fs::read(path).map_err(|source| RecordingError::Read { path: shown(), source })?;
    let report = check_tlog(&data, monitor);
    if report.codec.frames == 0 {
        return Err(RecordingError::NoFrame {
            path: shown(),
            bytes: report.bytes,
            unread: report.unread_bytes,
        });
    }
    Ok(report)
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
    let codec = reader.stats();
    RecordingReport {
        codec,
        skipped_records: reader.skipped_records,
        bytes: data.len() as u64,
        unread_bytes: codec.garbage_bytes.min(data.len() as u64),
        one_direction: summary.one_direction(),
        summary,
        violations,
        unverifiable,
        ns_per_message: if n > 0 { elapsed / n as f64 } else { 0.0 },
    }
}
