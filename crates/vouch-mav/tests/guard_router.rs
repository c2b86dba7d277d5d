//! The router with five endpoints at once on loopback — two vehicles (UDP client, TCP client),
//! two ground stations (UDP server, UDP client that the guard sends to first, as to
//! QGroundControl) and a companion (TCP server client) — and scripted peers that record every
//! frame they get: who receives what (targets, broadcasts, filters), a TCP endpoint that drops
//! and comes back, and monitor verdicts applied at the endpoint a frame arrives on. The expected
//! receivers follow mavlink-router's documented routing rules.

mod guard_support;

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream, UdpSocket};
use std::sync::Arc;
use std::time::{Duration, Instant};

use guard_support::{connected, loopback, standard_inspector};
use vouch_mav::Side;
use vouch_mav::codec::{FrameRef, MessageBuilder, StreamSplitter};
use vouch_mav::dialect::Dialect;
use vouch_mav::guard::{
    EndpointConfig, Filter, GuardConfig, PassThrough, RoutingOptions, RunningGuard, start,
};

const WAIT: Duration = Duration::from_millis(400);

fn dialect() -> Option<Arc<Dialect>> {
    match Dialect::default_dialect() {
        Ok(d) => Some(Arc::new(d)),
        Err(e) => vouch_testkit::missing(vouch_testkit::Need::Shared, &format!("no dialect ({e})")),
    }
}

/// (sysid, compid, msgid) of every frame in `bytes`.
fn frames(bytes: &[u8]) -> Vec<(u8, u8, u32)> {
    let mut out = vec![];
    StreamSplitter::default().push(bytes, |b, is_frame| {
        if is_frame {
            let f = FrameRef::new(b).expect("frame");
            out.push((f.sysid(), f.compid(), f.msgid()));
        }
    });
    out
}

/// A scripted peer on a UDP socket or a TCP stream.
enum Peer {
    Udp(UdpSocket, SocketAddr),
    Tcp(TcpStream),
}

impl Peer {
    fn send(&mut self, frame: &[u8]) {
        match self {
            Peer::Udp(s, to) => {
                s.send_to(frame, *to).unwrap();
            }
            Peer::Tcp(s) => s.write_all(frame).unwrap(),
        }
    }

    /// Every frame received within `wait`.
    fn got(&mut self, wait: Duration) -> Vec<(u8, u8, u32)> {
        let end = Instant::now() + wait;
        let mut bytes = vec![];
        let mut buf = [0u8; 4096];
        while Instant::now() < end {
            let n = match self {
                Peer::Udp(s, _) => s.recv_from(&mut buf).map(|(n, _)| n),
                Peer::Tcp(s) => s.read(&mut buf),
            };
            if let Ok(n) = n {
                bytes.extend_from_slice(&buf[..n]);
            }
        }
        frames(&bytes)
    }
}

fn udp_peer(to: SocketAddr) -> Peer {
    let s = UdpSocket::bind("127.0.0.1:0").unwrap();
    s.set_read_timeout(Some(Duration::from_millis(20))).unwrap();
    Peer::Udp(s, to)
}

fn tcp_peer(s: TcpStream) -> Peer {
    s.set_read_timeout(Some(Duration::from_millis(20))).unwrap();
    Peer::Tcp(s)
}

struct Msgs {
    d: Arc<Dialect>,
}

impl Msgs {
    fn heartbeat(&self, sys: u8, comp: u8, gcs: bool) -> Vec<u8> {
        let (ty, autopilot) = if gcs { (6, 8) } else { (2, 3) };
        MessageBuilder::new(&self.d, "HEARTBEAT")
            .and_then(|b| b.set("type", ty))
            .and_then(|b| b.set("autopilot", autopilot))
            .and_then(|b| b.set("mavlink_version", 3))
            .unwrap()
            .frame_v2(0, sys, comp)
    }
    fn command(&self, from: (u8, u8), to: (u8, u8), command: u16) -> Vec<u8> {
        MessageBuilder::new(&self.d, "COMMAND_LONG")
            .and_then(|b| b.set("target_system", to.0))
            .and_then(|b| b.set("target_component", to.1))
            .and_then(|b| b.set("command", command))
            .unwrap()
            .frame_v2(0, from.0, from.1)
    }
    fn attitude(&self, from: (u8, u8)) -> Vec<u8> {
        MessageBuilder::new(&self.d, "ATTITUDE").unwrap().frame_v2(0, from.0, from.1)
    }
    fn ack(&self, from: (u8, u8), to: (u8, u8)) -> Vec<u8> {
        MessageBuilder::new(&self.d, "COMMAND_ACK")
            .and_then(|b| b.set("command", 400))
            .and_then(|b| b.set("target_system", to.0))
            .and_then(|b| b.set("target_component", to.1))
            .unwrap()
            .frame_v2(0, from.0, from.1)
    }
}

struct Rig {
    guard: RunningGuard,
    v1: Peer,
    v2_listener: TcpListener,
    v2: Peer,
    a: Peer,
    b: Peer,
    comp: Peer,
    m: Msgs,
}

