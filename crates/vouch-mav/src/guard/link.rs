//! Sockets and serial ports behind an endpoint: reader threads that hand received bytes to the
//! proxy core, and an [`Egress`] that sends to every peer of a side or back to one of them.
//!
//! Readers block with a short timeout so they notice the stop flag; that keeps the hot path to
//! one `recvfrom` + one `sendto` per datagram with no poll call in between.

use std::fs::File;
use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use super::endpoint::Endpoint;
use super::sys::serial;
use super::sys::udp_batch::{self, RecvBatch};
use crate::codec::split::StreamSplitter;

/// How often blocked readers wake up to look at the stop flag.
pub const POLL_INTERVAL: Duration = Duration::from_millis(100);
/// Most UDP peers remembered per side (several GCS clients on one port); the least recently
/// heard one is forgotten first, so memory is bounded whatever arrives.
pub const MAX_UDP_PEERS: usize = 16;
/// Most simultaneous TCP clients accepted on a `tcpin` endpoint.
pub const MAX_TCP_CLIENTS: usize = 8;

/// Who sent a piece of traffic, so that a reply can go back to exactly that peer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Peer {
    /// A UDP sender.
    Udp(SocketAddr),
    /// A TCP connection, by its id.
    Stream(usize),
    /// The serial port.
    Serial,
}

