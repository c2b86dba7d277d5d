//! The router's shared state: what every reader thread works with. Admission (`admit.rs`) and
//! routing (`router.rs`) add their methods to [`Core`].

use std::fs::File;
use std::io::BufWriter;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU64};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use super::Inspector;
use super::counters::Counters;
use super::dedup::Dedup;
use super::endpoint::Endpoint;
use super::events::Events;
use super::filter::Filter;
use super::link::Egress;
use super::routing::{Routes, Targets};
use crate::side::Side;
use crate::signing::{Signer, Verifier};

/// What the router keeps of each endpoint's configuration.
pub(super) struct EndpointState {
    pub(super) name: String,
    pub(super) side: Side,
    pub(super) link: Endpoint,
    pub(super) inbound: Filter,
    /// The incoming filter lets everything through (the common case: no early integrity check).
    pub(super) inbound_open: bool,
    /// Whether the warning about autopilot heartbeats on a ground endpoint was given.
    pub(super) warned: AtomicBool,
}

pub(super) struct Core {
    pub(super) enforce: bool,
    pub(super) alert_gcs: bool,
    pub(super) inspector: Mutex<Box<dyn Inspector>>,
    pub(super) verifier: Option<Arc<Mutex<Verifier>>>,
    /// Signs what the guard sends toward the vehicle: its own replies whenever a key is set,
    /// forwarded frames too with `sign_forwarded` (`--sign-to-vehicle`).
    pub(super) signer: Option<Mutex<Signer>>,
    pub(super) sign_forwarded: bool,
    pub(super) endpoints: Vec<EndpointState>,
    pub(super) egress: Vec<OnceLock<Arc<Egress>>>,
    pub(super) routes: Mutex<Routes>,
    pub(super) targets: Option<Targets>,
    pub(super) dedup: Option<Mutex<Dedup>>,
    pub(super) counters: Counters,
    pub(super) log: Option<Mutex<BufWriter<File>>>,
    pub(super) tlog: Option<Mutex<BufWriter<File>>>,
    pub(super) own_seq: AtomicU8,
    /// Vehicle (sysid, compid) from its first HEARTBEAT, packed as sysid << 8 | compid + 1
    /// (0 = not seen yet); alerts are sent in the vehicle's name so GCSs display them.
    pub(super) vehicle_ids: AtomicU64,
    pub(super) alert_window: Mutex<(Instant, u64)>,
    pub(super) events: Events,
}

pub(super) fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

pub(super) fn unix_micros() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_micros() as u64).unwrap_or(0)
}
