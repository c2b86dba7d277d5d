//! `vouch mav guard`: gather the endpoints (configuration files, `--endpoint`, mavlink-router's
//! `-e`/`-p`/positional forms, the `--gcs`/`--vehicle` shorthands), start the router, print its
//! events (and statistics) until SIGINT/SIGTERM or `--duration`, then its counters.

use std::sync::atomic::Ordering;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

use vouch_mav::guard::conf::{self, GuardKeys, LogLevel};
use vouch_mav::guard::{
    self, CounterSnapshot, GuardConfig, GuardEvent, Inspector, MonitorInspector, PassThrough,
    RoutingOptions, SigningConfig, side_word,
};
use vouch_mav::monitor::MonitorSpec;
use vouch_mav::signing::state;
use vouch_mav::text::escape_controls;

use super::guard_args::GuardArgs;
use super::guard_setup::{endpoints, log_paths, merged_monitor};
use super::load_failure;
use crate::contract::{CmdResult, Ctx, Exit, Failure, Verbosity};

/// The inspector the options ask for, with a description and the dialect to route by.
fn inspector(
    relay_only: bool,
    pass_unknown_ids: bool,
    spec: &MonitorSpec,
    ctx: &Ctx,
) -> Result<(Box<dyn Inspector>, String, RoutingOptions), Failure> {
    if relay_only {
        let dialect = match spec.load_dialect() {
            Ok(d) => Some(d),
            Err(e) => {
                ctx.warn(&e);
                ctx.note("vouch mav guard: no dialect: every frame is routed as a broadcast");
                None
            }
        };
        let routing = RoutingOptions { dialect, ..RoutingOptions::default() };
        return Ok((Box::new(PassThrough), "no protocols (relay only)".into(), routing));
    }
    let monitor = spec.build().map_err(load_failure)?;
    let names: Vec<&str> = monitor.protocols().protocols.iter().map(|p| p.name.as_str()).collect();
    let what = format!("{} protocol(s): {}", names.len(), names.join(", "));
    let routing = RoutingOptions { dialect: Some(monitor.dialect().clone()), ..Default::default() };
    let inspector = MonitorInspector::new(monitor).pass_unknown_ids(pass_unknown_ids);
    Ok((Box::new(inspector), what, routing))
}

