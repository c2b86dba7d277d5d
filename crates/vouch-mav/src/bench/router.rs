//! The router scenario of `vouch mav bench`: the guard as a separate process with four
//! endpoints — the vehicle on a UDP server endpoint, two ground stations on UDP client endpoints
//! (listening, as QGroundControl does), a companion on a TCP server endpoint — and all standard
//! protocols, against the direct path and a socat relay (vehicle → first ground station) in the
//! same run:
//!
//! * one-way latency vehicle → first ground station, one telemetry frame in flight (median and
//!   spread);
//! * delivered throughput: telemetry frames *received* per second by the first ground station
//!   (and by all three ground peers together) while the vehicle sends as fast as it can, the
//!   relay pinned to CPU 0 and the bench to CPU 1; the offered rate and the relay's frames per
//!   CPU-second beside it;
//! * the relay's peak RSS at start-up and during the traffic.
//!
//! Every loop is bounded in count and time; only 127.0.0.1 is used.

use std::io::{self, Read};
use std::net::{SocketAddr, TcpStream, UdpSocket};
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serde::Serialize;

use super::traffic::{attitude, heartbeat_vehicle};
use super::{BenchConfig, Latency, PathKind, Relay, Skipped, Steps, spawn_relay, stop};
use crate::codec::frame::frame_len;
use crate::codec::split::{Piece, split_datagram};
use crate::guard::sys::{process, udp_batch};

/// Frames the vehicle sends in the throughput phase.
const BLAST: u32 = 600_000;
/// Phases of one path of the router scenario.
pub(super) const ROUTER_PHASES: u64 = 2;

/// The figures of one path of the router scenario.
#[derive(Clone, Debug, Serialize)]
pub struct RouterResult {
    /// Which path: `direct`, `socat`, `guard_router_relay_only`, `guard_router`.
    pub path: PathKind,
    /// Endpoints of the relay (1 + the ground peers it feeds).
    pub endpoints: u32,
    /// One-way latency vehicle → first ground station.
    pub telemetry: Latency,
    /// Frames per second the vehicle offered in the throughput phase.
    pub offered_per_s: f64,
    /// Frames per second received by the first ground station.
    pub delivered_per_s: f64,
    /// Frames per second received by all ground peers together.
    pub delivered_all_per_s: f64,
    /// Frames received by the first ground station per CPU-second of the relay.
    pub frames_per_cpu_second: Option<f64>,
    /// Peak RSS right after start-up, kB.
    pub startup_peak_rss_kb: Option<u64>,
    /// Peak RSS during the traffic, kB.
    pub peak_rss_kb: Option<u64>,
}

fn udp() -> io::Result<UdpSocket> {
    let s = UdpSocket::bind("127.0.0.1:0")?;
    s.set_read_timeout(Some(Duration::from_millis(100)))?;
    Ok(s)
}

fn frames_in(d: &[u8]) -> u64 {
    let mut n = 0;
    split_datagram(d, |p| n += u64::from(matches!(p, Piece::Frame(..))));
    n
}

/// A peer that only counts the frames it gets, until told to stop.
struct Drain {
    frames: Arc<AtomicU64>,
    done: Arc<AtomicBool>,
    thread: JoinHandle<()>,
}

impl Drain {
    fn udp(s: UdpSocket) -> Drain {
        let mut buf = vec![0u8; 65536];
        Self::spawn(move || s.recv_from(&mut buf).ok().map(|(n, _)| frames_in(&buf[..n])))
    }

    /// A TCP peer: whole frames are counted as the stream completes them.
    fn tcp(mut s: TcpStream) -> Drain {
        let _ = s.set_read_timeout(Some(Duration::from_millis(100)));
        let mut buf = vec![0u8; 65536];
        let mut carry: Vec<u8> = vec![];
        Self::spawn(move || {
            let n = s.read(&mut buf).ok().filter(|&n| n > 0)?;
            carry.extend_from_slice(&buf[..n]);
            let (mut used, mut frames) = (0, 0);
            while let Some(len) = frame_len(&carry[used..]) {
                if carry.len() - used < len {
                    break;
                }
                used += len;
                frames += 1;
            }
            carry.drain(..used);
            Some(frames)
        })
    }

    /// `recv` returns the frames of one receive (`None`: nothing within its timeout).
    fn spawn(mut recv: impl FnMut() -> Option<u64> + Send + 'static) -> Drain {
        let frames = Arc::new(AtomicU64::new(0));
        let done = Arc::new(AtomicBool::new(false));
        let (f, d) = (frames.clone(), done.clone());
        let thread = std::thread::spawn(move || {
            process::pin_current_thread(1);
            while !d.load(Ordering::Relaxed) {
                if let Some(n) = recv() {
                    f.fetch_add(n, Ordering::Relaxed);
                }
            }
        });
        Drain { frames, done, thread }
    }

