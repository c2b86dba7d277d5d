//! Sockets and serial ports behind the endpoints: reader threads that hand what they receive to
//! the router (a [`Sink`]), and an [`Egress`] per endpoint that sends to one of its connections.
//!
//! Readers block with a short timeout so they notice the stop flag; that keeps the hot path to
//! one receive and one send system call per batch with no poll call in between. After each
//! receive batch a reader calls [`Sink::end_batch`], where the router sends what the batch
//! produced.

mod serial;
mod stream;
mod udp;
mod writer;

use std::io;
use std::net::{SocketAddr, TcpStream, UdpSocket};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::config::EndpointConfig;
use super::endpoint::Endpoint;
use super::sys::udp_batch;
use writer::Writer;

/// How often blocked readers wake up to look at the stop flag.
pub const POLL_INTERVAL: Duration = Duration::from_millis(100);
/// Most UDP peers remembered per UDP server endpoint (several ground stations on one port); the
/// least recently heard one is forgotten first, so memory is bounded whatever arrives.
pub const MAX_UDP_PEERS: usize = 16;
/// A UDP server peer silent this long is forgotten.
pub const UDP_PEER_IDLE: Duration = Duration::from_secs(60);
/// A broadcast UDP client that heard nothing from its peer this long broadcasts again.
pub const BROADCAST_FALLBACK: Duration = Duration::from_secs(5);
/// Most simultaneous TCP clients accepted on a TCP server endpoint.
pub const MAX_TCP_CLIENTS: usize = 8;

/// One connection of an endpoint: what a route is, what a reply goes back to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Peer {
    /// The one connection of a UDP client, TCP client or serial endpoint.
    Fixed,
    /// A peer of a UDP server endpoint.
    Udp(SocketAddr),
    /// A client of a TCP server endpoint, by its connection number.
    Stream(u64),
}

impl std::fmt::Display for Peer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Peer::Fixed => write!(f, "-"),
            Peer::Udp(a) => write!(f, "{a}"),
            Peer::Stream(n) => write!(f, "client {n}"),
        }
    }
}

