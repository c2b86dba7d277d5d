//! UDP endpoints: a server (bound to a port; every peer that sends is a connection of its own,
//! at most [`MAX_UDP_PEERS`], forgotten after [`UDP_PEER_IDLE`] of silence) and a client (sends
//! to a fixed address from an ephemeral port; to a broadcast address until a peer answers).

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use super::{
    Egress, EgressKind, LinkEvent, MAX_UDP_PEERS, OpenedLink, POLL_INTERVAL, Peer, ReaderCtx,
    Received, UDP_PEER_IDLE, UdpTarget, is_transient,
};
use crate::guard::sys::udp_batch::RecvBatch;

/// The peers a UDP server has heard, least recently heard first to go.
struct PeerSet {
    peers: Vec<(SocketAddr, Instant)>,
}

impl PeerSet {
    /// Notes a datagram from `a`; returns whether `a` is new and which peer it displaced.
    fn note(&mut self, a: SocketAddr, now: Instant) -> (bool, Option<SocketAddr>) {
        if let Some(p) = self.peers.iter_mut().find(|p| p.0 == a) {
            p.1 = now;
            return (false, None);
        }
        let mut evicted = None;
        if self.peers.len() >= MAX_UDP_PEERS
            && let Some(oldest) = (0..self.peers.len()).min_by_key(|&i| self.peers[i].1)
        {
            evicted = Some(self.peers.swap_remove(oldest).0);
        }
        self.peers.push((a, now));
        (true, evicted)
    }

    /// Forgets peers silent for [`UDP_PEER_IDLE`], returning them.
    fn expire(&mut self, now: Instant) -> Vec<SocketAddr> {
        let mut gone = vec![];
        self.peers.retain(|(a, t)| {
            let keep = now.duration_since(*t) < UDP_PEER_IDLE;
            if !keep {
                gone.push(*a);
            }
            keep
        });
        gone
    }
}

pub(super) fn open_server(rc: ReaderCtx, addr: SocketAddr) -> io::Result<OpenedLink> {
    let sock = Arc::new(UdpSocket::bind(addr)?);
    let local = sock.local_addr()?;
    let egress = Arc::new(Egress { kind: EgressKind::UdpServer { sock: sock.clone() } });
    let t = spawn_reader(rc, sock, Role::Server(PeerSet { peers: vec![] }))?;
    Ok(OpenedLink { egress, local_addr: Some(local), threads: vec![t] })
}

pub(super) fn open_client(
    rc: ReaderCtx,
    to: SocketAddr,
    broadcast: bool,
) -> io::Result<OpenedLink> {
    let any: std::net::IpAddr = if to.is_ipv4() {
        std::net::Ipv4Addr::UNSPECIFIED.into()
    } else {
        std::net::Ipv6Addr::UNSPECIFIED.into()
    };
    let bind = SocketAddr::new(any, 0);
    let sock = Arc::new(UdpSocket::bind(bind)?);
    if broadcast {
        sock.set_broadcast(true)?;
    }
    let local = sock.local_addr()?;
    let target = Arc::new(UdpTarget { configured: to, learned: Mutex::new(None) });
    let egress = Arc::new(Egress {
        kind: EgressKind::UdpClient { sock: sock.clone(), target: target.clone(), broadcast },
    });
    let role = if broadcast { Role::Broadcast(target) } else { Role::Client };
    let t = spawn_reader(rc, sock, role)?;
    Ok(OpenedLink { egress, local_addr: Some(local), threads: vec![t] })
}

enum Role {
    Server(PeerSet),
    Client,
    Broadcast(Arc<UdpTarget>),
}

fn spawn_reader(rc: ReaderCtx, sock: Arc<UdpSocket>, mut role: Role) -> io::Result<JoinHandle<()>> {
    sock.set_read_timeout(Some(POLL_INTERVAL))?;
    thread::Builder::new().name(format!("{}-udp", rc.name)).spawn(move || {
        let mut batch = RecvBatch::new();
        let mut last_peer: Option<SocketAddr> = None;
        let mut last_sweep = Instant::now();
        while !rc.stop.load(Ordering::Relaxed) {
            match batch.recv(&sock) {
                Ok(n) => {
                    for i in 0..n {
                        let (from, bytes, truncated) = batch.get(i);
                        let Some(from) = from else { continue };
                        // Only look at the peer table when the sender changes (cheap hot path).
                        if last_peer != Some(from) {
                            note_peer(&rc, &mut role, from);
                            last_peer = Some(from);
                        }
                        let peer = match role {
                            Role::Server(_) => Peer::Udp(from),
                            _ => Peer::Fixed,
                        };
                        let rx = if truncated {
                            Received::Oversized(bytes.len())
                        } else {
                            Received::Datagram(bytes)
                        };
                        rc.sink.received(rc.ep, peer, rx);
                    }
                    rc.sink.end_batch();
                }
                Err(e) if is_transient(&e) => {}
                // ICMP port unreachable from an earlier send surfaces here on Linux: not fatal.
                Err(e) if e.kind() == io::ErrorKind::ConnectionRefused => {}
                Err(_) => thread::sleep(POLL_INTERVAL / 10),
            }
            if last_sweep.elapsed() >= Duration::from_secs(1) {
                last_sweep = Instant::now();
                if let Role::Server(peers) = &mut role {
                    for gone in peers.expire(last_sweep) {
                        closed(&rc, gone, "silent");
                        last_peer = None;
                    }
                }
            }
        }
    })
}

fn closed(rc: &ReaderCtx, a: SocketAddr, why: &str) {
    let ev = LinkEvent::Closed { reason: why.into(), reconnect_in: None };
    rc.sink.link(rc.ep, Peer::Udp(a), ev);
}

fn note_peer(rc: &ReaderCtx, role: &mut Role, from: SocketAddr) {
    match role {
        Role::Server(peers) => {
            let (new, evicted) = peers.note(from, Instant::now());
            if let Some(old) = evicted {
                closed(rc, old, "too many peers: least recently heard one forgotten");
            }
            if new {
                rc.sink.link(rc.ep, Peer::Udp(from), LinkEvent::Opened { what: from.to_string() });
            }
        }
        Role::Broadcast(target) => target.heard(from),
        Role::Client => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peer_set_is_bounded_and_forgets_the_least_recently_heard() {
        let mut s = PeerSet { peers: vec![] };
        let t0 = Instant::now();
        let addr = |i: u16| SocketAddr::from(([127, 0, 0, 1], 1000 + i));
        for i in 0..MAX_UDP_PEERS as u16 {
            assert_eq!(s.note(addr(i), t0 + Duration::from_millis(u64::from(i))), (true, None));
        }
        assert_eq!(s.note(addr(0), t0 + Duration::from_secs(1)), (false, None));
        // peer 1 is now the least recently heard
        assert_eq!(s.note(addr(99), t0 + Duration::from_secs(2)), (true, Some(addr(1))));
        assert_eq!(s.peers.len(), MAX_UDP_PEERS);
        let gone = s.expire(t0 + UDP_PEER_IDLE + Duration::from_millis(500));
        assert_eq!(gone.len(), MAX_UDP_PEERS - 2, "all but the two heard later");
    }
}