impl Rig {
    fn all(&mut self) -> [&mut Peer; 5] {
        [&mut self.v1, &mut self.v2, &mut self.a, &mut self.b, &mut self.comp]
    }

    /// What each peer got (v1, v2, a, b, comp) within the wait.
    fn received(&mut self) -> Vec<Vec<(u8, u8, u32)>> {
        let mut out = vec![];
        let end = Instant::now() + WAIT;
        for p in self.all() {
            out.push(
                p.got(end.saturating_duration_since(Instant::now()).max(Duration::from_millis(30))),
            );
        }
        out
    }
}

const ATTITUDE: u32 = 30;
const COMMAND_LONG: u32 = 76;
const COMMAND_ACK: u32 = 77;

fn rig(enforce: bool, inspector: Box<dyn vouch_mav::guard::Inspector>) -> Option<Rig> {
    let d = dialect()?;
    let v1_sock = UdpSocket::bind("127.0.0.1:0").unwrap();
    let v2_listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let b_sock = UdpSocket::bind("127.0.0.1:0").unwrap();
    let ep =
        |name: &str, side, link: String| EndpointConfig::new(name, side, link.parse().unwrap());
    let mut v2 = ep("v2", Side::Vehicle, format!("tcpout:{}", v2_listener.local_addr().unwrap()));
    v2.retry = Some(Duration::from_millis(300));
    let mut b = ep("b", Side::Gcs, format!("udpout:{}", b_sock.local_addr().unwrap()));
    b.filters.outbound = Filter { block_msg: vec![ATTITUDE], ..Filter::default() };
    let mut comp = ep("comp", Side::Gcs, "tcpin:127.0.0.1:0".into());
    comp.filters.inbound = Filter { block_msg: vec![ATTITUDE], ..Filter::default() };
    let endpoints = vec![
        ep("v1", Side::Vehicle, format!("udpout:{}", v1_sock.local_addr().unwrap())),
        v2,
        ep("a", Side::Gcs, "udpin:127.0.0.1:0".into()),
        b,
        comp,
    ];
    let cfg = GuardConfig {
        enforce,
        routing: RoutingOptions { dialect: Some(d.clone()), ..RoutingOptions::default() },
        ..GuardConfig::with_endpoints(endpoints)
    };
    let guard = start(cfg, inspector).expect("guard starts");
    let at = |n: &str| loopback(guard.local_addr(n).expect("bound"));
    v1_sock.set_read_timeout(Some(Duration::from_millis(20))).unwrap();
    b_sock.set_read_timeout(Some(Duration::from_millis(20))).unwrap();
    let v1 = Peer::Udp(v1_sock, at("v1"));
    let b = Peer::Udp(b_sock, at("b"));
    v2_listener.set_nonblocking(false).unwrap();
    let (v2s, _) = v2_listener.accept().expect("the guard connects to v2");
    let comp = tcp_peer(TcpStream::connect(at("comp")).unwrap());
    let a = udp_peer(at("a"));
    let mut r = Rig { guard, v1, v2_listener, v2: tcp_peer(v2s), a, b, comp, m: Msgs { d } };
    // TCP connections are accepted before the guard has registered them
    connected(&r.guard, "v2", 1);
    connected(&r.guard, "comp", 1);
    // everyone announces itself; heartbeats have no target: everyone else gets them
    let hbs = [
        r.m.heartbeat(1, 1, false),
        r.m.heartbeat(2, 1, false),
        r.m.heartbeat(255, 190, true),
        r.m.heartbeat(254, 190, true),
        r.m.heartbeat(1, 191, true),
    ];
    // a first: a UDP server learns its peers from what they send
    for i in [2, 0, 1, 3, 4] {
        r.all()[i].send(&hbs[i]);
        std::thread::sleep(Duration::from_millis(20));
    }
    let got = r.received();
    let ids = [(1, 1), (2, 1), (255, 190), (254, 190), (1, 191)];
    for (i, g) in got.iter().enumerate() {
        let mut want: Vec<(u8, u8, u32)> = ids
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, id)| (id.0, id.1, 0))
            .collect();
        let mut g = g.clone();
        g.sort();
        want.sort();
        assert_eq!(g, want, "heartbeats received by peer {i}");
    }
    Some(r)
}

