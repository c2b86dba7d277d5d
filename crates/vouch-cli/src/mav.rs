//! `vouch mav …` subcommands (owned by the mav family).
//!
//! `check` and `lint` are the monitor's (mav-monitor); `guard` and `bench` are added by the guard
//! (mav-guard). Shared option handling lives in the helpers at the bottom (`load_dialect`,
//! `load_monitor`, `parse_set`) so new subcommands reuse it.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use clap::{Args, Subcommand};
use vouch_mav::dialect::{load_dialect_file, Dialect};
use vouch_mav::monitor::offline::check_tlog;
use vouch_mav::monitor::Monitor;
use vouch_mav::protocol::{lint, stdlib};

// `guard` and `bench` (mav-guard) live in their own file.
#[path = "mav_guard.rs"]
mod guard_cli;

#[derive(Subcommand)]
pub enum MavCmd {
    /// Check recordings (.tlog) against session-type protocols (standard library by default)
    Check(CheckArgs),
    /// Check protocol files against a dialect (standard library if no file is given)
    Lint(LintArgs),
    /// Proxy between ground station(s) and vehicle checking every message (monitor or enforce)
    Guard(guard_cli::GuardCli),
    /// Latency, throughput and RSS of the guard vs a direct path and a socat relay (loopback)
    Bench(guard_cli::BenchCli),
}

/// Options shared by every subcommand that runs the monitor.
#[derive(Args, Clone, Debug)]
pub struct MonitorOpts {
    /// Protocol file(s); replaces the standard library unless --with-stdlib is given
    #[arg(long = "protocol", value_name = "FILE")]
    pub protocols: Vec<PathBuf>,
    /// Also load the standard library when --protocol is given
    #[arg(long)]
    pub with_stdlib: bool,
    /// MAVLink XML dialect (default: ardupilotmega with its includes, built in)
    #[arg(long, value_name = "FILE.xml")]
    pub dialect: Option<PathBuf>,
    /// Override a protocol constant, e.g. --set CHUTE_MAX_CLIMB=0.5
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
}

#[derive(Args)]
pub struct CheckArgs {
    /// Recording(s): 8-byte big-endian µs timestamp + raw frame, repeated
    #[arg(required = true, value_name = "FILE.tlog")]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub monitor: MonitorOpts,
    /// Machine-readable output (one JSON document)
    #[arg(long)]
    pub json: bool,
    /// Print at most this many violations per file (all are counted)
    #[arg(long, default_value_t = 50)]
    pub max_reports: usize,
}

#[derive(Args)]
pub struct LintArgs {
    /// Protocol file(s)
    #[arg(value_name = "PROTOCOL")]
    pub files: Vec<PathBuf>,
    /// MAVLink XML dialect (default: built-in ardupilotmega)
    #[arg(long, value_name = "FILE.xml")]
    pub dialect: Option<PathBuf>,
}

pub fn run(cmd: MavCmd, _ctx: &mut crate::contract::Ctx) -> crate::contract::CmdResult {
    crate::legacy(run_legacy(cmd))
}

fn run_legacy(cmd: MavCmd) -> ExitCode {
    match cmd {
        MavCmd::Check(a) => check(a),
        MavCmd::Lint(a) => lint_cmd(a),
        MavCmd::Guard(a) => guard_cli::guard(a),
        MavCmd::Bench(a) => guard_cli::bench(a),
    }
}

fn check(a: CheckArgs) -> ExitCode {
    let dialect = match load_dialect(a.monitor.dialect.as_deref()) {
        Ok(d) => d,
        Err(code) => return code,
    };
    let mut reports = Vec::new();
    let mut total_violations = 0usize;
    for file in &a.files {
        let data = match std::fs::read(file) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("error: cannot read {}: {e}", file.display());
                return ExitCode::from(2);
            }
        };
        let mut monitor = match load_monitor(&dialect, &a.monitor) {
            Ok(m) => m,
            Err(code) => return code,
        };
        let report = check_tlog(&data, &mut monitor);
        total_violations += report.violations.len();
        if !a.json {
            print_report(file, &report, a.max_reports);
        }
        reports.push(serde_json::json!({ "file": file.display().to_string(), "report": report }));
    }
    if a.json {
        let doc = serde_json::json!({ "files": reports, "violations": total_violations });
        println!("{}", serde_json::to_string_pretty(&doc).unwrap_or_default());
    }
    if total_violations > 0 {
        ExitCode::from(3)
    } else {
        ExitCode::SUCCESS
    }
}

