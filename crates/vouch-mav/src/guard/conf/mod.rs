//! mavlink-router's configuration files (`main.conf` and a conf directory) as the guard's
//! configuration: `[General]`, `[UartEndpoint NAME]`, `[UdpEndpoint NAME]`, `[TcpEndpoint NAME]`
//! with mavlink-router's keys and meanings, plus vouch's own: `Side = vehicle|ground` in endpoint
//! sections and a `[Guard]` section (protocols, enforce mode, signing, logs). mavlink-router
//! ignores both, so one file can serve both programs. A key or section that neither has is a
//! located error; keys vouch reads but does not act on as mavlink-router does are located
//! warnings.
//!
//! The reader is hand-written (`ini.rs`): the INI crates give no line numbers for keys and
//! sections, and mavlink-router's dialect (whole-line comments only, no quotes or escapes,
//! section-name rules, case-insensitive merging across files) is small.

mod endpoints;
mod error;
mod general;
mod ini;
mod logdir;
mod values;

use std::path::{Path, PathBuf};
use std::time::Duration;

pub use error::{ConfError, ConfErrorKind};
pub use general::{GuardKeys, LogLevel};
pub use ini::Source;
pub use logdir::{log_files, stamp};

use super::config::EndpointConfig;
use super::endpoint::Endpoint;
use crate::side::Side;
use endpoints::Kind;
use ini::Ini;
use values::Values;

/// mavlink-router's default TCP server port.
pub const DEFAULT_TCP_SERVER_PORT: u16 = 5760;
/// The name of the endpoint made for `TcpServerPort`.
pub const TCP_SERVER_NAME: &str = "tcp-server";

/// An endpoint from a file or the command line, with what decides its side when none is given.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileEndpoint {
    /// The endpoint (ground side until [`assign_sides`] decides otherwise).
    pub config: EndpointConfig,
    /// Whether its side was given (`Side = …`, `--endpoint SIDE:…`, a positional argument).
    pub side_given: bool,
    /// A UDP endpoint in server mode.
    pub udp_server: bool,
    /// A serial port.
    pub uart: bool,
}

impl FileEndpoint {
    /// An endpoint whose side is given.
    pub fn given(config: EndpointConfig) -> FileEndpoint {
        let udp_server = matches!(config.link, Endpoint::UdpIn(_));
        let uart = matches!(config.link, Endpoint::Serial { .. });
        FileEndpoint { config, side_given: true, udp_server, uart }
    }
}

/// Everything the files say.
#[derive(Debug, Default)]
pub struct RouterFile {
    /// Endpoint sections in the order they first appear.
    pub endpoints: Vec<FileEndpoint>,
    /// `TcpServerPort` (0 = no TCP server; mavlink-router's default is 5760).
    pub tcp_server_port: u16,
    /// `ReportStats`: print statistics every second.
    pub report_stats: bool,
    /// `DebugLogLevel`.
    pub log_level: Option<LogLevel>,
    /// `DeduplicationPeriod` (0 = off).
    pub dedup_period: Option<Duration>,
    /// `SnifferSysid` (0 = off).
    pub sniffer_sysid: Option<u8>,
    /// `Log`: the directory for the router's logs.
    pub log_dir: Option<PathBuf>,
    /// `LogTelemetry`: also record the traffic as a tlog in `log_dir`.
    pub log_telemetry: bool,
    /// `MaxLogFiles`: keep at most this many of vouch's log files in `log_dir` (0 = no limit).
    pub max_log_files: u64,
    /// The `[Guard]` section.
    pub guard: GuardKeys,
    /// Located warnings (keys accepted but not acted on as mavlink-router does).
    pub warnings: Vec<ConfError>,
}

/// Reads the configuration file `file` (if given), then every regular file of `dir` in name
/// order (if given), as mavlink-router does with `-c` and `-d`. Later files add sections and
/// replace values. Relative paths in `[Guard]` are relative to the file that names them.
pub fn load(file: Option<&Path>, dir: Option<&Path>) -> Result<RouterFile, ConfError> {
    let read = |p: &Path| {
        std::fs::read_to_string(p)
            .map(|text| Source { name: p.display().to_string(), text })
            .map_err(|e| ConfError::io(&p.display().to_string(), format!("{}: {e}", p.display())))
    };
    let mut sources = vec![];
    if let Some(f) = file {
        sources.push(read(f)?);
    }
    if let Some(d) = dir {
        let shown = d.display().to_string();
        let entries =
            std::fs::read_dir(d).map_err(|e| ConfError::io(&shown, format!("{shown}: {e}")))?;
        let mut files: Vec<PathBuf> =
            entries.flatten().map(|e| e.path()).filter(|p| p.is_file()).collect();
        files.sort();
        for f in files {
            sources.push(read(&f)?);
        }
    }
    parse_sources(sources)
}

