//! The arguments of `vouch mav guard`.

use std::path::PathBuf;
use std::time::Duration;

use clap::Args;
use vouch_mav::guard::Endpoint;
use vouch_mav::guard::conf::LogLevel;
use vouch_mav::signing::SigningKey;

use super::MonitorOpts;

/// Arguments of `vouch mav guard`.
#[derive(Args)]
pub struct GuardArgs {
    /// mavlink-router configuration file (its INI format; vouch's own keys: `Side` in endpoint
    /// sections and a [Guard] section)
    #[arg(short = 'c', long, value_name = "FILE")]
    pub conf_file: Option<PathBuf>,
    /// Directory of further configuration files, read in name order after --conf-file (as
    /// mavlink-router's -d)
    #[arg(short = 'd', long, value_name = "DIR")]
    pub conf_dir: Option<PathBuf>,
    /// An endpoint: [NAME=]SIDE:URL with SIDE vehicle or ground and URL in any tool's spelling
    /// (udpin:, udpout:, udpbcast:, tcpin:, tcp:, DEV,BAUD, HOST:PORT, /dev/ttyX:BAUD, udps:,
    /// udpc:, tcps:, tcpc:, serial:…); repeatable
    #[arg(long = "endpoint", value_name = "[NAME=]SIDE:URL")]
    pub endpoints: Vec<String>,
    /// Shorthand for --endpoint gcs=ground:URL
    #[arg(long, value_name = "URL")]
    pub gcs: Option<Endpoint>,
    /// Shorthand for --endpoint vehicle=vehicle:URL (e.g. serial:/dev/ttyUSB0:57600)
    #[arg(long, value_name = "URL")]
    pub vehicle: Option<Endpoint>,
    /// A ground endpoint as mavlink-router's -e: HOST[:PORT] is a UDP client (without a port:
    /// 14550, the next one if taken), any other spelling as --endpoint; repeatable
    #[arg(short = 'e', long = "udp-endpoint", value_name = "HOST[:PORT]")]
    pub udp_endpoints: Vec<String>,
    /// A ground TCP client endpoint as mavlink-router's -p (HOST:PORT, reconnects every 5 s);
    /// repeatable
    #[arg(short = 'p', long = "tcp-endpoint", value_name = "HOST:PORT")]
    pub tcp_endpoints: Vec<String>,
    /// The vehicle as mavlink-router's last argument: a serial device (DEVICE[:BAUD]) or a UDP
    /// address to listen on (HOST:PORT)
    #[arg(value_name = "UART|UDP")]
    pub master: Option<String>,
    /// Accept ground TCP clients on this port (0 = none); configuration files default to 5760
    /// as mavlink-router, the command line alone to none
    #[arg(short = 't', long, value_name = "PORT")]
    pub tcp_port: Option<u16>,
    /// Print per-endpoint statistics every SECONDS (1 without a value; JSON Lines on standard
    /// output with --json)
    #[arg(short = 'r', long, value_name = "SECONDS", num_args = 0..=1, default_missing_value = "1", value_parser = parse_seconds)]
    pub report_stats: Option<Duration>,
    /// Directory for the router's logs: violations (vouch-TIME.jsonl) and, with
    /// --telemetry-log, all traffic (vouch-TIME.tlog)
    #[arg(short = 'l', long, value_name = "DIR")]
    pub log_dir: Option<PathBuf>,
    /// With --log-dir: also record all traffic as a tlog there
    #[arg(short = 'T', long)]
    pub telemetry_log: bool,
    /// Endpoints where this system id was seen get every frame (mavlink-router's sniffer)
    #[arg(short = 's', long, value_name = "SYSID")]
    pub sniffer_sysid: Option<u8>,
    /// What to print: error, warning, info (default), debug, trace (mavlink-router's levels;
    /// -q and -v override)
    #[arg(short = 'g', long, value_name = "LEVEL", value_parser = parse_level)]
    pub debug_log_level: Option<LogLevel>,
    #[command(flatten)]
    pub monitor: MonitorOpts,
    /// Check nothing: a plain byte-exact router (the guard's own floor in benchmarks)
    #[arg(long)]
    pub relay_only: bool,
    /// Let frames of message ids the dialect does not know pass unchecked (by default they
    /// cannot be verified and are dropped in enforce mode; config key PassUnknownIds)
    #[arg(long)]
    pub pass_unknown_ids: bool,
    /// Drop violating messages and answer the sender instead of only reporting
    #[arg(long)]
    pub enforce: bool,
    /// Send a STATUSTEXT to the ground endpoints for each violation (at most 5 per second)
    #[arg(long)]
    pub alert_gcs: bool,
    /// Violations log of the whole router (one JSON object per line)
    #[arg(long, value_name = "FILE.jsonl")]
    pub log: Option<PathBuf>,
    /// Record every frame received on any endpoint as a tlog
    #[arg(long, value_name = "FILE.tlog")]
    pub tlog: Option<PathBuf>,
    /// MAVLink 2 signing key required on frames from ground endpoints: 64 hex digits,
    /// passphrase:TEXT (SHA-256 of TEXT, as MAVProxy's `signing setup`), or a key file
    #[arg(long, value_name = "KEY", value_parser = parse_key)]
    pub signing_key: Option<SigningKey>,
    /// (Re)sign the frames forwarded to vehicle endpoints with the key
    #[arg(long)]
    pub sign_to_vehicle: bool,
    /// Link id the guard signs with toward the vehicle
    #[arg(long, value_name = "ID")]
    pub signing_link_id: Option<u8>,
    /// Replay state file of the signing key (default $STATE_DIRECTORY, else
    /// $XDG_STATE_HOME/vouch, else ~/.local/state/vouch, file mav-signing-<key fingerprint>.json;
    /// config key SigningState): signed frames accepted before a restart stay refused
    #[arg(long, value_name = "FILE")]
    pub signing_state: Option<std::path::PathBuf>,
    /// Read the configuration and the protocols, print the endpoints and exit without opening
    /// anything (exit 0 when everything is accepted)
    #[arg(long)]
    pub check: bool,
    /// Stop by itself after this many seconds
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub duration: Option<Duration>,
    /// Print the final counters as JSON on standard output (JSON Lines: one line per
    /// --report-stats period, then the final counters)
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

fn parse_level(s: &str) -> Result<LogLevel, String> {
    let levels = [
        ("error", LogLevel::Error),
        ("warning", LogLevel::Warning),
        ("info", LogLevel::Info),
        ("debug", LogLevel::Debug),
        ("trace", LogLevel::Trace),
    ];
    levels
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(s))
        .map(|(_, l)| *l)
        .ok_or_else(|| format!("`{s}`: expected error, warning, info, debug or trace"))
}
