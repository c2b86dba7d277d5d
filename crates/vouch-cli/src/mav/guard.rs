//! `vouch mav guard`: start the proxy, print its events until SIGINT/SIGTERM or `--duration`,
//! then its counters.

use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

use clap::Args;
use vouch_mav::guard::{
    self, CounterSnapshot, Endpoint, GuardConfig, GuardEvent, Inspector, MonitorInspector,
    PassThrough, SigningConfig,
};
use vouch_mav::signing::{state, SigningKey};

use super::{load_failure, MonitorOpts};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch mav guard`.
#[derive(Args)]
pub struct GuardArgs {
    /// GCS side: udpin:ADDR:PORT, udpout:ADDR:PORT, tcpin:ADDR:PORT, tcpout:ADDR:PORT or
    /// serial:DEVICE:BAUD
    #[arg(long, value_name = "ENDPOINT")]
    pub gcs: Endpoint,
    /// Vehicle side, same forms (e.g. serial:/dev/ttyUSB0:57600)
    #[arg(long, value_name = "ENDPOINT")]
    pub vehicle: Endpoint,
    #[command(flatten)]
    pub monitor: MonitorOpts,
    /// Check nothing: a plain byte-exact relay (the guard's own floor in benchmarks)
    #[arg(long)]
    pub relay_only: bool,
    /// Drop violating messages and answer the sender instead of only reporting
    #[arg(long)]
    pub enforce: bool,
    /// Let frames of message ids the dialect does not know pass unchecked (by default they
    /// cannot be verified and are dropped in enforce mode)
    #[arg(long)]
    pub pass_unknown_ids: bool,
    /// Send a STATUSTEXT to the GCS for each violation (at most 5 per second)
    #[arg(long)]
    pub alert_gcs: bool,
    /// Violations log (one JSON object per line)
    #[arg(long, value_name = "FILE.jsonl")]
    pub log: Option<PathBuf>,
    /// Record every received frame, both directions, as a tlog
    #[arg(long, value_name = "FILE.tlog")]
    pub tlog: Option<PathBuf>,
    /// MAVLink 2 signing key required on frames from the GCS side: 64 hex digits,
    /// passphrase:TEXT (SHA-256 of TEXT, as MAVProxy's `signing setup`), or a key file
    #[arg(long, value_name = "KEY", value_parser = parse_key)]
    pub signing_key: Option<SigningKey>,
    /// (Re)sign the frames forwarded to the vehicle with the key
    #[arg(long, requires = "signing_key")]
    pub sign_to_vehicle: bool,
    /// Link id the guard signs with toward the vehicle
    #[arg(long, default_value_t = 0, value_name = "ID")]
    pub signing_link_id: u8,
    /// Replay state file of the signing key (with --signing-key; default
    /// $STATE_DIRECTORY, else $XDG_STATE_HOME/vouch, else ~/.local/state/vouch, file
    /// mav-signing-<key fingerprint>.json): signed frames accepted before a restart stay refused
    #[arg(long, value_name = "FILE", requires = "signing_key")]
    pub signing_state: Option<PathBuf>,
    /// Stop by itself after this many seconds
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub duration: Option<Duration>,
    /// Print the final counters as one JSON document on standard output
    #[arg(long)]
    pub json: bool,
}

fn parse_key(s: &str) -> Result<SigningKey, String> {
    SigningKey::parse(s).map_err(|e| e.to_string())
}

fn parse_seconds(s: &str) -> Result<Duration, String> {
    let secs: f64 = s.parse().map_err(|_| format!("`{s}` is not a number of seconds"))?;
    Duration::try_from_secs_f64(secs).map_err(|_| format!("`{s}` is not a number of seconds"))
}

pub fn run(a: GuardArgs, ctx: &mut Ctx) -> CmdResult {
    let (inspector, what): (Box<dyn Inspector>, String) = if a.relay_only {
        (Box::new(PassThrough), "no protocols (relay only)".into())
    } else {
        let monitor = a.monitor.spec().build().map_err(load_failure)?;
        let names: Vec<&str> =
            monitor.protocols().protocols.iter().map(|p| p.name.as_str()).collect();
        let what = format!("{} protocol(s): {}", names.len(), names.join(", "));
        (Box::new(MonitorInspector::new(monitor).pass_unknown_ids(a.pass_unknown_ids)), what)
    };
    let stop = guard::stop_on_signals()
        .map_err(|e| Failure::usage(format_args!("cannot install signal handlers: {e}")))?;
    let (events, received) = mpsc::sync_channel(64);
    let signing = match a.signing_key.clone() {
        Some(key) => Some(SigningConfig {
            state_file: Some(match &a.signing_state {
                Some(p) => p.clone(),
                None => {
                    state::default_path(&key).map_err(|e| Failure::Usage(miette::Report::new(e)))?
                }
            }),
            key,
            sign_to_vehicle: a.sign_to_vehicle,
            link_id: a.signing_link_id,
        }),
        None => None,
    };
    let cfg = GuardConfig {
        enforce: a.enforce,
        alert_gcs: a.alert_gcs,
        log_path: a.log.clone(),
        tlog_path: a.tlog.clone(),
        signing,
        events: Some(events),
        ..GuardConfig::new(a.gcs.clone(), a.vehicle.clone())
    };
    let g = guard::start(cfg, inspector).map_err(Failure::usage)?;
    let addr = |x: Option<std::net::SocketAddr>| x.map_or("-".into(), |x| x.to_string());
    ctx.note(format_args!(
        "vouch mav guard: gcs {} ({}) <-> vehicle {} ({}); {what}; {} mode{}{}",
        a.gcs,
        addr(g.gcs_addr),
        a.vehicle,
        addr(g.vehicle_addr),
        if a.enforce { "enforce" } else { "monitor" },
        if a.signing_key.is_some() { ", signing required from the GCS side" } else { "" },
        if a.alert_gcs { ", STATUSTEXT alerts" } else { "" },
    ));
    let started = Instant::now();
    while !stop.load(Ordering::Relaxed) && a.duration.is_none_or(|d| started.elapsed() < d) {
        match received.recv_timeout(Duration::from_millis(50)) {
            Ok(ev) => note_event(ctx, &ev),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
    }
    let counters = g.stop();
    received.try_iter().for_each(|ev| note_event(ctx, &ev));
    finish(ctx, &counters, started, a.json)
}

fn note_event(ctx: &Ctx, ev: &GuardEvent) {
    match ev {
        GuardEvent::Violation { from, dropped, summary } => ctx.note(format_args!(
            "vouch mav guard: violation from {} ({}): {summary}",
            from.as_str(),
            if *dropped { "dropped" } else { "forwarded" }
        )),
    }
}

fn finish(ctx: &mut Ctx, c: &CounterSnapshot, started: Instant, json: bool) -> CmdResult {
    if json {
        ctx.out.json_line(c)?;
    } else {
        ctx.note(format_args!(
            "vouch mav guard: stopped after {:.1} s",
            started.elapsed().as_secs_f64()
        ));
        for (name, value) in c.rows() {
            ctx.note(format_args!("  {name:<22} {value}"));
        }
    }
    Ok(Exit::Ok)
}
