//! `vouch mav bench`: runs the benchmark harness of `vouch_mav::bench` and prints its figures.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use vouch_mav::bench::{self, BenchConfig, BenchReport};

use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// The scenarios of `vouch mav bench`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Scenario {
    /// The guard between one GCS and one vehicle.
    Proxy,
    /// The guard routing between four endpoints.
    Router,
    /// Both.
    All,
}

/// Arguments of `vouch mav bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// 100-waypoint uploads per path (202 messages each) for the upload latency figures
    #[arg(long, default_value_t = 20, value_name = "N")]
    pub uploads: usize,
    /// Single telemetry messages (one in flight) per path
    #[arg(long, default_value_t = 5000, value_name = "N")]
    pub pings: usize,
    /// Paced telemetry stream rate, messages per second
    #[arg(long, default_value_t = 100_000, value_name = "MSG_PER_S")]
    pub rate: u32,
    /// Duration of the paced stream, seconds
    #[arg(long, default_value_t = 2.0, value_name = "SECONDS")]
    pub seconds: f64,
    /// Which scenario: proxy (one GCS, one vehicle), router (four endpoints: vehicle, two
    /// ground stations, a companion over TCP), or all
    #[arg(long, value_enum, default_value_t = Scenario::All)]
    pub scenario: Scenario,
    /// Print one JSON document (every path's figures) instead of a table
    #[arg(long)]
    pub json: bool,
    /// Write the table (or the JSON document) to FILE instead of standard output
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

pub fn run(a: BenchArgs, ctx: &mut Ctx) -> CmdResult {
    if !(a.seconds.is_finite() && a.seconds > 0.0) {
        return Err(Failure::usage(format_args!("--seconds {}: not a positive number", a.seconds)));
    }
    let vouch_exe = std::env::current_exe()
        .map_err(|e| Failure::usage(format_args!("cannot locate the vouch executable: {e}")))?;
    let cfg = BenchConfig {
        uploads: a.uploads,
        pings: a.pings,
        rate: a.rate,
        seconds: a.seconds,
        vouch_exe,
        guard_args: vec![],
        proxy: a.scenario != Scenario::Router,
        router: a.scenario != Scenario::Proxy,
    };
    let report = bench::run(&cfg).map_err(|e| Failure::usage(format_args!("loopback: {e}")))?;
    for (path, why) in &report.skipped {
        ctx.note(format_args!("path `{path}` skipped: {why}"));
    }
    let text = if a.json {
        let mut t = serde_json::to_string_pretty(&report)
            .map_err(|e| Failure::usage(format_args!("JSON report: {e}")))?;
        t.push('\n');
        t
    } else {
        table(&report, a.rate).map_err(|e| Failure::usage(format_args!("table: {e}")))?
    };
    match &a.output {
        Some(out) => std::fs::write(out, text).map_err(|e| Failure::io(out, &e))?,
        None => ctx.out.write_all(text.as_bytes())?,
    }
    Ok(Exit::Ok)
}

fn table(r: &BenchReport, rate: u32) -> Result<String, std::fmt::Error> {
    let mut w = String::new();
    if !r.paths.is_empty() {
        proxy_table(&mut w, r, rate)?;
    }
    if !r.router.is_empty() {
        router_table(&mut w, r)?;
    }
    Ok(w)
}

fn router_table(w: &mut String, r: &BenchReport) -> std::fmt::Result {
    let socat = r.router.iter().find(|p| p.path == "socat").map(|p| p.ping_p50_us);
    writeln!(
        w,
        "router scenario: vehicle (UDP server) → 2 ground stations (UDP clients) + companion (TCP), \
         guard with all standard protocols"
    )?;
    writeln!(
        w,
        "{:<24} {:>5} {:>8} {:>8} {:>10} {:>11} {:>13} {:>11} {:>11} {:>8} {:>8}",
        "path",
        "ends",
        "ping p50",
        "ping p99",
        "+p50 socat",
        "offered/s",
        "delivered/s",
        "all peers/s",
        "frames/CPU-s",
        "start kB",
        "peak kB"
    )?;
    let opt = |k: Option<u64>| k.map_or_else(|| "-".into(), |k| k.to_string());
    for p in &r.router {
        let vs = socat.map_or_else(|| "-".into(), |s| format!("{:+.1}", p.ping_p50_us - s));
        writeln!(
            w,
            "{:<24} {:>5} {:>8.1} {:>8.1} {:>10} {:>11.0} {:>13.0} {:>11.0} {:>11} {:>8} {:>8}",
            p.path,
            p.endpoints,
            p.ping_p50_us,
            p.ping_p99_us,
            vs,
            p.offered_per_s,
            p.delivered_per_s,
            p.delivered_all_per_s,
            p.frames_per_cpu_second.map_or_else(|| "-".into(), |m| format!("{m:.0}")),
            opt(p.startup_peak_rss_kb),
            opt(p.peak_rss_kb),
        )?;
    }
    writeln!(
        w,
        "(µs one-way vehicle → first ground station, one frame in flight; delivered/s = frames \
         received per second by the first ground station while the vehicle sends as fast as it \
         can, relay pinned to CPU 0; all peers = the ground stations and the companion together; \
         loadavg {})",
        r.load_average.as_deref().unwrap_or("-")
    )
}

fn proxy_table(w: &mut String, r: &BenchReport, rate: u32) -> std::fmt::Result {
    let direct = r.paths.first().cloned().unwrap_or_default();
    writeln!(
        w,
        "{:<17} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>8} {:>9} {:>9} {:>10} {:>8} {:>8} {:>8}",
        "path",
        "upl p50",
        "upl p99",
        "ping p50",
        "ping p99",
        "+p50 vs d",
        "+p99 vs d",
        "strm ok%",
        "strm p99",
        "sat msg/s",
        "msg/CPU-s",
        "start kB",
        "peak kB",
        "end kB"
    )?;
    let opt = |k: Option<u64>| k.map_or_else(|| "-".into(), |k| k.to_string());
    for p in &r.paths {
        writeln!(
            w,
            "{:<17} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>9.1} {:>9.1} {:>8.2} {:>9.1} {:>9.0} {:>10} {:>8} {:>8} {:>8}",
            p.path,
            p.upload_p50_us,
            p.upload_p99_us,
            p.ping_p50_us,
            p.ping_p99_us,
            p.upload_p50_us - direct.upload_p50_us,
            p.upload_p99_us - direct.upload_p99_us,
            p.stream_delivered_pct,
            p.stream_p99_us,
            p.saturation_msgs_per_s,
            p.msgs_per_cpu_second.map_or_else(|| "-".into(), |m| format!("{m:.0}")),
            opt(p.startup_peak_rss_kb),
            opt(p.peak_rss_kb),
            opt(p.end_rss_kb),
        )?;
    }
    writeln!(
        w,
        "(µs one-way, one message in flight; +vs d = added over direct; stream = {rate} msg/s \
         vehicle→GCS; sat = blast with the relay pinned to CPU 0; start kB = peak RSS at start-up, \
         peak kB = peak RSS during the measured traffic, end kB = RSS at the end; loadavg {})",
        r.load_average.as_deref().unwrap_or("-")
    )
}
