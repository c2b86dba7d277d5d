//! `vouch mav guard`: a MAVLink proxy between ground station(s) and vehicle that forwards every
//! frame byte for byte and lets an [`Inspector`] (the protocol monitor) judge each one.
//!
//! Data path per received datagram: split into frames → (from the GCS, when a key is set) signing
//! check → inspector verdict → forward the original bytes, or in enforce mode drop and answer.
//! The IR-level protocol checking lives in the monitor; this module knows sockets and bytes.

#[allow(unsafe_code)] // process and thread CPU clocks through libc
pub mod bench;
pub mod cli;
pub mod endpoint;
pub mod frame;
mod link;
pub mod messages;
mod monitor_inspector;
mod proxy;
#[allow(unsafe_code)] // termios through libc
mod serial;
#[allow(unsafe_code)] // recvmmsg/sendmmsg through libc
mod udp_batch;

use serde_json::Value;

pub use endpoint::Endpoint;
pub use frame::FrameRef;
pub use link::{MAX_TCP_CLIENTS, MAX_UDP_PEERS};
pub use monitor_inspector::build as standard_inspector;
pub use proxy::{start, CounterSnapshot, GuardConfig, RunningGuard, SigningConfig};

/// Which side of the proxy a frame came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    Gcs,
    Vehicle,
}

impl Side {
    pub fn other(self) -> Side {
        match self {
            Side::Gcs => Side::Vehicle,
            Side::Vehicle => Side::Gcs,
        }
    }
    pub fn as_str(self) -> &'static str {
        match self {
            Side::Gcs => "gcs",
            Side::Vehicle => "vehicle",
        }
    }
    fn index(self) -> usize {
        self as usize
    }
}

/// A message the guard sends on its own (enforce-mode answers, alerts). The guard frames it as
/// MAVLink 2 with its own sequence counter; `payload` may be given untruncated.
#[derive(Clone, Debug, PartialEq)]
pub struct Reply {
    pub to: Side,
    pub msgid: u32,
    pub crc_extra: u8,
    pub payload: Vec<u8>,
    /// Source ids to send from, normally the peer the answer stands in for (e.g. the vehicle's
    /// ids for a MISSION_ACK sent to the GCS, so that the GCS accepts it).
    pub sysid: u8,
    pub compid: u8,
}

/// A protocol violation found by the inspector.
#[derive(Clone, Debug)]
pub struct Finding {
    /// One line for humans and STATUSTEXT (cut to 50 bytes there).
    pub summary: String,
    /// Full machine-readable report, written to the violations log.
    pub record: Value,
    /// What to answer in enforce mode so that neither side hangs (may be empty).
    pub replies: Vec<Reply>,
}

/// The inspector's judgement of one frame.
#[derive(Debug)]
pub enum Verdict {
    /// Part of no tracked protocol, or a correct step of one: forward.
    Accept,
    /// Not a valid frame (bad checksum, unknown incompatibility flag, …): the proxy treats its
    /// bytes as garbage and rescans after its start marker (dropped in enforce mode).
    Malformed(&'static str),
    Violation(Finding),
}

/// Judges frames. Called from the reader threads under one lock, so implementations see every
/// frame of both directions in arrival order.
pub trait Inspector: Send {
    fn inspect(&mut self, from: Side, frame: FrameRef<'_>) -> Verdict;

    /// Whether a length-cut candidate is an intact frame (checksum, incompatibility flags). The
    /// proxy asks this before checking signatures, so that a corrupt frame is resynchronised over
    /// rather than judged; without signing, [`Verdict::Malformed`] from `inspect` has the same
    /// effect. The default trusts the length cut (no dialect, no checksum knowledge).
    fn is_intact(&mut self, _frame: FrameRef<'_>) -> bool {
        true
    }
}

/// The do-nothing inspector: the guard then behaves as a plain (optionally signing) relay.
pub struct PassThrough;

impl Inspector for PassThrough {
    fn inspect(&mut self, _: Side, _: FrameRef<'_>) -> Verdict {
        Verdict::Accept
    }
}
