//! The traffic of the benchmark: the messages of a 100-waypoint upload and telemetry frames
//! (MAVLink 2, CRC_EXTRA from common.xml), and the loops that time them through a path.

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crate::codec::encode::frame_v2_truncated;
use crate::codec::split::{Piece, split_datagram};
use crate::guard::sys::process;

/// How long a receive waits before a message counts as lost.
pub(super) const WAIT: Duration = Duration::from_millis(500);

fn frame(msgid: u32, crc_extra: u8, payload: &[u8], sysid: u8, compid: u8, seq: u8) -> Vec<u8> {
    frame_v2_truncated(msgid, crc_extra, payload, seq, sysid, compid)
}

struct Seqs(u8);
impl Seqs {
    fn next(&mut self) -> u8 {
        self.0 = self.0.wrapping_add(1);
        self.0
    }
}

fn mission_count(n: u16, s: u8) -> Vec<u8> {
    let c = n.to_le_bytes();
    frame(44, 221, &[c[0], c[1], 1, 1, 0], 255, 190, s)
}
fn mission_request_int(seq: u16, s: u8) -> Vec<u8> {
    let q = seq.to_le_bytes();
    frame(51, 196, &[q[0], q[1], 255, 190, 0], 1, 1, s)
}
fn mission_item_int(seq: u16, s: u8) -> Vec<u8> {
    let mut p = vec![0u8; 38];
    p[16..20].copy_from_slice(&(-353_600_000i32 + i32::from(seq) * 1000).to_le_bytes());
    p[20..24].copy_from_slice(&(1_491_600_000i32 + i32::from(seq) * 1000).to_le_bytes());
    p[24..28].copy_from_slice(&(100.0f32 + f32::from(seq)).to_le_bytes());
    p[28..30].copy_from_slice(&seq.to_le_bytes());
    p[30..32].copy_from_slice(&16u16.to_le_bytes()); // MAV_CMD_NAV_WAYPOINT
    p[32] = 1;
    p[33] = 1;
    p[34] = if seq == 0 { 0 } else { 3 }; // frame
    p[36] = 1; // autocontinue
    frame(73, 38, &p, 255, 190, s)
}
fn mission_ack(s: u8) -> Vec<u8> {
    frame(47, 153, &[255, 190, 0, 0], 1, 1, s)
}
/// ATTITUDE with the sample index in `time_boot_ms`, so the receiver can match send instants.
pub(super) fn attitude(index: u32, s: u8) -> Vec<u8> {
    let mut p = vec![0u8; 28];
    p[..4].copy_from_slice(&index.to_le_bytes());
    p[4..8].copy_from_slice(&0.1f32.to_le_bytes());
    frame(30, 39, &p, 1, 1, s)
}
/// HEARTBEAT of the autopilot 1/1 (quadrotor, ArduPilot).
pub(super) fn heartbeat_vehicle(s: u8) -> Vec<u8> {
    frame(0, 50, &[0, 0, 0, 0, 2, 3, 0, 4, 3], 1, 1, s)
}
fn heartbeat_gcs(s: u8) -> Vec<u8> {
    frame(0, 50, &[0, 0, 0, 0, 6, 8, 0, 0, 3], 255, 190, s)
}

fn attitude_index(f: &[u8]) -> Option<u32> {
    (f.len() >= 14 && f[0] == 0xFD && f[7] == 30).then(|| {
        let mut b = [0u8; 4];
        let n = (f[1] as usize).min(4);
        b[..n].copy_from_slice(&f[10..10 + n]);
        u32::from_le_bytes(b)
    })
}

/// Receives until a datagram arrives or WAIT passes; returns its length.
fn recv(s: &UdpSocket, buf: &mut [u8]) -> Option<(usize, SocketAddr)> {
    s.recv_from(buf).ok()
}

pub(super) struct Rig {
    gcs: UdpSocket,
    vehicle: UdpSocket,
    entry: SocketAddr,
    back: SocketAddr,
}

/// Makes the vehicle learn where the path's far end is (the relay's sending socket), and the
/// path learn both ends: each side's heartbeat reaches the other (a router sends frames that
/// target a system only where that system has been heard).
pub(super) fn handshake(gcs: UdpSocket, vehicle: UdpSocket, entry: SocketAddr) -> io::Result<Rig> {
    let mut buf = [0u8; 512];
    let mut seqs = Seqs(0);
    let end = Instant::now() + Duration::from_secs(5);
    vehicle.set_read_timeout(Some(Duration::from_millis(50)))?;
    gcs.set_read_timeout(Some(Duration::from_millis(50)))?;
    let timed_out =
        || io::Error::new(io::ErrorKind::TimedOut, "path did not deliver a heartbeat within 5 s");
    let back = loop {
        if Instant::now() > end {
            return Err(timed_out());
        }
        gcs.send_to(&heartbeat_gcs(seqs.next()), entry)?;
        if let Some((_, from)) = recv(&vehicle, &mut buf) {
            break from;
        }
    };
    loop {
        if Instant::now() > end {
            return Err(timed_out());
        }
        vehicle.send_to(&heartbeat_vehicle(seqs.next()), back)?;
        if recv(&gcs, &mut buf).is_some() {
            break;
        }
    }
    // drain what else is in flight
    while recv(&vehicle, &mut buf).is_some() || recv(&gcs, &mut buf).is_some() {}
    vehicle.set_read_timeout(Some(WAIT))?;
    gcs.set_read_timeout(Some(WAIT))?;
    Ok(Rig { gcs, vehicle, entry, back })
}

