//! `vouch mav …`: argument types and printing; the work is in `vouch_mav`.

mod bench;
mod check;
mod guard;
mod guard_args;
mod guard_setup;
mod lint;

use std::path::PathBuf;

use clap::{Args, Subcommand};
use vouch_mav::monitor::{LoadError, MonitorSpec};

use crate::contract::{CmdResult, Ctx, Failure};

/// The `vouch mav` subcommands.
#[derive(Subcommand)]
pub enum MavCmd {
    /// Check recordings (.tlog) against session-type protocols (the standard library unless
    /// --protocol is given). Exit 0 clean (unverifiable messages alone are no violation),
    /// 1 protocol file rejected, 2 usage or I/O error, 3 violations found
    #[command(after_help = "Example:\n  vouch mav check flight.tlog --max-reports 10")]
    Check(check::CheckArgs),
    /// Check protocol files against a dialect (the standard library if no file is given) and
    /// warn (mav::R001) about every route to a guarded action (a command checked on one carrier,
    /// an effect) that no loaded protocol covers. Exit 0 when every file is accepted (warnings
    /// included), 1 when one is rejected, 2 on an I/O error
    #[command(
        after_help = "Example:\n  vouch mav lint crates/vouch-mav/protocols/mission.vproto\n  vouch mav lint my.vproto --with-stdlib --message-format short"
    )]
    Lint(lint::LintArgs),
    /// MAVLink router between vehicles, ground stations and companions (any number of
    /// endpoints, mavlink-router's configuration files and routing by target) that checks every
    /// message against the protocols at the trust boundary it crosses, reporting violations
    /// (monitor) or dropping and answering them (enforce). Runs until SIGINT/SIGTERM or
    /// --duration
    #[command(
        after_help = "Example:\n  vouch mav guard -c /etc/vouch/guard.conf\n  vouch mav guard --vehicle serial:/dev/ttyACM0:115200 --endpoint qgc=ground:udpout:127.0.0.1:14550 --enforce --alert-gcs\n  vouch mav guard -e 192.168.1.20:14550 -e 127.0.0.1:14560 /dev/ttyS1:921600"
    )]
    Guard(Box<guard_args::GuardArgs>),
    /// Latency, throughput and memory of the guard against a direct path and a socat relay,
    /// side by side on loopback (Linux: CPU pinning and RSS from /proc)
    #[command(after_help = "Example:\n  vouch mav bench --uploads 5 --pings 1000 --seconds 1")]
    Bench(bench::BenchArgs),
}

/// Runs one `vouch mav` subcommand.
pub fn run(cmd: MavCmd, ctx: &mut Ctx) -> CmdResult {
    match cmd {
        MavCmd::Check(a) => check::run(a, ctx),
        MavCmd::Lint(a) => lint::run(a, ctx),
        MavCmd::Guard(a) => guard::run(*a, ctx),
        MavCmd::Bench(a) => bench::run(a, ctx),
    }
}

/// Options of every subcommand that runs the monitor.
#[derive(Args, Clone, Debug)]
pub struct MonitorOpts {
    /// Protocol file (repeatable); replaces the standard library unless --with-stdlib is given
    #[arg(long = "protocol", value_name = "FILE")]
    pub protocols: Vec<PathBuf>,
    /// Also load the standard library when --protocol is given
    #[arg(long)]
    pub with_stdlib: bool,
    /// MAVLink XML dialect, includes relative to it (default: ardupilotmega with its includes,
    /// built in)
    #[arg(long, value_name = "FILE.xml")]
    pub dialect: Option<PathBuf>,
    /// New value of a declared protocol constant (repeatable), e.g. --set CHUTE_MAX_CLIMB=0.5
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
    pub set: Vec<(String, f64)>,
}

impl MonitorOpts {
    /// The library's description of the monitor these options ask for.
    pub fn spec(&self) -> MonitorSpec {
        MonitorSpec {
            dialect: self.dialect.clone(),
            protocols: self.protocols.clone(),
            with_stdlib: self.with_stdlib,
            overrides: self.set.clone(),
        }
    }
}

/// `NAME=VALUE` of `--set`.
fn parse_set(s: &str) -> Result<(String, f64), String> {
    let (n, v) = s.split_once('=').ok_or_else(|| format!("`{s}`: expected NAME=VALUE"))?;
    let v: f64 = v.trim().parse().map_err(|_| format!("`{v}` is not a number"))?;
    Ok((n.trim().to_string(), v))
}

/// A monitor that could not be built: unreadable files are usage/I-O errors (exit 2), rejected
/// dialects and protocols are rejected input (exit 1).
fn load_failure(e: LoadError) -> Failure {
    if e.is_io() { Failure::Usage(miette::Report::new(e)) } else { Failure::rejected(e) }
}
