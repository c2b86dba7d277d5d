//! The guarding router between ground stations, companions and vehicles: any number of
//! endpoints, each trusted as the ground side or the vehicle side, routed as mavlink-router
//! routes (by target system and component, learned from the traffic), every frame forwarded byte
//! for byte and judged once by an [`Inspector`] (normally the protocol monitor,
//! [`MonitorInspector`]) at the trust boundary it crosses.
//!
//! Data path per received datagram: split into frames (the codec's resynchronising scan) →
//! integrity, deduplication, the endpoint's incoming filter → (from a ground endpoint, when a key
//! is set) signing check → inspector verdict → learn the sender on its connection → route by
//! target through the outgoing filters → forward the original bytes, or in enforce mode drop and
//! answer. The guard knows sockets and bytes; protocol semantics are the monitor's. It prints
//! nothing: what happens is reported as [`GuardEvent`]s on a channel the caller reads, and in the
//! counters. Endpoints come from the caller or from mavlink-router's configuration files
//! ([`conf`]).

mod admit;
pub mod conf;
mod config;
mod counters;
mod dedup;
mod endpoint;
mod events;
mod filter;
mod inspector;
mod link;
pub mod messages;
mod outbox;
pub(crate) mod portable;
mod router;
mod routing;
mod state;

#[cfg(target_os = "linux")]
#[allow(unsafe_code)] // the guard's Linux I/O module: recvmmsg/sendmmsg, process control
pub(crate) mod linux;

#[cfg(target_os = "linux")]
pub(crate) use linux as sys;
#[cfg(not(target_os = "linux"))]
pub(crate) use portable as sys;

use std::io;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

pub use config::{
    DEFAULT_TCP_RETRY, EndpointConfig, GuardConfig, RoutingOptions, SigningConfig, parse_side,
    side_word,
};
pub use counters::{CounterSnapshot, EndpointSnapshot};
pub use endpoint::{DEFAULT_BAUD, Endpoint, EndpointError, SUPPORTED_BAUDS};
pub use events::{GuardEvent, MAX_EVENTS_PER_SECOND};
pub use filter::{Filter, Filters};
pub use inspector::MonitorInspector;
pub use link::{MAX_TCP_CLIENTS, MAX_UDP_PEERS};
pub use outbox::DATAGRAM_LIMIT;
pub use router::{MAX_ENDPOINTS, RunningGuard, start};
pub use routing::{MAX_IDS_PER_ROUTE, MAX_ROUTES};

use crate::codec::{FrameRef, InvalidKind};
use crate::monitor::Verdict;
use crate::side::Side;

/// Judges frames. Called from the reader threads under one lock, so implementations see every
/// frame of both directions in arrival order.
pub trait Inspector: Send {
    /// Judges one length-cut frame from side `from`. `Err` means it is not an intact frame (bad
    /// checksum, unknown incompatibility flag, …): the proxy then treats its bytes as garbage and
    /// rescans after its start marker (dropped in enforce mode).
    fn inspect(&mut self, from: Side, frame: FrameRef<'_>) -> Result<Verdict, InvalidKind>;

    /// Whether a length-cut candidate is an intact frame (checksum, incompatibility flags). The
    /// proxy asks this before checking signatures, so that a corrupt frame is resynchronised over
    /// rather than counted as a forgery. The default trusts the length cut (no dialect, no
    /// checksum knowledge).
    fn is_intact(&mut self, _frame: FrameRef<'_>) -> bool {
        true
    }
}

/// The do-nothing inspector: the guard then behaves as a plain (optionally signing) relay.
pub struct PassThrough;

impl Inspector for PassThrough {
    fn inspect(&mut self, _: Side, _: FrameRef<'_>) -> Result<Verdict, InvalidKind> {
        Ok(Verdict::Ignore)
    }
}

/// A flag that SIGINT and SIGTERM set, for waiting until the operator stops the guard.
pub fn stop_on_signals() -> io::Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&stop))?;
    }
    Ok(stop)
}