/// What a reader hands to the router: a whole UDP datagram, or one piece cut from a byte stream.
pub enum Received<'a> {
    Datagram(&'a [u8]),
    StreamFrame(&'a [u8]),
    StreamJunk(&'a [u8]),
    /// A datagram larger than a receive slot: cannot be forwarded intact, so never forwarded.
    Oversized(usize),
}

/// A change of an endpoint's connections.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LinkEvent {
    /// A connection exists now (a UDP server heard a new peer, a TCP client connected or was
    /// accepted); `what` describes it (the remote address).
    Opened { what: String },
    /// A connection is gone; `reconnect_in` is set when a TCP client will try again.
    Closed { reason: String, reconnect_in: Option<Duration> },
    /// A TCP client could not connect.
    ConnectFailed { reason: String, reconnect_in: Option<Duration> },
}

/// The router, as the readers see it.
pub trait Sink: Send + Sync {
    /// Handles one received piece from connection `peer` of endpoint `ep`. Returns `false` only
    /// for a `StreamFrame` that is not a frame after all (bad checksum): the stream reader then
    /// resynchronises after its first byte.
    fn received(&self, ep: usize, peer: Peer, rx: Received<'_>) -> bool;
    /// The end of one receive batch: send what it produced.
    fn end_batch(&self);
    /// A connection of endpoint `ep` opened or closed.
    fn link(&self, ep: usize, peer: Peer, ev: LinkEvent);
}

/// Where a UDP client sends: its configured address, or (broadcast) the last peer that answered.
struct UdpTarget {
    configured: SocketAddr,
    learned: Mutex<Option<(SocketAddr, Instant)>>,
}

enum EgressKind {
    /// A UDP server: sends to the peer named by the route.
    UdpServer {
        sock: Arc<UdpSocket>,
    },
    /// A UDP client: sends to its target.
    UdpClient {
        sock: Arc<UdpSocket>,
        target: Arc<UdpTarget>,
        broadcast: bool,
    },
    /// TCP server clients by connection number, or the one connection of a TCP client (`Fixed`),
    /// each with its writer thread.
    Streams {
        conns: Mutex<Vec<(u64, Writer)>>,
    },
    Serial {
        out: Writer,
    },
}

/// Sending half of one endpoint.
pub struct Egress {
    kind: EgressKind,
}

/// The connection number the one connection of a TCP client endpoint is stored under.
const FIXED_STREAM: u64 = u64::MAX;

impl Egress {
    /// Sends `bytes` to connection `peer`. A UDP send joins the calling thread's `sendmmsg`
    /// batch when one is open ([`udp_batch::begin`]); a stream send is written at once when the
    /// stream is idle, else queued for its writer thread (`false` when its queue is full).
    pub fn send(&self, peer: Peer, bytes: &[u8]) -> bool {
        match (&self.kind, peer) {
            (EgressKind::UdpServer { sock }, Peer::Udp(a)) => udp_batch::send_to(sock, bytes, &a),
            (EgressKind::UdpClient { sock, target, broadcast }, _) => {
                let to = if *broadcast { target.current() } else { target.configured };
                udp_batch::send_to(sock, bytes, &to)
            }
            (EgressKind::Streams { conns }, p) => {
                let id = match p {
                    Peer::Stream(id) => id,
                    _ => FIXED_STREAM,
                };
                lock(conns).iter().find(|(i, _)| *i == id).is_some_and(|(_, w)| w.send(bytes))
            }
            (EgressKind::Serial { out }, _) => out.send(bytes),
            (EgressKind::UdpServer { .. }, _) => false,
        }
    }

    /// Whether this endpoint cuts what it sends into datagrams (so that coalesced frames must
    /// stay within a datagram size).
    pub fn is_datagram(&self) -> bool {
        matches!(self.kind, EgressKind::UdpServer { .. } | EgressKind::UdpClient { .. })
    }

    /// Registers a TCP connection with a writer thread (and direct writes while nothing is
    /// queued); a failed write shuts the connection down, so that its reader ends and closes it.
    fn add_stream(&self, id: u64, s: TcpStream, name: &str) -> io::Result<()> {
        let EgressKind::Streams { conns } = &self.kind else { return Ok(()) };
        let closer = s.try_clone()?;
        let direct = Some(s.try_clone()?);
        let w = Writer::spawn(format!("{name}-write"), s, direct, move || {
            let _ = closer.shutdown(std::net::Shutdown::Both);
        })?;
        lock(conns).push((id, w));
        Ok(())
    }

    fn remove_stream(&self, id: u64) {
        if let EgressKind::Streams { conns } = &self.kind {
            lock(conns).retain(|(i, _)| *i != id);
        }
    }

    fn stream_count(&self) -> usize {
        match &self.kind {
            EgressKind::Streams { conns } => lock(conns).len(),
            _ => 0,
        }
    }
}

impl UdpTarget {
    fn current(&self) -> SocketAddr {
        match *lock(&self.learned) {
            Some((a, t)) if t.elapsed() < BROADCAST_FALLBACK => a,
            _ => self.configured,
        }
    }

    fn heard(&self, from: SocketAddr) {
        *lock(&self.learned) = Some((from, Instant::now()));
    }
}

/// A receive error that only means "nothing yet" (timeout, signal).
fn is_transient(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut | io::ErrorKind::Interrupted
    )
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    // A panicking holder cannot leave these simple collections inconsistent: keep going.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// An opened endpoint: its egress, its reader threads, and the local address it is bound to.
pub struct OpenedLink {
    pub egress: Arc<Egress>,
    pub local_addr: Option<SocketAddr>,
    pub threads: Vec<JoinHandle<()>>,
}

/// What every reader of one endpoint needs.
#[derive(Clone)]
pub(super) struct ReaderCtx {
    pub ep: usize,
    pub name: String,
    pub sink: Arc<dyn Sink>,
    pub stop: Arc<AtomicBool>,
}

/// Opens endpoint number `ep` and starts its readers. Binding or opening errors are returned;
/// a TCP client that cannot connect yet is not an error (it retries in the background).
pub fn open(
    ep: usize,
    cfg: &EndpointConfig,
    sink: Arc<dyn Sink>,
    stop: Arc<AtomicBool>,
) -> io::Result<OpenedLink> {
    let rc = ReaderCtx { ep, name: cfg.name.clone(), sink, stop };
    match &cfg.link {
        Endpoint::UdpIn(addr) => udp::open_server(rc, *addr),
        Endpoint::UdpOut(to) | Endpoint::UdpBcast(to) => {
            udp::open_client(rc, *to, cfg.link.is_broadcast())
        }
        Endpoint::TcpIn(addr) => stream::open_tcp_server(rc, *addr),
        Endpoint::TcpOut(peer) => Ok(stream::open_tcp_client(rc, *peer, cfg.retry)),
        Endpoint::Serial { device, baud } => {
            stream::open_serial(rc, device, *baud, cfg.flow_control)
        }
    }
}