fn print_report(file: &Path, r: &vouch_mav::monitor::offline::RecordingReport, max: usize) {
    let c = &r.codec;
    println!("{}", file.display());
    println!(
        "  frames {} (v1 {}, v2 {}, signed {}), messages checked {}, relevant to protocols {}",
        c.frames, c.frames_v1, c.frames_v2, c.signed, r.summary.messages, r.summary.relevant
    );
    println!(
        "  input problems: bad crc {}, bad length {}, unknown id {}, bad incompat flags {}, truncated {}, garbage bytes {}, records skipped {}",
        c.bad_crc, c.bad_length, c.unknown_id, c.bad_incompat, c.truncated, c.garbage_bytes, r.skipped_records
    );
    println!(
        "  {:<26} {:>8} {:>10} {:>10} {:>11} {:>11}",
        "protocol", "started", "completed", "abandoned", "unfinished", "violations"
    );
    for p in &r.summary.protocols {
        println!(
            "  {:<26} {:>8} {:>10} {:>10} {:>11} {:>11}",
            p.name, p.started, p.completed, p.abandoned, p.unfinished, p.violations
        );
    }
    println!("  violations: {}", r.violations.len());
    for v in r.violations.iter().take(max) {
        println!("  - t={} µs {v}", v.time_us);
    }
    if r.violations.len() > max {
        println!("  … {} more (use --max-reports or --json)", r.violations.len() - max);
    }
    println!("  decode + monitor: {:.0} ns/message", r.ns_per_message);
}

fn lint_cmd(a: LintArgs) -> ExitCode {
    let dialect = match load_dialect(a.dialect.as_deref()) {
        Ok(d) => d,
        Err(code) => return code,
    };
    let sources = if a.files.is_empty() {
        stdlib::sources()
    } else {
        match read_sources(&a.files) {
            Ok(s) => s,
            Err(code) => return code,
        }
    };
    match lint(&dialect, &sources) {
        Ok(set) => {
            for p in &set.protocols {
                println!(
                    "ok: protocol {} ({} states, {} messages, roles {})",
                    p.name,
                    p.states.len(),
                    p.alphabet.len(),
                    p.roles.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ")
                );
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{:?}", miette::Report::new(e));
            ExitCode::from(1)
        }
    }
}

// ---- helpers shared by the mav subcommands ----

/// The dialect from `--dialect` or the built-in default; prints the error and returns exit 2.
pub fn load_dialect(path: Option<&Path>) -> Result<Arc<Dialect>, ExitCode> {
    let d = match path {
        Some(p) => load_dialect_file(p),
        None => Dialect::default_dialect(),
    };
    d.map(Arc::new).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

fn read_sources(files: &[PathBuf]) -> Result<Vec<(String, String)>, ExitCode> {
    files
        .iter()
        .map(|f| {
            std::fs::read_to_string(f).map(|t| (f.display().to_string(), t)).map_err(|e| {
                eprintln!("error: cannot read {}: {e}", f.display());
                ExitCode::from(2)
            })
        })
        .collect()
}

/// `NAME=VALUE` pairs of `--set`.
pub fn parse_set(items: &[String]) -> Result<Vec<(String, f64)>, ExitCode> {
    items
        .iter()
        .map(|s| {
            let (n, v) = s.split_once('=').ok_or(())?;
            let v: f64 = v.trim().parse().map_err(|_| ())?;
            Ok((n.trim().to_string(), v))
        })
        .collect::<Result<_, ()>>()
        .map_err(|_| {
            eprintln!("error: --set expects NAME=NUMBER");
            ExitCode::from(2)
        })
}

/// A monitor from the options: protocol files (exit 1 on a protocol error) or the standard library.
pub fn load_monitor(dialect: &Arc<Dialect>, o: &MonitorOpts) -> Result<Monitor, ExitCode> {
    let overrides = parse_set(&o.set)?;
    let mut sources =
        if o.protocols.is_empty() || o.with_stdlib { stdlib::sources() } else { Vec::new() };
    sources.extend(read_sources(&o.protocols)?);
    Monitor::from_sources(Arc::clone(dialect), &sources, &overrides).map_err(|e| {
        eprintln!("{:?}", miette::Report::new(e));
        ExitCode::from(1)
    })
}
