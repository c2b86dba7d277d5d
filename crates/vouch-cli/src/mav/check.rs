//! `vouch mav check`: recordings through the monitor, one report per file.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::Args;
use vouch_mav::monitor::offline::{RecordingReport, check_tlog};

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

pub fn run(a: CheckArgs, ctx: &mut Ctx) -> CmdResult {
    let monitor = a.monitor.spec().build().map_err(load_failure)?;
    let mut text = String::new();
    let mut files = Vec::new();
    let mut violations = 0usize;
    for file in &a.files {
        let data = std::fs::read(file).map_err(|e| Failure::io(file, &e))?;
        let report = check_tlog(&data, &mut monitor.fresh());
        violations += report.violations.len();
        if a.json {
            files.push(serde_json::json!({ "file": file.display().to_string(), "report": report }));
            continue;
        }
        let mut one = String::new();
        write_report(&mut one, file, &report, a.max_reports)
            .map_err(|e| Failure::usage(format_args!("formatting the report: {e}")))?;
        match a.output {
            Some(_) => text.push_str(&one),
            // File by file: a reader that stops early (`| head`) ends the command at once.
            None => ctx.out.write_all(one.as_bytes())?,
        }
    }
    if a.json {
        let doc = serde_json::json!({ "files": files, "violations": violations });
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
    Ok(if violations > 0 { Exit::Findings } else { Exit::Ok })
}

fn write_report(w: &mut String, file: &Path, r: &RecordingReport, max: usize) -> std::fmt::Result {
    let c = &r.codec;
    writeln!(w, "{}", file.display())?;
    writeln!(
        w,
        "  frames {} (v1 {}, v2 {}, signed {}), messages checked {}, relevant to protocols {}",
        c.frames, c.frames_v1, c.frames_v2, c.signed, r.summary.messages, r.summary.relevant
    )?;
    writeln!(
        w,
        "  input problems: bad crc {}, bad length {}, unknown id {}, bad incompat flags {}, truncated {}, garbage bytes {}, records skipped {}",
        c.bad_crc,
        c.bad_length,
        c.unknown_id,
        c.bad_incompat,
        c.truncated,
        c.garbage_bytes,
        r.skipped_records
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
