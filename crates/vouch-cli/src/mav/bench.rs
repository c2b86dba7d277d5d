//! `vouch mav bench`: runs the benchmark harness of `vouch_mav::bench` and prints its figures.

use std::path::PathBuf;

use clap::Args;
use vouch_mav::bench::{self, BenchConfig, Step};

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
    let bar = progress_bar(ctx);
    let mut on_step = |step: Step| {
        if let Some(bar) = &bar {
            bar.set_length(step.total);
            bar.set_position(step.done);
            bar.set_message(step.what);
        }
    };
    let report = bench::run(&cfg, &mut on_step);
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let report = report.map_err(|e| Failure::usage(format_args!("loopback: {e}")))?;
    for s in &report.skipped {
        ctx.note(format_args!(
            "{} scenario, path `{}` skipped: {}",
            s.scenario,
            s.path.label(),
            s.reason
        ));
    }
    let text = if a.json {
        let mut t = serde_json::to_string_pretty(&report)
            .map_err(|e| Failure::usage(format_args!("JSON report: {e}")))?;
        t.push('\n');
        t
    } else {
        bench::table(&report)
    };
    match &a.output {
        Some(out) => std::fs::write(out, text).map_err(|e| Failure::io(out, &e))?,
        None => ctx.out.write_all(text.as_bytes())?,
    }
    Ok(Exit::Ok)
}

/// A bar of the run's phases on stderr, when stderr is a terminal and not `-q`.
fn progress_bar(ctx: &Ctx) -> Option<indicatif::ProgressBar> {
    if !ctx.progress_allowed() {
        return None;
    }
    let style = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:30}] {pos}/{len} phases  {wide_msg}",
    )
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    let bar = indicatif::ProgressBar::new(0).with_style(style);
    bar.enable_steady_tick(std::time::Duration::from_millis(250));
    Some(bar)
}