    fn count(&self) -> u64 {
        self.frames.load(Ordering::Relaxed)
    }

    fn stop(self) {
        self.done.store(true, Ordering::Relaxed);
        let _ = self.thread.join();
    }
}

/// Sends vehicle heartbeats to `entry` until the first ground station hears one.
fn handshake(vehicle: &UdpSocket, entry: SocketAddr, gcs: &UdpSocket) -> io::Result<()> {
    let end = Instant::now() + Duration::from_secs(5);
    let mut buf = [0u8; 2048];
    let mut seq = 0u8;
    while Instant::now() < end {
        seq = seq.wrapping_add(1);
        vehicle.send_to(&heartbeat_vehicle(seq), entry)?;
        if gcs.recv_from(&mut buf).is_ok() {
            std::thread::sleep(Duration::from_millis(50));
            while gcs.recv_from(&mut buf).is_ok() {}
            return Ok(());
        }
    }
    Err(io::Error::new(io::ErrorKind::TimedOut, "path did not deliver a heartbeat within 5 s"))
}

/// One in-flight telemetry frames vehicle → first ground station.
fn pings(
    vehicle: &UdpSocket,
    entry: SocketAddr,
    gcs: &UdpSocket,
    n: usize,
) -> io::Result<Vec<f64>> {
    let mut out = Vec::with_capacity(n);
    let mut buf = [0u8; 2048];
    for i in 0..n {
        let t = Instant::now();
        vehicle.send_to(&attitude(i as u32, i as u8), entry)?;
        if gcs.recv_from(&mut buf).is_ok() {
            out.push(t.elapsed().as_secs_f64() * 1e6);
        }
    }
    Ok(out)
}

/// The vehicle sends [`BLAST`] frames as fast as it can (sendmmsg batches of 32); returns the
/// send duration.
fn blast(vehicle: &UdpSocket, entry: SocketAddr) -> f64 {
    process::pin_current_thread(1);
    let frames: Vec<Vec<u8>> = (0..1024u32).map(|i| attitude(i, i as u8)).collect();
    let start = Instant::now();
    let mut i = 0u32;
    while i < BLAST {
        udp_batch::begin();
        for _ in 0..32 {
            udp_batch::send_to(vehicle, &frames[(i % 1024) as usize], &entry);
            i += 1;
        }
        udp_batch::flush();
    }
    let secs = start.elapsed().as_secs_f64();
    process::unpin_current_thread();
    secs
}

/// Waits until the counts stop growing (300 ms without change), returning when they last grew.
fn settle(drains: &[&Drain], started: Instant) -> f64 {
    let mut last = drains.iter().map(|d| d.count()).sum::<u64>();
    let mut last_change = started.elapsed().as_secs_f64();
    let end = Instant::now() + Duration::from_secs(20);
    while Instant::now() < end {
        std::thread::sleep(Duration::from_millis(20));
        let now = drains.iter().map(|d| d.count()).sum::<u64>();
        if now != last {
            last = now;
            last_change = started.elapsed().as_secs_f64();
        } else if started.elapsed().as_secs_f64() - last_change > 0.3 {
            break;
        }
    }
    last_change
}

fn measure(
    path: PathKind,
    relay: &mut Relay,
    rig: Rig,
    a: &BenchConfig,
    steps: &mut Steps<'_>,
) -> io::Result<RouterResult> {
    let Rig { vehicle, entry, gcs1, gcs2, companion } = rig;
    let pid = match relay {
        Relay::Direct => None,
        Relay::Process { child, .. } => Some(child.id()),
    };
    handshake(&vehicle, entry, &gcs1)?;
    let endpoints = 2 + u32::from(gcs2.is_some()) + u32::from(companion.is_some());
    let mut r = RouterResult {
        path,
        endpoints,
        telemetry: Latency::default(),
        offered_per_s: 0.0,
        delivered_per_s: 0.0,
        delivered_all_per_s: 0.0,
        frames_per_cpu_second: None,
        startup_peak_rss_kb: None,
        peak_rss_kb: None,
    };
    if let Some(pid) = pid {
        r.startup_peak_rss_kb = process::peak_rss_kb(pid);
        process::reset_peak_rss(pid);
    }
    // The other peers are read only from the throughput phase on, so that no reader of theirs
    // wakes up during the latency phase (what they get meanwhile waits in socket buffers).
    steps.start(path, "telemetry latency");
    r.telemetry = Latency::of(pings(&vehicle, entry, &gcs1, a.pings)?);
    let mut others: Vec<Drain> = gcs2.into_iter().map(Drain::udp).collect();
    others.extend(companion.map(Drain::tcp));
    std::thread::sleep(Duration::from_millis(100));
    steps.start(path, "flood");
    if let Some(pid) = pid {
        process::pin_process(pid, 0);
    }
    let cpu0 = pid.and_then(process::cpu_seconds);
    let base: Vec<u64> = others.iter().map(Drain::count).collect();
    let first = Drain::udp(gcs1.try_clone()?);
    let started = Instant::now();
    let send_secs = blast(&vehicle, entry);
    let mut all: Vec<&Drain> = vec![&first];
    all.extend(others.iter());
    let last = settle(&all, started).max(1e-6);
    r.offered_per_s = f64::from(BLAST) / send_secs;
    let got = first.count();
    r.delivered_per_s = got as f64 / last;
    let rest: u64 = others.iter().zip(&base).map(|(d, b)| d.count() - b).sum();
    r.delivered_all_per_s = (got + rest) as f64 / last;
    if let (Some(pid), Some(c0)) = (pid, cpu0) {
        r.frames_per_cpu_second =
            process::cpu_seconds(pid).map(|c1| got as f64 / (c1 - c0).max(0.01));
        r.peak_rss_kb = process::peak_rss_kb(pid);
    }
    first.stop();
    others.into_iter().for_each(Drain::stop);
    Ok(r)
}