pub(super) fn upload_latencies(rig: &Rig, uploads: usize, out: &mut Vec<f64>) -> io::Result<()> {
    let mut buf = [0u8; 512];
    let (mut gs, mut vs) = (Seqs(0), Seqs(0));
    let mut hop =
        |from: &UdpSocket, to_addr: SocketAddr, to: &UdpSocket, frame: &[u8]| -> io::Result<()> {
            let t = Instant::now();
            from.send_to(frame, to_addr)?;
            recv(to, &mut buf)
                .ok_or_else(|| io::Error::new(io::ErrorKind::TimedOut, "message lost in upload"))?;
            out.push(t.elapsed().as_secs_f64() * 1e6);
            Ok(())
        };
    for _ in 0..uploads {
        hop(&rig.gcs, rig.entry, &rig.vehicle, &mission_count(100, gs.next()))?;
        for seq in 0..100u16 {
            hop(&rig.vehicle, rig.back, &rig.gcs, &mission_request_int(seq, vs.next()))?;
            hop(&rig.gcs, rig.entry, &rig.vehicle, &mission_item_int(seq, gs.next()))?;
        }
        hop(&rig.vehicle, rig.back, &rig.gcs, &mission_ack(vs.next()))?;
    }
    Ok(())
}

pub(super) fn ping_latencies(rig: &Rig, pings: usize, out: &mut Vec<f64>) -> io::Result<()> {
    let mut buf = [0u8; 512];
    let mut vs = Seqs(0);
    for i in 0..pings {
        let t = Instant::now();
        rig.vehicle.send_to(&attitude(i as u32, vs.next()), rig.back)?;
        if recv(&rig.gcs, &mut buf).is_some() {
            out.push(t.elapsed().as_secs_f64() * 1e6);
        }
    }
    Ok(())
}

/// Sends `count` ATTITUDE frames at `rate`/s (or as fast as possible with rate 0) from the
/// vehicle; a receiver thread stamps arrivals. Returns (delivered, latencies µs, elapsed s).
pub(super) fn stream(
    rig: &Rig,
    count: u32,
    rate: u32,
    pin: bool,
) -> io::Result<(u64, Vec<f64>, f64)> {
    let gcs = rig.gcs.try_clone()?;
    gcs.set_read_timeout(Some(Duration::from_millis(200)))?;
    let base = Instant::now();
    let sent_ns: Arc<Vec<AtomicU64>> = Arc::new((0..count).map(|_| AtomicU64::new(0)).collect());
    let done = Arc::new(AtomicBool::new(false));
    let (s2, d2) = (sent_ns.clone(), done.clone());
    let rx = std::thread::spawn(move || {
        if pin {
            process::pin_current_thread(1);
        }
        let mut lat = Vec::with_capacity(count as usize);
        let mut got = 0u64;
        let mut last = base;
        let mut buf = [0u8; 4096];
        loop {
            match gcs.recv_from(&mut buf) {
                Ok((n, _)) => {
                    let now = base.elapsed().as_nanos() as u64;
                    last = Instant::now();
                    // a router may put several frames of one batch into one datagram
                    let d = &buf[..n];
                    split_datagram(d, |p| {
                        let Piece::Frame(a, b) = p else { return };
                        got += 1;
                        if let Some(t) = attitude_index(&d[a..b]).and_then(|i| s2.get(i as usize)) {
                            let t = t.load(Ordering::Relaxed);
                            if t > 0 && now >= t {
                                lat.push((now - t) as f64 / 1000.0);
                            }
                        }
                    });
                }
                Err(_) if d2.load(Ordering::Relaxed) => break,
                Err(_) => {}
            }
        }
        (got, lat, last)
    });
    if pin {
        process::pin_current_thread(1);
    }
    let frames: Vec<Vec<u8>> = (0..count).map(|i| attitude(i, i as u8)).collect();
    let start = Instant::now();
    let period_ns = if rate == 0 { 0 } else { 1_000_000_000u64 / u64::from(rate) };
    for (i, f) in frames.iter().enumerate() {
        if period_ns > 0 {
            // burst pacing: 10 frames at a time, waiting (not spinning) between bursts
            let due = start + Duration::from_nanos(period_ns * i as u64);
            if i % 10 == 0 {
                while Instant::now() < due {
                    std::thread::yield_now();
                }
            }
        }
        sent_ns[i].store(base.elapsed().as_nanos() as u64, Ordering::Relaxed);
        let _ = rig.vehicle.send_to(f, rig.back);
    }
    std::thread::sleep(Duration::from_millis(300));
    done.store(true, Ordering::Relaxed);
    let (got, lat, last) = rx.join().map_err(|_| io::Error::other("receiver thread panicked"))?;
    let elapsed = last.duration_since(start).as_secs_f64().max(1e-9);
    Ok((got, lat, elapsed))
}
