//! Real recordings replayed live through `vouch mav guard --enforce`: a ground-station socket and
//! a vehicle socket on 127.0.0.1, the guard between them, each recorded frame sent from the side
//! that sent it (vehicle: the systems whose heartbeats describe an autopilot). A side only speaks
//! once everything the other side said before has come through, as the real peers answered what
//! they had received. Every frame must arrive at the other side, byte for byte and in order:
//! whatever the vehicle accepted in the recording, the guard must let through.
//!
//! The recordings (../shared/mavlink) cover the exchanges the guard judges: mission uploads
//! (full, after a clear sent back to back), downloads with reads of home beyond the count,
//! guided-mode items, parameter lists, reads and writes, commands and mode changes.

mod common;

use std::collections::HashSet;
use std::net::{SocketAddr, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use vouch_mav::codec::split::split_datagram;
use vouch_mav::codec::{MessageView, Piece, TlogReader};
use vouch_mav::dialect::Dialect;

/// One recorded frame and the side that sent it.
struct Sent {
    from_vehicle: bool,
    bytes: Vec<u8>,
}

/// The frames of a recording the vehicle or the ground station could have sent: known messages
/// (the guard refuses unknown ids in enforce mode), sides from the heartbeats.
fn frames(data: &[u8], d: &Dialect) -> Vec<Sent> {
    let mut vehicles = HashSet::new();
    for rec in TlogReader::new(data, d) {
        if let Some(v) = MessageView::of_frame(&rec.frame, d).filter(|v| v.name() == "HEARTBEAT") {
            let ty = v.get_f64("type").unwrap_or(0.0);
            let ap = v.get_f64("autopilot").unwrap_or(8.0);
            if ty != 6.0 && ap != 8.0 {
                vehicles.insert(rec.frame.sysid);
            }
        }
    }
    TlogReader::new(data, d)
        .filter(|rec| MessageView::of_frame(&rec.frame, d).is_some())
        .map(|rec| Sent {
            from_vehicle: vehicles.contains(&rec.frame.sysid),
            bytes: rec.frame.bytes.to_vec(),
        })
        .collect()
}

/// A socket on one side and the frames that came out of the guard to it, split from datagrams.
struct Peer {
    sock: UdpSocket,
    got: Arc<Mutex<Vec<Vec<u8>>>>,
}

impl Peer {
    fn new(stop: &Arc<AtomicBool>) -> Peer {
        let sock = UdpSocket::bind("127.0.0.1:0").expect("bind");
        sock.set_read_timeout(Some(Duration::from_millis(50))).expect("timeout");
        let got = Arc::new(Mutex::new(Vec::new()));
        let (rx, sink, stop) =
            (sock.try_clone().expect("clone"), Arc::clone(&got), Arc::clone(stop));
        std::thread::spawn(move || {
            let mut buf = [0u8; 65536];
            while !stop.load(Ordering::Relaxed) {
                let Ok(n) = rx.recv(&mut buf) else { continue };
                let mut g = sink.lock().expect("lock");
                split_datagram(&buf[..n], |p| {
                    if let Piece::Frame(a, b) = p {
                        g.push(buf[a..b].to_vec());
                    }
                });
            }
        });
        Peer { sock, got }
    }

    fn received(&self) -> usize {
        self.got.lock().expect("lock").len()
    }
}

fn free_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0").and_then(|s| s.local_addr()).map(|a| a.port()).expect("port")
}

struct Guard(Child);