/// The configuration of files already read, in order.
pub fn parse_sources(sources: Vec<Source>) -> Result<RouterFile, ConfError> {
    let mut ini = Ini::default();
    for s in sources {
        ini.add(s)?;
    }
    let v = Values { ini: &ini };
    let mut out = RouterFile { tcp_server_port: DEFAULT_TCP_SERVER_PORT, ..RouterFile::default() };
    let mut pending_ports = vec![];
    for s in &ini.sections {
        if s.kind.eq_ignore_ascii_case("General") && s.name.is_none() {
            general::read_general(&v, s, &mut out)?;
            continue;
        }
        if s.kind.eq_ignore_ascii_case("Guard") && s.name.is_none() {
            let base = Path::new(&ini.sources[s.at.file].name).parent().map(Path::to_path_buf);
            general::read_guard(&v, s, base.as_deref().unwrap_or(Path::new("")), &mut out.guard)?;
            continue;
        }
        let Some(kind) = Kind::of(&s.kind) else {
            let msg = format!(
                "unknown section [{}{}]",
                s.kind,
                s.name.as_ref().map_or(String::new(), |n| format!(" {n}"))
            );
            return Err(ini
                .err(ConfErrorKind::UnknownSection, s.at, msg)
                .with_help("sections: [General], [UartEndpoint NAME], [UdpEndpoint NAME], [TcpEndpoint NAME], [Guard]"));
        };
        let Some(name) = &s.name else {
            let msg = format!("[{}] needs a name, e.g. [{} autopilot]", s.kind, s.kind);
            return Err(ini.err(ConfErrorKind::Syntax, s.at, msg));
        };
        let clash = out.endpoints.iter().any(|e| e.config.name.eq_ignore_ascii_case(name));
        if clash || name.eq_ignore_ascii_case(TCP_SERVER_NAME) {
            let msg = format!(
                "a second endpoint named `{name}` (endpoint names are its identity in logs and statistics)"
            );
            return Err(ini.err(ConfErrorKind::Conflict, s.at, msg));
        }
        let read = endpoints::read(&v, kind, s, name, &mut out.warnings)?;
        if read.needs_port {
            pending_ports.push(out.endpoints.len());
        }
        out.endpoints.push(read.endpoint);
    }
    number_udp_clients(&mut out.endpoints, pending_ports);
    Ok(out)
}

/// Gives UDP clients without `Port` mavlink-router's port: 14550, or the next free one for the
/// same address.
fn number_udp_clients(eps: &mut [FileEndpoint], pending: Vec<usize>) {
    let mut taken: Vec<(std::net::IpAddr, u16)> = eps
        .iter()
        .enumerate()
        .filter(|(i, _)| !pending.contains(i))
        .filter_map(|(_, e)| match e.config.link {
            Endpoint::UdpOut(a) | Endpoint::UdpIn(a) => Some((a.ip(), a.port())),
            _ => None,
        })
        .collect();
    for i in pending {
        if let Endpoint::UdpOut(a) = &mut eps[i].config.link {
            let port = endpoints::next_udp_port(a.ip(), &taken);
            taken.push((a.ip(), port));
            a.set_port(port);
        }
    }
}

/// The TCP server endpoint `TcpServerPort` asks for (ground side, every address), if any.
pub fn tcp_server(port: u16) -> Option<FileEndpoint> {
    (port != 0).then(|| {
        let link = Endpoint::TcpIn(std::net::SocketAddr::from(([0, 0, 0, 0], port)));
        FileEndpoint::given(EndpointConfig::new(TCP_SERVER_NAME, Side::Gcs, link))
    })
}

/// Decides the side of endpoints whose side was not given: serial ports are the vehicle, the
/// rest the ground; when that leaves no vehicle endpoint and exactly one UDP server endpoint has
/// no side given, that one is the vehicle (mavlink-router's usual companion set-up: the autopilot
/// sends to a UDP server, the ground stations are UDP clients). No vehicle endpoint at all is an
/// error: the guard must know what to trust as the vehicle.
pub fn assign_sides(eps: &mut [FileEndpoint]) -> Result<(), String> {
    for e in eps.iter_mut().filter(|e| !e.side_given) {
        e.config.side = if e.uart { Side::Vehicle } else { Side::Gcs };
    }
    if !eps.iter().any(|e| e.config.side == Side::Vehicle) {
        let servers: Vec<usize> =
            (0..eps.len()).filter(|&i| !eps[i].side_given && eps[i].udp_server).collect();
        if let [one] = servers[..] {
            eps[one].config.side = Side::Vehicle;
        }
    }
    if eps.iter().any(|e| e.config.side == Side::Vehicle) {
        Ok(())
    } else {
        Err("no vehicle endpoint: add `Side = vehicle` to the autopilot's endpoint section, or \
             give it as --endpoint vehicle:URL (or --vehicle URL)"
            .into())
    }
}

#[cfg(test)]
mod tests;
