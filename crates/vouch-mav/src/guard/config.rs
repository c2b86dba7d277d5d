//! What the guard is told: its endpoints (each with a name and the side its frames are trusted
//! as), routing options, mode, logs, signing. Plain data; the CLI fills it from its arguments and
//! configuration files (`super::conf`), tests and library users directly.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc::SyncSender;
use std::time::Duration;

use super::endpoint::{Endpoint, EndpointError};
use super::events::GuardEvent;
use super::filter::Filters;
use crate::dialect::Dialect;
use crate::side::Side;
use crate::signing::SigningKey;

/// mavlink-router's default `RetryTimeout` of a TCP client endpoint.
pub const DEFAULT_TCP_RETRY: Duration = Duration::from_secs(5);

/// One endpoint of the router.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EndpointConfig {
    /// Its name in logs, statistics and events (a configuration section's name).
    pub name: String,
    /// What its frames are trusted as: checked as coming from the ground station(s) or from the
    /// vehicle.
    pub side: Side,
    /// The connection.
    pub link: Endpoint,
    /// Message filters in and out.
    pub filters: Filters,
    /// Endpoints of one group share the systems they have seen (parallel links to one system).
    pub group: Option<String>,
    /// TCP client: wait this long before reconnecting; `None` = never reconnect.
    pub retry: Option<Duration>,
    /// Serial: RTS/CTS flow control.
    pub flow_control: bool,
}

impl EndpointConfig {
    /// An endpoint with no filters, no group, the default TCP retry and no flow control.
    pub fn new(name: impl Into<String>, side: Side, link: Endpoint) -> Self {
        EndpointConfig {
            name: name.into(),
            side,
            link,
            filters: Filters::default(),
            group: None,
            retry: Some(DEFAULT_TCP_RETRY),
            flow_control: false,
        }
    }

    /// `[NAME=]SIDE:URL` as on the command line (`--endpoint`), with SIDE `vehicle`, `ground` or
    /// `gcs`; without a name the endpoint is named `SIDE-N` (N = `index` + 1).
    pub fn parse_sided(s: &str, index: usize) -> Result<Self, EndpointError> {
        let no_side = || EndpointError::NoSide { spec: s.to_string() };
        let (name, rest) = match s.split_once('=') {
            Some((n, r))
                if is_name(n) && parse_side(r.split(':').next().unwrap_or("")).is_some() =>
            {
                (Some(n.to_string()), r)
            }
            _ => (None, s),
        };
        let (side, url) = rest.split_once(':').ok_or_else(no_side)?;
        let side = parse_side(side).ok_or_else(no_side)?;
        let link: Endpoint = url.parse()?;
        let name = name.unwrap_or_else(|| format!("{}-{}", side_word(side), index + 1));
        Ok(EndpointConfig::new(name, side, link))
    }
}

fn is_name(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
}

/// `vehicle`, `ground` or `gcs` (any case).
pub fn parse_side(s: &str) -> Option<Side> {
    match s.trim().to_ascii_lowercase().as_str() {
        "vehicle" => Some(Side::Vehicle),
        "ground" | "gcs" => Some(Side::Gcs),
        _ => None,
    }
}

/// `vehicle` or `ground`, as configuration files and the command line spell the sides.
pub fn side_word(side: Side) -> &'static str {
    match side {
        Side::Vehicle => "vehicle",
        Side::Gcs => "ground",
    }
}

/// How frames find their endpoints.
#[derive(Clone, Debug, Default)]
pub struct RoutingOptions {
    /// Where the target fields of each message are. `None`: every frame counts as broadcast
    /// (goes everywhere but back).
    pub dialect: Option<Arc<Dialect>>,
    /// Endpoints on which this system id was seen get every frame (mavlink-router's
    /// `SnifferSysid`).
    pub sniffer_sysid: Option<u8>,
    /// Drop a frame received again, byte for byte, within this period (mavlink-router's
    /// `DeduplicationPeriod`).
    pub dedup_period: Option<Duration>,
}

