//! `vouch mav check`: recordings through the monitor, one report per file.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use vouch_mav::monitor::offline::{RecordingError, RecordingReport, check_file};
use vouch_mav::text::escape_controls;

use super::{MonitorOpts, load_failure};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch mav check`.
#[derive(Args)]
pub struct CheckArgs {
    /// Recording(s): 8-byte big-endian µs timestamp + raw frame, repeated
    #[arg(required = true, value_name = "FILE.tlog")]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub monitor: MonitorOpts,
    /// Print one JSON document (every file's counters, violations and unverifiable messages)
    /// instead of text
    #[arg(long)]
    pub json: bool,
    /// Write the report to FILE instead of standard output
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Print at most this many violations per file in the text report (all are counted)
    #[arg(long, default_value_t = 50, value_name = "N")]
    pub max_reports: usize,
}

/// Version of the `--json` document: 2 added `version`, per-file `bytes`, `unread_bytes`,
/// `warnings` and `error` (a file that could not be checked).
const CHECK_JSON_VERSION: u32 = 2;

pub fn run(a: CheckArgs, ctx: &mut Ctx) -> CmdResult {
    let monitor = a.monitor.spec().build().map_err(load_failure)?;
    let mut text = String::new();
    let mut files = Vec::new();
    let mut violations = 0usize;
    // The first file that could not be checked decides the exit status (I/O before rejected).
    let mut failure: Option<RecordingError> = None;
    for file in &a.files {
        let shown = escape_controls(&file.display().to_string()).into_owned();
        let report = match check_file(file, &mut monitor.fresh()) {
            Ok(r) => r,
            Err(e) => {
                let line = format!("{shown}\n  error[{}]: {e}\n", code_of(&e));
                if a.json {
                    let error =
                        serde_json::json!({ "code": code_of(&e), "message": e.to_string() });
                    files.push(serde_json::json!({ "file": shown, "error": error }));
                } else {
                    emit(&mut text, ctx, a.output.is_some(), &line)?;
                }
                if failure.as_ref().is_none_or(|f| e.is_io() && !f.is_io()) {
                    failure = Some(e);
                }
                continue;
            }
        };
        violations += report.violations.len();
        let warning = report.unread_warning(file);
        if let Some(w) = &warning {
            ctx.warn(w);
        }
        if a.json {
            let warnings: Vec<_> = warning
                .iter()
                .map(|w| serde_json::json!({ "code": "mav::T003", "message": w.to_string() }))
                .collect();
            files
                .push(serde_json::json!({ "file": shown, "report": report, "warnings": warnings }));
            continue;
        }
        let mut one = String::new();
        write_report(&mut one, &shown, &report, a.max_reports)
            .map_err(|e| Failure::usage(format_args!("formatting the report: {e}")))?;
        emit(&mut text, ctx, a.output.is_some(), &one)?;
    }
    if a.json {
        let doc = serde_json::json!({
            "version": CHECK_JSON_VERSION,
            "files": files,
            "violations": violations,
            "unreadable_files": files.iter().filter(|f| f.get("error").is_some()).count(),
        });
        match &a.output {
            Some(_) => {
                text = serde_json::to_string_pretty(&doc)
                    .map_err(|e| Failure::usage(format_args!("JSON report: {e}")))?;
                text.push('\n');
            }
            None => ctx.out.json(&doc)?,
        }
    }
    if let Some(out) = &a.output {
        std::fs::write(out, text).map_err(|e| Failure::io(out, &e))?;
    }
    match failure {
        // A checker never passes what it could not read: one such file fails the run.
        Some(e) if e.is_io() => Err(Failure::Usage(miette::Report::new(e))),
        Some(e) => Err(Failure::rejected(e)),
        None => Ok(if violations > 0 { Exit::Findings } else { Exit::Ok }),
    }
}

/// The report of one file: into the output file's text, or at once to standard output (file by
/// file: a reader that stops early, `| head`, ends the command at once).
fn emit(text: &mut String, ctx: &mut Ctx, to_file: bool, one: &str) -> Result<(), Failure> {
    if to_file {
        text.push_str(one);
        Ok(())
    } else {
        ctx.out.write_all(one.as_bytes())
    }
}

fn code_of(e: &RecordingError) -> String {
    miette::Diagnostic::code(e).map(|c| c.to_string()).unwrap_or_default()
}

fn write_report(w: &mut String, file: &str, r: &RecordingReport, max: usize) -> std::fmt::Result {
    let c = &r.codec;
    writeln!(w, "{file}")?;
    writeln!(
        w,
        "  frames {} (v1 {}, v2 {}, signed {}), messages checked {}, relevant to protocols {}",
        c.frames, c.frames_v1, c.frames_v2, c.signed, r.summary.messages, r.summary.relevant
    )?;
    writeln!(
        w,
        "  input problems: bad crc {}, bad length {}, unknown id {}, bad incompat flags {}, truncated {}, garbage bytes {}, records skipped {}; {} of {} bytes ({:.2} %) not frame records",
        c.bad_crc,
        c.bad_length,
        c.unknown_id,
        c.bad_incompat,
        c.truncated,
        c.garbage_bytes,
        r.skipped_records,
        r.unread_bytes,
        r.bytes,
        100.0 * r.unread_fraction()
    )?;
    let s = &r.summary;
    writeln!(
        w,
        "  sides (derived from heartbeats): gcs {}, vehicle {}",
        s.from_gcs, s.from_vehicle
    )?;
    if let Some(side) = r.one_direction {
        writeln!(
            w,
            "  only one direction is recorded ({} side): answers to requests that are not in \
             the recording are unverifiable, not violations",
            side.as_str()
        )?;
    }
    writeln!(
        w,
        "  {:<26} {:>8} {:>10} {:>10} {:>11} {:>11} {:>13}",
        "protocol", "started", "completed", "abandoned", "unfinished", "violations", "unverifiable"
    )?;
    for p in &s.protocols {
        writeln!(
            w,
            "  {:<26} {:>8} {:>10} {:>10} {:>11} {:>11} {:>13}",
            p.name, p.started, p.completed, p.abandoned, p.unfinished, p.violations, p.unverifiable
        )?;
    }
    if !r.unverifiable.is_empty() {
        writeln!(
            w,
            "  unverifiable: {} (their sessions' openers are not in the recording; listed with --json)",
            r.unverifiable.len()
        )?;
    }
    writeln!(w, "  violations: {}", r.violations.len())?;
    for v in r.violations.iter().take(max) {
        writeln!(w, "  - t={} µs {v}", v.time_us)?;
    }
    if r.violations.len() > max {
        writeln!(w, "  … {} more (use --max-reports or --json)", r.violations.len() - max)?;
    }
    writeln!(w, "  decode + monitor: {:.0} ns/message", r.ns_per_message)
}