#[test]
fn targeted_frames_reach_only_their_target_and_broadcasts_reach_everyone_else() {
    let Some(mut r) = rig(false, Box::new(PassThrough)) else { return };
    let who = |got: &[Vec<(u8, u8, u32)>], msgid: u32| -> Vec<usize> {
        (0..got.len()).filter(|&i| got[i].iter().any(|f| f.2 == msgid)).collect()
    };
    // GCS a commands vehicle 2: only vehicle 2 gets it
    let cmd = r.m.command((255, 190), (2, 1), 400);
    r.a.send(&cmd);
    assert_eq!(who(&r.received(), COMMAND_LONG), vec![1]);
    // GCS b asks vehicle 1
    let cmd = r.m.command((254, 190), (1, 1), 400);
    r.b.send(&cmd);
    assert_eq!(who(&r.received(), COMMAND_LONG), vec![0]);
    // vehicle 1 answers GCS b only
    let ack = r.m.ack((1, 1), (254, 190));
    r.v1.send(&ack);
    assert_eq!(who(&r.received(), COMMAND_ACK), vec![3]);
    // to every component of system 1: vehicle 1 and the companion (1/191)
    let cmd = r.m.command((255, 190), (1, 0), 400);
    r.a.send(&cmd);
    assert_eq!(who(&r.received(), COMMAND_LONG), vec![0, 4]);
    // to a system never seen: nobody
    let cmd = r.m.command((255, 190), (9, 1), 400);
    r.a.send(&cmd);
    assert_eq!(who(&r.received(), COMMAND_LONG), Vec::<usize>::new());
    // telemetry of vehicle 1: everyone but b (BlockMsgIdOut = 30)
    let att = r.m.attitude((1, 1));
    r.v1.send(&att);
    assert_eq!(who(&r.received(), ATTITUDE), vec![1, 2, 4]);
    // the companion's own telemetry is dropped on the way in (BlockMsgIdIn = 30)
    let att = r.m.attitude((1, 191));
    r.comp.send(&att);
    assert_eq!(who(&r.received(), ATTITUDE), Vec::<usize>::new());
    let c = r.guard.stop();
    assert!(c.unrouted >= 1, "{c:?}");
    assert_eq!(c.endpoint("b").unwrap().filtered_out, 1, "{c:?}");
    assert_eq!(c.endpoint("comp").unwrap().filtered_in, 1, "{c:?}");
    assert_eq!(c.endpoint("v2").unwrap().frames_in, 1, "{c:?}");
}

#[test]
fn a_tcp_vehicle_that_drops_is_reconnected_and_routed_again() {
    let Some(mut r) = rig(false, Box::new(PassThrough)) else { return };
    // vehicle 2 goes away; the guard connects again after its retry time
    let Peer::Tcp(s) = &r.v2 else { unreachable!() };
    s.shutdown(std::net::Shutdown::Both).unwrap();
    r.v2_listener.set_nonblocking(false).unwrap();
    let t = Instant::now();
    let (again, _) = r.v2_listener.accept().expect("the guard reconnects");
    assert!(t.elapsed() < Duration::from_secs(3), "reconnected after {:?}", t.elapsed());
    r.v2 = tcp_peer(again);
    connected(&r.guard, "v2", 2);
    // what it learned about system 2 is kept: a command to 2/1 reaches the new connection
    let cmd = r.m.command((255, 190), (2, 1), 400);
    r.a.send(&cmd);
    let got = r.received();
    assert!(got[1].iter().any(|f| f.2 == COMMAND_LONG), "{got:?}");
    let hb = r.m.heartbeat(2, 1, false);
    r.v2.send(&hb);
    let got = r.received();
    assert!(got[2].contains(&(2, 1, 0)), "ground station a hears vehicle 2 again: {got:?}");
    let c = r.guard.counters();
    let v2 = c.endpoint("v2").unwrap();
    assert_eq!((v2.connects, v2.connections), (2, 1), "{c:?}");
    r.guard.stop();
}

#[test]
fn a_violation_from_one_gcs_is_dropped_while_the_other_keeps_working() {
    let Some(inspector) = standard_inspector() else { return };
    let Some(mut r) = rig(true, inspector) else { return };
    // DO_PARACHUTE release (208, param1 = 2) from a to vehicle 2, which never said it is armed
    let chute = MessageBuilder::new(&r.m.d, "COMMAND_LONG")
        .and_then(|b| b.set("target_system", 2))
        .and_then(|b| b.set("target_component", 1))
        .and_then(|b| b.set("command", 208))
        .and_then(|b| b.set("param1", 2))
        .unwrap()
        .frame_v2(1, 255, 190);
    r.a.send(&chute);
    // b's request to vehicle 1 at the same time
    let cmd = r.m.command((254, 190), (1, 1), 400);
    r.b.send(&cmd);
    let got = r.received();
    assert!(
        !got[1].iter().any(|f| f.2 == COMMAND_LONG),
        "vehicle 2 never gets the release: {got:?}"
    );
    assert!(got[0].contains(&(254, 190, COMMAND_LONG)), "vehicle 1 gets b's command: {got:?}");
    // the answer goes back to a only (in vehicle 2's name or the guard's), nobody else
    assert!(got[2].iter().any(|f| f.2 == COMMAND_ACK), "a is answered: {got:?}");
    for i in [0, 1, 3, 4] {
        assert!(!got[i].iter().any(|f| f.2 == COMMAND_ACK), "peer {i}: {got:?}");
    }
    let c = r.guard.stop();
    assert_eq!((c.violations, c.dropped_violations, c.replies_sent), (1, 1, 1), "{c:?}");
}