pub fn run(a: GuardArgs, ctx: &mut Ctx) -> CmdResult {
    let file = if a.conf_file.is_some() || a.conf_dir.is_some() {
        let f =
            conf::load(a.conf_file.as_deref(), a.conf_dir.as_deref()).map_err(Failure::rejected)?;
        f.warnings.iter().for_each(|w| ctx.warn(w));
        Some(f)
    } else {
        None
    };
    apply_log_level(ctx, a.debug_log_level.or(file.as_ref().and_then(|f| f.log_level)));
    let file = file.unwrap_or_default();
    let eps = endpoints(&a, &file)?;
    let g = &file.guard;
    let relay_only = a.relay_only || g.relay_only.unwrap_or(false);
    let pass_unknown_ids = a.pass_unknown_ids || g.pass_unknown_ids.unwrap_or(false);
    let (inspector, what, mut routing) =
        inspector(relay_only, pass_unknown_ids, &merged_monitor(&a.monitor, g), ctx)?;
    routing.sniffer_sysid = a.sniffer_sysid.or(file.sniffer_sysid);
    routing.dedup_period = file.dedup_period;
    let stop = guard::stop_on_signals()
        .map_err(|e| Failure::usage(format_args!("cannot install signal handlers: {e}")))?;
    let (events, received) = mpsc::sync_channel(64);
    let signing = signing_config(&a, g)?;
    // --check opens nothing: the log directory is neither created nor trimmed
    let (log_path, tlog_path) = if a.check { (None, None) } else { log_paths(&a, &file)? };
    let cfg = GuardConfig {
        routing,
        enforce: a.enforce || g.enforce.unwrap_or(false),
        alert_gcs: a.alert_gcs || g.alert_gcs.unwrap_or(false),
        log_path,
        tlog_path,
        signing,
        events: Some(events),
        ..GuardConfig::with_endpoints(eps.iter().map(|e| e.config.clone()).collect())
    };
    let mode = if cfg.enforce { "enforce" } else { "monitor" };
    let extras = format!(
        "{}{}",
        if cfg.signing.is_some() { ", signing required from ground endpoints" } else { "" },
        if cfg.alert_gcs { ", STATUSTEXT alerts" } else { "" }
    );
    if a.check {
        ctx.note(format_args!(
            "vouch mav guard: configuration accepted: {what}; {mode} mode{extras}"
        ));
        for e in &eps {
            let c = &e.config;
            let (name, link) = (escape_controls(&c.name), c.link.to_string());
            writeln!(ctx.out, "{name}\t{}\t{}", side_word(c.side), escape_controls(&link))?;
        }
        return Ok(Exit::Ok);
    }
    let running = guard::start(cfg, inspector).map_err(Failure::usage)?;
    ctx.note(format_args!("vouch mav guard: {what}; {mode} mode{extras}"));
    for e in &eps {
        let c = &e.config;
        let bound = running.local_addr(&c.name).map_or(String::new(), |x| format!(" (bound {x})"));
        let line = format!("  {:<12} {:<7} {}{bound}", c.name, side_word(c.side), c.link);
        ctx.note(escape_controls(&line));
    }
    let report = a.report_stats.or(file.report_stats.then_some(Duration::from_secs(1)));
    let started = Instant::now();
    let mut last_report = Instant::now();
    while !stop.load(Ordering::Relaxed) && a.duration.is_none_or(|d| started.elapsed() < d) {
        match received.recv_timeout(Duration::from_millis(50)) {
            Ok(ev) => note_event(ctx, &ev),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if report.is_some_and(|p| last_report.elapsed() >= p) {
            last_report = Instant::now();
            stats(ctx, &running.counters(), started, a.json)?;
        }
    }
    let counters = running.stop();
    received.try_iter().for_each(|ev| note_event(ctx, &ev));
    finish(ctx, &counters, started, a.json)
}

/// mavlink-router's `DebugLogLevel` (or `--debug-log-level`) as vouch's verbosity, unless `-q`
/// or `-v` chose one.
fn apply_log_level(ctx: &mut Ctx, level: Option<LogLevel>) {
    if ctx.verbosity == Verbosity::Normal {
        match level {
            Some(LogLevel::Error | LogLevel::Warning) => ctx.verbosity = Verbosity::Quiet,
            Some(LogLevel::Debug | LogLevel::Trace) => ctx.verbosity = Verbosity::Verbose,
            _ => {}
        }
    }
}

/// Signing from the command line over the `[Guard]` section; `None` without a key.
fn signing_config(a: &GuardArgs, g: &GuardKeys) -> Result<Option<SigningConfig>, Failure> {
    let sign_to_vehicle = a.sign_to_vehicle || g.sign_to_vehicle.unwrap_or(false);
    let key = a.signing_key.clone().or(g.signing_key.clone());
    if sign_to_vehicle && key.is_none() {
        return Err(Failure::usage(
            "--sign-to-vehicle needs a signing key (--signing-key or SigningKey)",
        ));
    }
    let Some(key) = key else { return Ok(None) };
    // Replay protection across restarts is on whenever a key is set.
    let state_file = match a.signing_state.clone().or(g.signing_state.clone()) {
        Some(p) => p,
        None => state::default_path(&key).map_err(|e| Failure::Usage(miette::Report::new(e)))?,
    };
    Ok(Some(SigningConfig {
        key,
        sign_to_vehicle,
        link_id: a.signing_link_id.or(g.signing_link_id).unwrap_or(0),
        state_file: Some(state_file),
    }))
}

fn note_event(ctx: &Ctx, ev: &GuardEvent) {
    let line = match ev {
        GuardEvent::Violation { from, dropped, summary, endpoint } => format!(
            "violation from {endpoint} ({}, {}): {summary}",
            from.as_str(),
            if *dropped { "dropped" } else { "forwarded" }
        ),
        GuardEvent::Connected { endpoint, peer } => format!("{endpoint}: connected {peer}"),
        GuardEvent::Disconnected { endpoint, peer, reason, reconnect_in_s } => {
            let again = reconnect_in_s.map_or(String::new(), |s| format!("; retrying in {s:.0} s"));
            let who = if peer == "-" { String::new() } else { format!(" {peer}") };
            format!("{endpoint}: disconnected{who} ({reason}){again}")
        }
        GuardEvent::Warning { endpoint, message } => format!("{endpoint}: warning: {message}"),
    };
    // Endpoint names, peers and reasons may come from configuration files or the network.
    ctx.note(format_args!("vouch mav guard: {}", escape_controls(&line)));
}

/// Per-endpoint counters: a table on standard error, or a JSON line on standard output.
fn stats(ctx: &mut Ctx, c: &CounterSnapshot, started: Instant, json: bool) -> Result<(), Failure> {
    let t = started.elapsed().as_secs_f64();
    if json {
        ctx.out.json_line(&serde_json::json!({ "t_s": t, "stats": c }))?;
        return ctx.out.flush();
    }
    ctx.note(format_args!(
        "vouch mav guard: {t:.1} s: {} violations, {} unrouted",
        c.violations, c.unrouted
    ));
    endpoint_table(ctx, c);
    Ok(())
}

fn endpoint_table(ctx: &Ctx, c: &CounterSnapshot) {
    ctx.note(format_args!(
        "  {:<12} {:<7} {:>10} {:>10} {:>12} {:>8} {:>8} {:>6}",
        "endpoint", "side", "frames in", "frames out", "bytes out", "filt in", "filt out", "conns"
    ));
    for e in &c.endpoints {
        ctx.note(format_args!(
            "  {:<12} {:<7} {:>10} {:>10} {:>12} {:>8} {:>8} {:>6}",
            e.name,
            e.side,
            e.frames_in,
            e.frames_out,
            e.bytes_out,
            e.filtered_in,
            e.filtered_out,
            e.connections
        ));
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
        endpoint_table(ctx, c);
    }
    Ok(Exit::Ok)
}