struct Rig {
    vehicle: UdpSocket,
    entry: SocketAddr,
    gcs1: UdpSocket,
    gcs2: Option<UdpSocket>,
    companion: Option<TcpStream>,
}

fn free_port() -> io::Result<u16> {
    Ok(UdpSocket::bind("127.0.0.1:0")?.local_addr()?.port())
}

fn connect(port: u16) -> io::Result<TcpStream> {
    let end = Instant::now() + Duration::from_secs(5);
    loop {
        match TcpStream::connect(("127.0.0.1", port)) {
            Ok(s) => return Ok(s),
            Err(e) if Instant::now() > end => return Err(e),
            Err(_) => std::thread::sleep(Duration::from_millis(50)),
        }
    }
}

fn one(
    path: PathKind,
    extra: Option<Vec<String>>,
    a: &BenchConfig,
    steps: &mut Steps<'_>,
) -> io::Result<RouterResult> {
    let (vehicle, gcs1) = (udp()?, udp()?);
    let g1 = gcs1.local_addr()?;
    let entry = SocketAddr::from(([127, 0, 0, 1], free_port()?));
    let (mut relay, gcs2, companion) = match (path, extra) {
        (PathKind::Direct, _) => (Relay::Direct, None, None),
        (PathKind::Socat, _) => {
            let mut cmd = Command::new("socat");
            cmd.arg("-b65536")
                .arg(format!("UDP4-LISTEN:{},bind=127.0.0.1,reuseaddr", entry.port()))
                .arg(format!("UDP4:{g1}"));
            (spawn_relay(&mut cmd, entry)?, None, None)
        }
        (_, extra) => {
            let gcs2 = udp()?;
            let tcp = free_port()?;
            let mut cmd = Command::new(&a.vouch_exe);
            cmd.args(["mav", "guard", "--endpoint", &format!("vehicle=vehicle:udpin:{entry}")])
                .args(["--endpoint", &format!("gcs1=ground:udpout:{g1}")])
                .args(["--endpoint", &format!("gcs2=ground:udpout:{}", gcs2.local_addr()?)])
                .args(["--endpoint", &format!("companion=ground:tcpin:127.0.0.1:{tcp}")])
                .args(extra.unwrap_or_default());
            let relay = spawn_relay(&mut cmd, entry)?;
            (relay, Some(gcs2), Some(connect(tcp)?))
        }
    };
    let entry = if matches!(relay, Relay::Direct) { g1 } else { entry };
    let rig = Rig { vehicle, entry, gcs1, gcs2, companion };
    let r = measure(path, &mut relay, rig, a, steps);
    stop(relay);
    r
}

/// The paths of the router scenario and the guard's arguments for each (`None` = no guard).
pub(super) fn paths(a: &BenchConfig, socat: bool) -> Vec<(PathKind, Option<Vec<String>>)> {
    let mut paths = vec![(PathKind::Direct, None)];
    if socat {
        paths.push((PathKind::Socat, None));
    }
    paths.push((PathKind::GuardRouterRelayOnly, Some(vec!["--relay-only".into()])));
    paths.push((PathKind::GuardRouter, Some(a.guard_args.clone())));
    paths
}

/// Runs the router scenario's paths; a path that cannot run is listed with its reason.
pub(super) fn run(
    a: &BenchConfig,
    paths: Vec<(PathKind, Option<Vec<String>>)>,
    steps: &mut Steps<'_>,
) -> (Vec<RouterResult>, Vec<Skipped>) {
    let (mut done, mut skipped) = (vec![], vec![]);
    for (path, extra) in paths {
        let before = steps.done;
        match one(path, extra, a, steps) {
            Ok(r) => done.push(r),
            Err(e) => {
                steps.skip(ROUTER_PHASES - (steps.done - before));
                skipped.push(Skipped { scenario: "router", path, reason: e.to_string() });
            }
        }
    }
    (done, skipped)
}