/// What a reader hands to the core: a whole UDP datagram, or one piece cut from a byte stream.
pub enum Received<'a> {
    Datagram(&'a [u8]),
    StreamFrame(&'a [u8]),
    StreamJunk(&'a [u8]),
    /// A datagram larger than a receive slot: cannot be forwarded intact, so never forwarded.
    Oversized(usize),
}

/// Called for everything a reader receives. Returns `false` only for a `StreamFrame` that is not
/// a frame after all (bad checksum): the stream reader then resynchronises after its first byte.
pub type Handler = Arc<dyn Fn(Peer, Received<'_>) -> bool + Send + Sync>;

struct PeerSet {
    peers: Vec<(SocketAddr, Instant)>,
}

impl PeerSet {
    fn note(&mut self, a: SocketAddr) {
        let now = Instant::now();
        if let Some(p) = self.peers.iter_mut().find(|p| p.0 == a) {
            p.1 = now;
            return;
        }
        if self.peers.len() >= MAX_UDP_PEERS {
            if let Some(oldest) = (0..self.peers.len()).min_by_key(|&i| self.peers[i].1) {
                self.peers.swap_remove(oldest);
            }
        }
        self.peers.push((a, now));
    }
}

enum EgressKind {
    /// `udpout`: one fixed peer.
    UdpFixed {
        sock: Arc<UdpSocket>,
        peer: SocketAddr,
    },
    /// `udpin`: peers learned from received datagrams.
    UdpLearned {
        sock: Arc<UdpSocket>,
        peers: Mutex<PeerSet>,
    },
    /// `tcpin`/`tcpout`: live connections by id.
    Streams {
        conns: Mutex<Vec<(usize, TcpStream)>>,
    },
    Serial {
        port: Mutex<File>,
    },
}

/// Sending half of one side of the proxy.
pub struct Egress {
    kind: EgressKind,
}

impl Egress {
    /// Sends `bytes` to every peer of this side. Errors on one peer do not stop the others
    /// (a GCS that went away must not block the rest); the count of successful sends is returned.
    pub fn send_all(&self, bytes: &[u8]) -> usize {
        match &self.kind {
            EgressKind::UdpFixed { sock, peer } => {
                usize::from(udp_batch::send_to(sock, bytes, peer))
            }
            EgressKind::UdpLearned { sock, peers } => {
                let peers = lock(peers);
                peers.peers.iter().filter(|(a, _)| udp_batch::send_to(sock, bytes, a)).count()
            }
            EgressKind::Streams { conns } => {
                let mut conns = lock(conns);
                // a connection that fails a write is gone: forget it
                conns.retain_mut(|(_, s)| s.write_all(bytes).is_ok());
                conns.len()
            }
            EgressKind::Serial { port } => usize::from(lock(port).write_all(bytes).is_ok()),
        }
    }

    /// Sends `bytes` only to the peer that `peer` names (replies to the sender).
    pub fn send_to(&self, peer: Peer, bytes: &[u8]) -> bool {
        match (&self.kind, peer) {
            (EgressKind::UdpFixed { sock, peer }, _) => udp_batch::send_to(sock, bytes, peer),
            (EgressKind::UdpLearned { sock, .. }, Peer::Udp(a)) => {
                udp_batch::send_to(sock, bytes, &a)
            }
            (EgressKind::Streams { conns }, Peer::Stream(id)) => lock(conns)
                .iter_mut()
                .find(|(i, _)| *i == id)
                .is_some_and(|(_, s)| s.write_all(bytes).is_ok()),
            (EgressKind::Serial { port }, _) => lock(port).write_all(bytes).is_ok(),
            _ => self.send_all(bytes) > 0,
        }
    }

    /// Number of peers this side currently sends to.
    pub fn peer_count(&self) -> usize {
        match &self.kind {
            EgressKind::UdpFixed { .. } | EgressKind::Serial { .. } => 1,
            EgressKind::UdpLearned { peers, .. } => lock(peers).peers.len(),
            EgressKind::Streams { conns } => lock(conns).len(),
        }
    }
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

/// Opens `ep`, starts its readers (named after `side`), and returns its egress.
pub fn open(
    ep: &Endpoint,
    side: &'static str,
    handler: Handler,
    stop: Arc<AtomicBool>,
) -> io::Result<OpenedLink> {
    match ep {
        Endpoint::UdpIn(addr) => {
            let sock = Arc::new(UdpSocket::bind(addr)?);
            let local = sock.local_addr()?;
            let egress = Arc::new(Egress {
                kind: EgressKind::UdpLearned {
                    sock: sock.clone(),
                    peers: Mutex::new(PeerSet { peers: vec![] }),
                },
            });
            let t = spawn_udp_reader(side, sock, Some(egress.clone()), handler, stop)?;
            Ok(OpenedLink { egress, local_addr: Some(local), threads: vec![t] })
        }
        Endpoint::UdpOut(peer) => {
            let bind: SocketAddr =
                if peer.is_ipv4() { "0.0.0.0:0" } else { "[::]:0" }.parse().expect("literal");
            let sock = Arc::new(UdpSocket::bind(bind)?);
            let local = sock.local_addr()?;
            let egress =
                Arc::new(Egress { kind: EgressKind::UdpFixed { sock: sock.clone(), peer: *peer } });
            let t = spawn_udp_reader(side, sock, None, handler, stop)?;
            Ok(OpenedLink { egress, local_addr: Some(local), threads: vec![t] })
        }
        Endpoint::TcpIn(addr) => {
            let listener = TcpListener::bind(addr)?;
            let local = listener.local_addr()?;
            listener.set_nonblocking(true)?;
            let egress =
                Arc::new(Egress { kind: EgressKind::Streams { conns: Mutex::new(vec![]) } });
            let eg = egress.clone();
            let t = thread::Builder::new().name(format!("{side}-accept")).spawn(move || {
                let next_id = AtomicUsize::new(0);
                let mut readers: Vec<JoinHandle<()>> = vec![];
                while !stop.load(Ordering::Relaxed) {
                    match listener.accept() {
                        Ok((s, _)) if eg.peer_count() < MAX_TCP_CLIENTS => {
                            let id = next_id.fetch_add(1, Ordering::Relaxed);
                            if let Ok(r) =
                                register_stream(&eg, id, s, side, handler.clone(), stop.clone())
                            {
                                readers.push(r);
                            }
                        }
                        Ok(_) => {} // over the client limit: dropping the stream closes it
                        Err(_) => thread::sleep(POLL_INTERVAL / 4),
                    }
                    readers.retain(|r| !r.is_finished());
                }
                readers.into_iter().for_each(|r| {
                    let _ = r.join();
                });
            })?;
            Ok(OpenedLink { egress, local_addr: Some(local), threads: vec![t] })
        }
        Endpoint::TcpOut(peer) => {
            let s = TcpStream::connect_timeout(peer, Duration::from_secs(5))?;
            let local = s.local_addr().ok();
            let egress =
                Arc::new(Egress { kind: EgressKind::Streams { conns: Mutex::new(vec![]) } });
            let t = register_stream(&egress, 0, s, side, handler, stop)?;
            Ok(OpenedLink { egress, local_addr: local, threads: vec![t] })
        }
        Endpoint::Serial { device, baud } => {
            let port = serial::open_raw(device, *baud)?;
            let reader = port.try_clone()?;
            let egress = Arc::new(Egress { kind: EgressKind::Serial { port: Mutex::new(port) } });
            let t = spawn_stream_reader(side, reader, Peer::Serial, false, handler, stop, || {})?;
            Ok(OpenedLink { egress, local_addr: None, threads: vec![t] })
        }
    }
}

fn register_stream(
    eg: &Arc<Egress>,
    id: usize,
    s: TcpStream,
    side: &'static str,
    handler: Handler,
    stop: Arc<AtomicBool>,
) -> io::Result<JoinHandle<()>> {
    s.set_nonblocking(false)?;
    s.set_nodelay(true)?;
    s.set_read_timeout(Some(POLL_INTERVAL))?;
    let reader = s.try_clone()?;
    if let EgressKind::Streams { conns } = &eg.kind {
        lock(conns).push((id, s));
    }
    let eg2 = eg.clone();
    spawn_stream_reader(side, reader, Peer::Stream(id), true, handler, stop, move || {
        if let EgressKind::Streams { conns } = &eg2.kind {
            lock(conns).retain(|(i, _)| *i != id);
        }
    })
}

fn spawn_udp_reader(
    side: &'static str,
    sock: Arc<UdpSocket>,
    learn: Option<Arc<Egress>>,
    handler: Handler,
    stop: Arc<AtomicBool>,
) -> io::Result<JoinHandle<()>> {
    sock.set_read_timeout(Some(POLL_INTERVAL))?;
    thread::Builder::new().name(format!("{side}-udp")).spawn(move || {
        let mut batch = RecvBatch::new();
        let mut last_peer: Option<SocketAddr> = None;
        while !stop.load(Ordering::Relaxed) {
            match batch.recv(&sock) {
                Ok(n) => {
                    udp_batch::begin();
                    for i in 0..n {
                        let (from, bytes, truncated) = batch.get(i);
                        let Some(from) = from else { continue };
                        if let Some(eg) = &learn {
                            // Only touch the peer table when the sender changes (cheap hot path).
                            if last_peer != Some(from) {
                                if let EgressKind::UdpLearned { peers, .. } = &eg.kind {
                                    lock(peers).note(from);
                                }
                                last_peer = Some(from);
                            }
                        }
                        if truncated {
                            let _ = handler(Peer::Udp(from), Received::Oversized(bytes.len()));
                        } else {
                            let _ = handler(Peer::Udp(from), Received::Datagram(bytes));
                        }
                    }
                    udp_batch::flush();
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::WouldBlock
                            | io::ErrorKind::TimedOut
                            | io::ErrorKind::Interrupted
                    ) => {}
                // ICMP port unreachable from an earlier send surfaces here on Linux: not fatal.
                Err(e) if e.kind() == io::ErrorKind::ConnectionRefused => {}
                Err(_) => thread::sleep(POLL_INTERVAL / 10),
            }
        }
    })
}

fn spawn_stream_reader<R: Read + Send + 'static>(
    side: &'static str,
    mut reader: R,
    peer: Peer,
    zero_is_eof: bool,
    handler: Handler,
    stop: Arc<AtomicBool>,
    on_close: impl FnOnce() + Send + 'static,
) -> io::Result<JoinHandle<()>> {
    thread::Builder::new().name(format!("{side}-stream")).spawn(move || {
        let mut buf = vec![0u8; 4096];
        let mut splitter = StreamSplitter::default();
        while !stop.load(Ordering::Relaxed) {
            match reader.read(&mut buf) {
                // TCP: 0 = peer closed. Serial (VMIN=0, VTIME=1): 0 = read timeout.
                Ok(0) if zero_is_eof => break,
                Ok(0) => {}
                Ok(n) => splitter.push_resync(&buf[..n], |piece, is_frame| {
                    handler(
                        peer,
                        if is_frame {
                            Received::StreamFrame(piece)
                        } else {
                            Received::StreamJunk(piece)
                        },
                    )
                }),
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::WouldBlock
                            | io::ErrorKind::TimedOut
                            | io::ErrorKind::Interrupted
                    ) => {}
                Err(_) => break,
            }
        }
        on_close();
    })
}
