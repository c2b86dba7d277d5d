//! What the guard is told: endpoints, mode, logs, signing. Plain data; the CLI fills it from its
//! arguments, tests and library users directly.

use std::path::PathBuf;
use std::sync::mpsc::SyncSender;

use super::endpoint::Endpoint;
use super::events::GuardEvent;
use crate::signing::SigningKey;

/// Configuration of one guard.
#[derive(Debug)]
pub struct GuardConfig {
    /// The ground-station side.
    pub gcs: Endpoint,
    /// The vehicle side.
    pub vehicle: Endpoint,
    /// Drop violating frames and answer instead of only reporting.
    pub enforce: bool,
    /// Send a STATUSTEXT to the GCS for each violation (rate-limited).
    pub alert_gcs: bool,
    /// Violations log, one JSON object per line.
    pub log_path: Option<PathBuf>,
    /// Recording of every received frame (8-byte big-endian µs timestamp + frame), both ways.
    pub tlog_path: Option<PathBuf>,
    /// MAVLink 2 signing required from the GCS side.
    pub signing: Option<SigningConfig>,
    /// Where events go as they happen (at most [`MAX_EVENTS_PER_SECOND`](super::MAX_EVENTS_PER_SECOND);
    /// events that find the channel full are not sent). `None`: counters and log only.
    pub events: Option<SyncSender<GuardEvent>>,
}

impl GuardConfig {
    /// Monitor mode, no alerts, logs, signing or events.
    pub fn new(gcs: Endpoint, vehicle: Endpoint) -> Self {
        GuardConfig {
            gcs,
            vehicle,
            enforce: false,
            alert_gcs: false,
            log_path: None,
            tlog_path: None,
            signing: None,
            events: None,
        }
    }
}

/// MAVLink 2 signing: frames from the GCS side must carry a valid signature; optionally the
/// guard (re)signs what it forwards to the vehicle.
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