/// Configuration of one guard.
#[derive(Debug)]
pub struct GuardConfig {
    /// The endpoints, in the order they are opened and reported.
    pub endpoints: Vec<EndpointConfig>,
    /// Routing options.
    pub routing: RoutingOptions,
    /// Drop violating frames and answer instead of only reporting.
    pub enforce: bool,
    /// Send a STATUSTEXT to the ground endpoints for each violation (rate-limited).
    pub alert_gcs: bool,
    /// Violations log of the whole router, one JSON object per line.
    pub log_path: Option<PathBuf>,
    /// Recording of every frame received on any endpoint (8-byte big-endian µs timestamp +
    /// frame).
    pub tlog_path: Option<PathBuf>,
    /// MAVLink 2 signing required on frames from ground endpoints.
    pub signing: Option<SigningConfig>,
    /// Where events go as they happen (at most [`MAX_EVENTS_PER_SECOND`](super::MAX_EVENTS_PER_SECOND);
    /// events that find the channel full are not sent). `None`: counters and log only.
    pub events: Option<SyncSender<GuardEvent>>,
}

impl GuardConfig {
    /// Two endpoints, `gcs` (ground side) and `vehicle`: monitor mode, no alerts, logs, signing
    /// or events.
    pub fn new(gcs: Endpoint, vehicle: Endpoint) -> Self {
        Self::with_endpoints(vec![
            EndpointConfig::new("gcs", Side::Gcs, gcs),
            EndpointConfig::new("vehicle", Side::Vehicle, vehicle),
        ])
    }

    /// Any endpoints: monitor mode, no alerts, logs, signing or events.
    pub fn with_endpoints(endpoints: Vec<EndpointConfig>) -> Self {
        GuardConfig {
            endpoints,
            routing: RoutingOptions::default(),
            enforce: false,
            alert_gcs: false,
            log_path: None,
            tlog_path: None,
            signing: None,
            events: None,
        }
    }
}

/// MAVLink 2 signing: frames from ground endpoints must carry a valid signature; optionally the
/// guard (re)signs what it forwards to vehicle endpoints.
#[derive(Clone, Debug)]
pub struct SigningConfig {
    /// The shared secret.
    pub key: SigningKey,
    /// (Re)sign frames forwarded to the vehicle (the guard signs its own messages toward the
    /// vehicle whenever a key is set).
    pub sign_to_vehicle: bool,
    /// Link id the guard signs with toward the vehicle.
    pub link_id: u8,
    /// Where the replay state is kept across restarts (read at start, written at least every
    /// second and at shutdown; see [`crate::signing::state`]). `None`: in memory only.
    pub state_file: Option<PathBuf>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sided_endpoints_as_on_the_command_line() {
        let e = EndpointConfig::parse_sided("vehicle:serial:/dev/ttyACM0:115200", 0).unwrap();
        assert_eq!((e.name.as_str(), e.side), ("vehicle-1", Side::Vehicle));
        assert_eq!(e.link, Endpoint::Serial { device: "/dev/ttyACM0".into(), baud: 115200 });
        let e = EndpointConfig::parse_sided("qgc=ground:udpout:127.0.0.1:14550", 3).unwrap();
        assert_eq!((e.name.as_str(), e.side), ("qgc", Side::Gcs));
        let e = EndpointConfig::parse_sided("gcs:127.0.0.1:14550", 1).unwrap();
        assert_eq!((e.name.as_str(), e.side), ("ground-2", Side::Gcs));
        let err = EndpointConfig::parse_sided("udpin:0.0.0.0:14550", 0).unwrap_err();
        assert!(err.to_string().contains("SIDE:URL"), "{err}");
        let err = EndpointConfig::parse_sided("vehicle:bogus:1.2.3.4:5", 0).unwrap_err();
        assert!(err.to_string().contains("unknown scheme"), "{err}");
    }
}
