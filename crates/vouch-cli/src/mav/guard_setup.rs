//! What `vouch mav guard` gathers before starting: endpoints from the files and the command line
//! (the command line adds to the files, as mavlink-router's does), the monitor options and the
//! log files.

use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;

use vouch_mav::Side;
use vouch_mav::guard::conf::{self, FileEndpoint, GuardKeys, RouterFile};
use vouch_mav::guard::{DEFAULT_TCP_RETRY, Endpoint, EndpointConfig};
use vouch_mav::monitor::MonitorSpec;

use super::MonitorOpts;
use super::guard_args::GuardArgs;
use crate::contract::Failure;

fn endpoint_failure(e: vouch_mav::guard::EndpointError) -> Failure {
    Failure::Usage(miette::Report::new(e))
}

/// mavlink-router's `-e HOST[:PORT]` (no port: 14550, or the next one that `-e` did not take
/// for the same host), or any other spelling.
fn udp_endpoint(spec: &str, taken: &mut Vec<SocketAddr>) -> Result<Endpoint, Failure> {
    if let Ok(ip) = spec.trim_matches(['[', ']']).parse::<IpAddr>() {
        let mut a = SocketAddr::new(ip, 14550);
        while taken.contains(&a) {
            a.set_port(a.port() + 1);
        }
        taken.push(a);
        return Ok(Endpoint::UdpOut(a));
    }
    let e: Endpoint = spec.parse().map_err(endpoint_failure)?;
    if let Endpoint::UdpOut(a) = e {
        taken.push(a);
    }
    Ok(e)
}

/// mavlink-router's last argument: a serial device (`DEVICE[:BAUD]`) or a UDP address to
/// listen on.
fn master(spec: &str) -> Result<Endpoint, Failure> {
    let device = spec.split(':').next().unwrap_or("");
    let is_device = std::fs::metadata(device).is_ok_and(|m| !m.is_dir() && !m.is_file())
        || spec.starts_with("/dev/");
    if is_device {
        spec.parse().map_err(endpoint_failure)
    } else {
        format!("udpin:{spec}").parse().map_err(endpoint_failure)
    }
}

/// Every endpoint, sides decided.
pub(super) fn endpoints(a: &GuardArgs, file: &RouterFile) -> Result<Vec<FileEndpoint>, Failure> {
    let mut eps = file.endpoints.clone();
    let given = |name: &str, side: Side, link: Endpoint| {
        FileEndpoint::given(EndpointConfig::new(name, side, link))
    };
    if let Some(tcp) = conf::tcp_server(a.tcp_port.unwrap_or(file.tcp_server_port)) {
        eps.push(tcp);
    }
    if let Some(v) = &a.vehicle {
        eps.push(given("vehicle", Side::Vehicle, v.clone()));
    }
    if let Some(g) = &a.gcs {
        eps.push(given("gcs", Side::Gcs, g.clone()));
    }
    for (i, spec) in a.endpoints.iter().enumerate() {
        let e = EndpointConfig::parse_sided(spec, i).map_err(endpoint_failure)?;
        eps.push(FileEndpoint::given(e));
    }
    let mut taken = vec![];
    for (i, spec) in a.udp_endpoints.iter().enumerate() {
        let link = udp_endpoint(spec, &mut taken)?;
        eps.push(given(&format!("udp-{}", i + 1), Side::Gcs, link));
    }
    for (i, spec) in a.tcp_endpoints.iter().enumerate() {
        let link: Endpoint = format!("tcp:{spec}").parse().map_err(endpoint_failure)?;
        let mut e = EndpointConfig::new(format!("tcp-{}", i + 1), Side::Gcs, link);
        e.retry = Some(DEFAULT_TCP_RETRY);
        eps.push(FileEndpoint::given(e));
    }
    if let Some(m) = &a.master {
        eps.push(given("master", Side::Vehicle, master(m)?));
    }
    if eps.is_empty() {
        return Err(Failure::usage(
            "no endpoints: give a configuration file (-c FILE), --endpoint SIDE:URL, or --gcs URL \
             and --vehicle URL",
        ));
    }
    conf::assign_sides(&mut eps).map_err(Failure::usage)?;
    Ok(eps)
}

/// The monitor options of the command line over those of the [Guard] section.
pub(super) fn merged_monitor(o: &MonitorOpts, g: &GuardKeys) -> MonitorSpec {
    let mut spec = o.spec();
    if spec.dialect.is_none() {
        spec.dialect = g.dialect.clone();
    }
    if spec.protocols.is_empty() {
        spec.protocols = g.protocols.clone();
    }
    spec.with_stdlib |= g.with_stdlib.unwrap_or(false);
    let mut overrides = g.set.clone();
    overrides.extend(o.set.iter().cloned());
    spec.overrides = overrides;
    spec
}

/// The violations log and the tlog: named on the command line, in [Guard], or made in the log
/// directory (`--log-dir`, `Log`) with its file limit.
pub(super) fn log_paths(
    a: &GuardArgs,
    file: &RouterFile,
) -> Result<(Option<PathBuf>, Option<PathBuf>), Failure> {
    let g = &file.guard;
    let mut log = a.log.clone().or(g.violation_log.clone());
    let mut tlog = a.tlog.clone().or(g.tlog.clone());
    if let Some(dir) = a.log_dir.as_ref().or(file.log_dir.as_ref()) {
        let telemetry = a.telemetry_log || file.log_telemetry;
        let made = conf::log_files(dir, telemetry, file.max_log_files)
            .map_err(|e| Failure::io(dir, &e))?;
        log = log.or(Some(made.0));
        tlog = tlog.or(made.1);
    }
    Ok((log, tlog))
}
