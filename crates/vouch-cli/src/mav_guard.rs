//! `vouch mav guard` and `vouch mav bench` (mav-guard). Argument parsing only: the proxy and
//! the benchmark live in `vouch_mav::guard`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::MonitorOpts;

#[derive(Args)]
pub struct GuardCli {
    /// GCS side: udpin:ADDR:PORT, udpout:ADDR:PORT, tcpin:…, tcpout:…, serial:DEVICE:BAUD
    #[arg(long, value_name = "ENDPOINT")]
    gcs: String,
    /// Vehicle side, same forms (e.g. serial:/dev/ttyUSB0:57600)
    #[arg(long, value_name = "ENDPOINT")]
    vehicle: String,
    #[command(flatten)]
    monitor: MonitorOpts,
    /// Check nothing: a plain byte-exact relay (the guard's own floor in benchmarks)
    #[arg(long)]
    relay_only: bool,
    /// Drop violating messages and answer the sender instead of only reporting
    #[arg(long)]
    enforce: bool,
    /// Send a STATUSTEXT to the GCS for each violation (at most 5 per second)
    #[arg(long)]
    alert_gcs: bool,
    /// Violations log (one JSON object per line)
    #[arg(long, value_name = "FILE.jsonl")]
    log: Option<PathBuf>,
    /// Record every received frame, both directions, as a tlog
    #[arg(long, value_name = "FILE.tlog")]
    tlog: Option<PathBuf>,
    /// MAVLink 2 signing key required on frames from the GCS side: 64 hex digits,
    /// passphrase:TEXT (SHA-256 of TEXT, as MAVProxy's `signing setup`), or a key file
    #[arg(long, value_name = "KEY")]
    signing_key: Option<String>,
    /// (Re)sign the frames forwarded to the vehicle with the key
    #[arg(long)]
    sign_to_vehicle: bool,
    /// Link id the guard signs with toward the vehicle
    #[arg(long, default_value_t = 0)]
    signing_link_id: u8,
    /// Stop by itself after this many seconds
    #[arg(long, value_name = "SECONDS")]
    duration: Option<f64>,
    /// Print the final counters as one JSON object on stdout
    #[arg(long)]
    json: bool,
}

pub fn guard(g: GuardCli) -> ExitCode {
    let args = vouch_mav::guard::cli::GuardArgs {
        gcs: g.gcs,
        vehicle: g.vehicle,
        protocols: g.monitor.protocols,
        with_stdlib: g.monitor.with_stdlib,
        relay_only: g.relay_only,
        dialect: g.monitor.dialect,
        set: g.monitor.set,
        enforce: g.enforce,
        alert_gcs: g.alert_gcs,
        log: g.log,
        tlog: g.tlog,
        signing_key: g.signing_key,
        sign_to_vehicle: g.sign_to_vehicle,
        signing_link_id: g.signing_link_id,
        duration: g.duration,
        json: g.json,
    };
    ExitCode::from(vouch_mav::guard::cli::run_guard(args))
}

#[derive(Args)]
pub struct BenchCli {
    /// 100-waypoint uploads per path (202 messages each) for the upload latency figures
    #[arg(long, default_value_t = 20)]
    uploads: usize,
    /// Single telemetry messages (one in flight) per path
    #[arg(long, default_value_t = 5000)]
    pings: usize,
    /// Paced telemetry stream rate, messages per second
    #[arg(long, default_value_t = 100_000)]
    rate: u32,
    /// Duration of the paced stream, seconds
    #[arg(long, default_value_t = 2.0)]
    seconds: f64,
    /// Print JSON instead of a table
    #[arg(long)]
    json: bool,
}

pub fn bench(b: BenchCli) -> ExitCode {
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("vouch mav bench: cannot locate the vouch executable: {e}");
            return ExitCode::from(2);
        }
    };
    let args = vouch_mav::guard::bench::BenchArgs {
        uploads: b.uploads,
        pings: b.pings,
        rate: b.rate,
        seconds: b.seconds,
        vouch_exe: exe,
        guard_args: vec![],
        json: b.json,
    };
    match vouch_mav::guard::bench::run_bench(args) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("vouch mav bench: {e}");
            ExitCode::from(2)
        }
    }
}
