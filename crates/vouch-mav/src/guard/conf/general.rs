//! `[General]` (mavlink-router's keys) and `[Guard]` (vouch's: protocols, mode, signing, logs).

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::RouterFile;
use super::error::{ConfError, ConfErrorKind};
use super::ini::{Entry, Section};
use super::values::Values;
use crate::signing::SigningKey;

/// mavlink-router's `DebugLogLevel`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum LogLevel {
    /// Errors only.
    Error,
    /// Errors and warnings.
    Warning,
    /// The default.
    Info,
    /// More detail.
    Debug,
    /// Everything.
    Trace,
}

/// The `[Guard]` section; `None` = not given (the command line or the default decides).
#[derive(Clone, Debug, Default)]
pub struct GuardKeys {
    /// `Enforce`: drop violating frames and answer.
    pub enforce: Option<bool>,
    /// `AlertGcs`: STATUSTEXT alerts to the ground endpoints.
    pub alert_gcs: Option<bool>,
    /// `RelayOnly`: check nothing.
    pub relay_only: Option<bool>,
    /// `Protocols`: protocol files (comma-separated).
    pub protocols: Vec<PathBuf>,
    /// `WithStdlib`: the standard library besides `Protocols`.
    pub with_stdlib: Option<bool>,
    /// `Dialect`: a MAVLink XML dialect.
    pub dialect: Option<PathBuf>,
    /// `Set`: protocol constants, `NAME=VALUE` comma-separated.
    pub set: Vec<(String, f64)>,
    /// `SigningKey`: required on frames from ground endpoints.
    pub signing_key: Option<SigningKey>,
    /// `SignToVehicle`.
    pub sign_to_vehicle: Option<bool>,
    /// `SigningLinkId`.
    pub signing_link_id: Option<u8>,
    /// `SigningState`: the replay state file of the signing key.
    pub signing_state: Option<PathBuf>,
    /// `PassUnknownIds`: let frames of ids the dialect does not know pass unchecked.
    pub pass_unknown_ids: Option<bool>,
    /// `ViolationLog`: JSON Lines file.
    pub violation_log: Option<PathBuf>,
    /// `TLog`: recording of all traffic.
    pub tlog: Option<PathBuf>,
}

fn unknown(v: &Values<'_>, s: &Section, e: &Entry, keys: &[&str]) -> ConfError {
    let msg = format!("unknown key `{}` in [{}]", e.key, s.kind);
    v.ini
        .err(ConfErrorKind::UnknownKey, e.key_at, msg)
        .with_help(format!("keys of this section: {}", keys.join(", ")))
}

fn warn(v: &Values<'_>, e: &Entry, out: &mut RouterFile, msg: &str) {
    let msg = format!("`{}` = `{}`: {msg}", e.key, e.value);
    out.warnings.push(v.ini.err(ConfErrorKind::NotImplemented, e.key_at, msg));
}

const GENERAL_KEYS: &[&str] = &[
    "TcpServerPort",
    "ReportStats",
    "DebugLogLevel",
    "DeduplicationPeriod",
    "SnifferSysid",
    "MavlinkDialect",
    "Log",
    "LogMode",
    "LogSystemId",
    "MinFreeSpace",
    "MaxLogFiles",
    "LogTelemetry",
];

