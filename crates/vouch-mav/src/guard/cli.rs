//! What `vouch mav guard` does between parsing its arguments and exiting: build the inspector,
//! start the proxy, wait for SIGINT/SIGTERM (or `--duration`), print the counters.
//! Kept here (not in the CLI crate) so that the CLI file shared by the family stays small.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::{start, GuardConfig, Inspector, PassThrough, SigningConfig};
use crate::signing::SigningKey;

/// Arguments of `vouch mav guard`, already split by the CLI parser.
#[derive(Clone, Debug, Default)]
pub struct GuardArgs {
    pub gcs: String,
    pub vehicle: String,
    /// Protocol files; empty = the standard library.
    pub protocols: Vec<PathBuf>,
    /// Also load the standard library when protocol files are given.
    pub with_stdlib: bool,
    /// No protocol checking at all: a plain relay (benchmark floor of the guard itself).
    pub relay_only: bool,
    pub dialect: Option<PathBuf>,
    /// `NAME=VALUE` overrides of protocol constants.
    pub set: Vec<String>,
    pub enforce: bool,
    pub alert_gcs: bool,
    pub log: Option<PathBuf>,
    pub tlog: Option<PathBuf>,
    pub signing_key: Option<String>,
    pub sign_to_vehicle: bool,
    pub signing_link_id: u8,
    /// Stop by itself after this many seconds (tests, benchmarks).
    pub duration: Option<f64>,
    /// Print the final counters as one JSON object on stdout.
    pub json: bool,
}

/// Exit codes shared by the workspace.
pub const EXIT_OK: u8 = 0;
pub const EXIT_REJECTED: u8 = 1;
pub const EXIT_USAGE: u8 = 2;

/// Runs the guard until SIGINT/SIGTERM or `duration`; returns the process exit code
/// (0 clean shutdown, 1 protocol file rejected, 2 usage or I/O error).
pub fn run_guard(a: GuardArgs) -> u8 {
    match run(a) {
        Ok(()) => EXIT_OK,
        Err((code, e)) => {
            eprintln!("vouch mav guard: {e}");
            code
        }
    }
}

fn run(a: GuardArgs) -> Result<(), (u8, String)> {
    let usage = |e: String| (EXIT_USAGE, e);
    if let Some(d) = a.duration {
        Duration::try_from_secs_f64(d)
            .map_err(|_| usage(format!("--duration {d}: not a number of seconds")))?;
    }
    let gcs = a.gcs.parse().map_err(usage)?;
    let vehicle = a.vehicle.parse().map_err(usage)?;
    let signing = match &a.signing_key {
        Some(k) => Some(SigningConfig {
            key: SigningKey::parse(k).map_err(usage)?,
            sign_to_vehicle: a.sign_to_vehicle,
            link_id: a.signing_link_id,
        }),
        None if a.sign_to_vehicle => {
            return Err(usage("--sign-to-vehicle needs --signing-key".into()))
        }
        None => None,
    };
    let (inspector, what): (Box<dyn Inspector>, String) = if a.relay_only {
        (Box::new(PassThrough), "no protocols (relay only)".into())
    } else {
        super::monitor_inspector::build(a.dialect.as_deref(), &a.protocols, a.with_stdlib, &a.set)
            .map_err(|e| match e {
            super::monitor_inspector::BuildError::Io(s) => (EXIT_USAGE, s),
            super::monitor_inspector::BuildError::Rejected(s) => (EXIT_REJECTED, s),
        })?
    };
    let cfg = GuardConfig {
        gcs,
        vehicle,
        enforce: a.enforce,
        alert_gcs: a.alert_gcs,
        print_violations: true,
        log_path: a.log.clone(),
        tlog_path: a.tlog.clone(),
        signing,
    };
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, stop.clone())
            .map_err(|e| usage(format!("cannot install signal handler: {e}")))?;
    }
    let g = start(cfg, inspector).map_err(|e| usage(e.to_string()))?;
    eprintln!(
        "vouch mav guard: gcs {} ({}) <-> vehicle {} ({}); {}; {} mode{}{}",
        a.gcs,
        g.gcs_addr.map(|x| x.to_string()).unwrap_or_else(|| "-".into()),
        a.vehicle,
        g.vehicle_addr.map(|x| x.to_string()).unwrap_or_else(|| "-".into()),
        what,
        if a.enforce { "enforce" } else { "monitor" },
        if a.signing_key.is_some() { ", signing required from the GCS side" } else { "" },
        if a.alert_gcs { ", STATUSTEXT alerts" } else { "" },
    );
    let started = Instant::now();
    let limit = match a.duration {
        Some(d) => Some(
            Duration::try_from_secs_f64(d)
                .map_err(|_| usage(format!("--duration {d}: not a number of seconds")))?,
        ),
        None => None,
    };
    while !stop.load(Ordering::Relaxed) && limit.is_none_or(|l| started.elapsed() < l) {
        std::thread::sleep(Duration::from_millis(50));
    }
    let c = g.stop();
    if a.json {
        println!("{}", serde_json::to_string(&c).unwrap_or_default());
    } else {
        eprintln!("vouch mav guard: stopped after {:.1} s", started.elapsed().as_secs_f64());
        for (name, value) in c.rows() {
            eprintln!("  {name:<22} {value}");
        }
    }
    Ok(())
}
