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
    /// Check recordings (.tlog) against session-type protocols
    ///
    /// The standard protocol library unless --protocol is given. Messages a recording cannot
    /// judge (answers whose requests are not in it) are counted as unverifiable, not violations.
    #[command(after_help = after_help!(
        ["vouch mav check flight.tlog --max-reports 10", "vouch mav check --json flight.tlog"],
        "0 no violation, 1 protocol file rejected, 2 usage or I/O error, 3 violations found"
    ))]
    Check(check::CheckArgs),
    /// Check protocol files against a dialect, and warn about unguarded routes
    ///
    /// The standard library if no file is given. Warns (mav::R001) about every route to a
    /// guarded action (a command checked on one carrier, an effect) that no loaded protocol
    /// covers; warnings do not change the exit code.
    #[command(after_help = after_help!(
        [
            "vouch mav lint",
            "vouch mav lint crates/vouch-mav/protocols/mission.vproto",
            "vouch mav lint my.vproto --with-stdlib --message-format short"
        ],
        "0 every file accepted (warnings included), 1 a file rejected, 2 usage or I/O error"
    ))]
    Lint(lint::LintArgs),
    /// Route MAVLink between vehicles and ground stations, checking every message
    ///
    /// Any number of endpoints (UDP, TCP, serial), mavlink-router's configuration files and
    /// routing by target; every message is checked against the protocols at the trust boundary
    /// it crosses, and violations are reported (monitor) or dropped and answered (enforce). Runs
    /// until SIGINT/SIGTERM or --duration; --check only reads the configuration.
    #[command(after_help = after_help!(
        [
            "vouch mav guard -c /etc/vouch/guard.conf",
            "vouch mav guard -c packaging/guard.conf.example --check",
            "vouch mav guard --vehicle serial:/dev/ttyACM0:115200 \\\n      \
             --endpoint qgc=ground:udpout:127.0.0.1:14550 --enforce --alert-gcs",
            "vouch mav guard -e 192.168.1.20:14550 -e 127.0.0.1:14560 /dev/ttyS1:921600"
        ],
        "0 stopped cleanly (or configuration accepted with --check), 1 configuration rejected, \
         2 usage or I/O error"
    ))]
    Guard(Box<guard_args::GuardArgs>),
    /// Measure the guard's latency, throughput and memory beside socat and no relay
    ///
    /// Side by side in one run on 127.0.0.1; on Linux the relay is pinned to a CPU and its
    /// memory read from /proc. A progress bar shows on a terminal.
    #[command(after_help = after_help!(
        [
            "vouch mav bench --scenario proxy --uploads 5 --pings 1000 --seconds 1",
            "vouch mav bench --json -o bench.json"
        ],
        "0 measured (paths that cannot run are listed as skipped), 2 usage or I/O error"
    ))]
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
    /// Protocol file, repeatable; replaces the standard library (kept with --with-stdlib)
    #[arg(long = "protocol", value_name = "FILE")]
    pub protocols: Vec<PathBuf>,
    /// Also load the standard library when --protocol is given
    #[arg(long)]
    pub with_stdlib: bool,
    /// MAVLink XML dialect, includes relative to it (default: ardupilotmega with its includes,
    /// built in)
    #[arg(long, value_name = "FILE.xml")]
    pub dialect: Option<PathBuf>,
    /// New value of a declared protocol constant, repeatable (e.g. `CHUTE_MAX_CLIMB=0.5`)
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