pub(super) fn read_general(
    v: &Values<'_>,
    s: &Section,
    out: &mut RouterFile,
) -> Result<(), ConfError> {
    for e in &s.entries {
        match e.key.to_ascii_lowercase().as_str() {
            "tcpserverport" => out.tcp_server_port = v.number(e, 65535)? as u16,
            "reportstats" => out.report_stats = v.boolean(e)?,
            "debugloglevel" => {
                let levels = [
                    LogLevel::Error,
                    LogLevel::Warning,
                    LogLevel::Info,
                    LogLevel::Debug,
                    LogLevel::Trace,
                ];
                let i = v.choice(e, &["error", "warning", "info", "debug", "trace"])?;
                out.log_level = Some(levels[i]);
            }
            "deduplicationperiod" => {
                let ms = v.number(e, 3_600_000)?;
                out.dedup_period = (ms > 0).then(|| Duration::from_millis(ms));
            }
            "sniffersysid" => out.sniffer_sysid = Some(v.number(e, 255)? as u8).filter(|&s| s > 0),
            // the built-in dialect (ardupilotmega) includes common: both values read the same
            "mavlinkdialect" => {
                v.choice(e, &["auto", "common", "ardupilotmega"])?;
            }
            "log" => {
                out.log_dir = Some(PathBuf::from(&e.value));
                warn(
                    v,
                    e,
                    out,
                    "vouch writes its violations log here (and the traffic as a tlog with LogTelemetry = true), not the autopilot's .bin/.ulg flight logs",
                );
            }
            "logmode" => {
                if v.choice(e, &["always", "while-armed"])? == 1 {
                    warn(v, e, out, "vouch records always");
                }
            }
            "logsystemid" => {
                v.number(e, 255)?;
                warn(v, e, out, "vouch records every system");
            }
            "minfreespace" => {
                if v.number(e, u64::MAX)? > 0 {
                    warn(
                        v,
                        e,
                        out,
                        "vouch does not delete logs for free space (MaxLogFiles works)",
                    );
                }
            }
            "maxlogfiles" => out.max_log_files = v.number(e, u64::MAX)?,
            "logtelemetry" => out.log_telemetry = v.boolean(e)?,
            _ => return Err(unknown(v, s, e, GENERAL_KEYS)),
        }
    }
    Ok(())
}

const GUARD_KEYS: &[&str] = &[
    "Enforce",
    "AlertGcs",
    "RelayOnly",
    "Protocols",
    "WithStdlib",
    "Dialect",
    "Set",
    "SigningKey",
    "SignToVehicle",
    "SigningLinkId",
    "SigningState",
    "PassUnknownIds",
    "ViolationLog",
    "TLog",
];

pub(super) fn read_guard(
    v: &Values<'_>,
    s: &Section,
    base: &Path,
    g: &mut GuardKeys,
) -> Result<(), ConfError> {
    let path = |e: &Entry| base.join(&e.value);
    for e in &s.entries {
        match e.key.to_ascii_lowercase().as_str() {
            "enforce" => g.enforce = Some(v.boolean(e)?),
            "alertgcs" => g.alert_gcs = Some(v.boolean(e)?),
            "relayonly" => g.relay_only = Some(v.boolean(e)?),
            "withstdlib" => g.with_stdlib = Some(v.boolean(e)?),
            "signtovehicle" => g.sign_to_vehicle = Some(v.boolean(e)?),
            "protocols" => {
                g.protocols = e
                    .value
                    .split(',')
                    .map(str::trim)
                    .filter(|p| !p.is_empty())
                    .map(|p| base.join(p))
                    .collect();
            }
            "dialect" => g.dialect = Some(path(e)),
            "set" => g.set = constants(v, e)?,
            "signingkey" => g.signing_key = Some(signing_key(v, e, base)?),
            "signinglinkid" => g.signing_link_id = Some(v.number(e, 255)? as u8),
            "signingstate" => g.signing_state = Some(path(e)),
            "passunknownids" => g.pass_unknown_ids = Some(v.boolean(e)?),
            "violationlog" => g.violation_log = Some(path(e)),
            "tlog" => g.tlog = Some(path(e)),
            _ => return Err(unknown(v, s, e, GUARD_KEYS)),
        }
    }
    Ok(())
}

/// `NAME=VALUE, NAME=VALUE`.
fn constants(v: &Values<'_>, e: &Entry) -> Result<Vec<(String, f64)>, ConfError> {
    e.value
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|item| {
            let (n, x) = item.split_once('=').ok_or_else(|| v.bad(e, "NAME=VALUE, …"))?;
            let x: f64 = x.trim().parse().map_err(|_| v.bad(e, "NAME=VALUE with a number"))?;
            Ok((n.trim().to_string(), x))
        })
        .collect()
}

/// A key as `--signing-key` takes it; a file name is relative to the configuration file.
fn signing_key(v: &Values<'_>, e: &Entry, base: &Path) -> Result<SigningKey, ConfError> {
    let spec = &e.value;
    let direct = spec.starts_with("passphrase:") || SigningKey::from_hex(spec).is_some();
    let spec = if direct { spec.clone() } else { base.join(spec).display().to_string() };
    SigningKey::parse(&spec).map_err(|err| v.bad(e, &format!("a signing key ({err})")))
}