impl Drop for Guard {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Waits until `peer` holds `n` frames (or the time is up).
fn wait_for(peer: &Peer, n: usize, limit: Duration) -> bool {
    let end = Instant::now() + limit;
    while peer.received() < n {
        if Instant::now() > end {
            return false;
        }
        std::thread::sleep(Duration::from_micros(200));
    }
    true
}

/// Replays `file` through a fresh guard; returns (frames sent per side, problems).
fn replay(file: &Path, d: &Dialect) -> (usize, usize, Vec<String>) {
    let data = std::fs::read(file).expect("read recording");
    let sent = frames(&data, d);
    let (gcs_port, vehicle_port) = (free_port(), free_port());
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mav_live_replay");
    std::fs::create_dir_all(&dir).expect("dir");
    let log = std::fs::File::create(dir.join("guard.err")).expect("log");
    let child = Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["mav", "guard", "--enforce"])
        .args(["--gcs", &format!("udpin:127.0.0.1:{gcs_port}")])
        .args(["--vehicle", &format!("udpin:127.0.0.1:{vehicle_port}")])
        .env("XDG_STATE_HOME", dir.join("state"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .expect("the vouch binary starts");
    let _guard = Guard(child);
    for port in [gcs_port, vehicle_port] {
        let end = Instant::now() + Duration::from_secs(10);
        while UdpSocket::bind(("127.0.0.1", port)).is_ok() {
            assert!(Instant::now() < end, "the guard did not bind {port}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    let stop = Arc::new(AtomicBool::new(false));
    let (gcs, vehicle) = (Peer::new(&stop), Peer::new(&stop));
    let to_gcs: SocketAddr = ([127, 0, 0, 1], gcs_port).into();
    let to_vehicle: SocketAddr = ([127, 0, 0, 1], vehicle_port).into();
    let mut problems = Vec::new();
    let (mut from_vehicle, mut from_gcs) = (0usize, 0usize);
    let mut last_side = None;
    for s in &sent {
        if last_side != Some(s.from_vehicle) {
            // The other side answers only what it received: wait until it all came through.
            let ok = wait_for(&vehicle, from_gcs, Duration::from_secs(2))
                && wait_for(&gcs, from_vehicle, Duration::from_secs(2));
            if !ok {
                problems.push(format!(
                    "{}: stalled after {from_gcs} GCS and {from_vehicle} vehicle frames",
                    file.display()
                ));
                break;
            }
            last_side = Some(s.from_vehicle);
        }
        let r = if s.from_vehicle {
            from_vehicle += 1;
            vehicle.sock.send_to(&s.bytes, to_vehicle)
        } else {
            from_gcs += 1;
            gcs.sock.send_to(&s.bytes, to_gcs)
        };
        r.expect("send");
    }
    wait_for(&vehicle, from_gcs, Duration::from_secs(3));
    wait_for(&gcs, from_vehicle, Duration::from_secs(3));
    stop.store(true, Ordering::Relaxed);
    let want = |v: bool| sent.iter().filter(move |s| s.from_vehicle == v).map(|s| s.bytes.clone());
    let check = |what: &str, peer: &Peer, expected: Vec<Vec<u8>>, problems: &mut Vec<String>| {
        let got = peer.got.lock().expect("lock");
        if *got != expected {
            let first = got.iter().zip(&expected).position(|(a, b)| a != b);
            problems.push(format!(
                "{}: {what}: {} of {} frames arrived, first difference at {first:?}",
                file.display(),
                got.len(),
                expected.len()
            ));
        }
    };
    check("GCS → vehicle", &vehicle, want(false).collect(), &mut problems);
    check("vehicle → GCS", &gcs, want(true).collect(), &mut problems);
    if !problems.is_empty() {
        let log = std::fs::read_to_string(dir.join("guard.err")).unwrap_or_default();
        problems.push(format!("guard log: {}", log.chars().take(3000).collect::<String>()));
    }
    (from_gcs, from_vehicle, problems)
}

const RECORDINGS: &[&str] = &[
    "tlogs/upload100_mavproxy_to_pymavlink_vehicle.tlog",
    "tlogs/missionplanner_arducopter_sitl_2024.tlog",
    "tlogs_wild2/arducopter_sitl_mavproxy_missionplanner_2021_extractor.tlog",
    "tlogs_wild2/arduplane_sitl_mavproxy_2017_winddrone.tlog",
    "tlogs_wild2/arducopter_sitl_mavproxy_missionplanner_2021_beyondterra.tlog",
    "tlogs_wild2/arducopter_sitl_mavproxy_script_2020_pvardupilot.tlog",
];

#[test]
fn recordings_replayed_through_the_enforcing_guard_arrive_whole() {
    let Some(dir) = vouch_testkit::shared("mavlink", "tlogs_wild2/README.md") else { return };
    let Ok(d) = Dialect::default_dialect() else {
        let _: Option<()> =
            vouch_testkit::missing(vouch_testkit::Need::Shared, "no default dialect");
        return;
    };
    let mut problems = Vec::new();
    for rel in RECORDINGS {
        let path: PathBuf = dir.join(rel);
        let t = Instant::now();
        let (g, v, p) = replay(&path, &d);
        eprintln!("{rel}: {g} GCS + {v} vehicle frames in {:.1} s", t.elapsed().as_secs_f64());
        problems.extend(p);
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
