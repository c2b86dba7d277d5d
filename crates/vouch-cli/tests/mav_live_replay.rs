//! Real recordings replayed live through `vouch mav guard --enforce`: a ground-station socket and
//! a vehicle socket on 127.0.0.1, the guard between them, each recorded frame sent from the side
//! that sent it (vehicle: the systems whose heartbeats describe an autopilot). A side only speaks
//! once everything the other side said before has come through, as the real peers answered what
//! they had received. Every frame must arrive at the other side, byte for byte and in order:
//! whatever the vehicle accepted in the recording, the guard must let through.
//!
//! The recordings (../shared/mavlink) cover the exchanges the guard judges: mission uploads
//! (full, after a clear sent back to back), downloads with reads of home beyond the count,
//! guided-mode items, parameter lists, reads and writes, commands and mode changes. A frame
//! addressed to ids the other side never showed is not routed (the guard routes as
//! mavlink-router does) and is not expected; the test prints how many there were.

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

/// One recorded frame, the side that sent it, and the other side's recorded ids.
struct Sent {
    from_vehicle: bool,
    bytes: Vec<u8>,
    /// (target system, target component), `None` for messages without a target.
    target: Option<(u8, u8)>,
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
        .map(|rec| {
            let v = MessageView::of_frame(&rec.frame, d);
            let field = |f: &str| v.as_ref().and_then(|v| v.get_f64(f)).map(|x| x as u8);
            Sent {
                from_vehicle: vehicles.contains(&rec.frame.sysid),
                bytes: rec.frame.bytes.to_vec(),
                target: field("target_system").map(|s| (s, field("target_component").unwrap_or(0))),
            }
        })
        .collect()
}

/// Whether the guard routes `s` to the other side, by the routing rule it shares with
/// mavlink-router: no target or target system 0, else the target (component 0: its system) must
/// have been seen on the other side. `seen` holds the ids each side has sent so far.
fn routed(s: &Sent, seen: &[HashSet<(u8, u8)>; 2]) -> bool {
    let other = &seen[usize::from(!s.from_vehicle)];
    match s.target {
        None | Some((0, _)) => true,
        Some((sys, 0)) => other.iter().any(|&(x, _)| x == sys),
        Some(t) => other.contains(&t),
    }
}

fn sender(s: &Sent) -> (u8, u8) {
    (
        s.bytes[if s.bytes[0] == 0xfd { 5 } else { 3 }],
        s.bytes[if s.bytes[0] == 0xfd { 6 } else { 4 }],
    )
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
    // A UDP server learns a peer from its first datagram: each side speaks once (its first
    // recorded frame) before the replay proper, which starts once both have spoken in the
    // recording; what came before that had nowhere to go.
    let first = |v: bool| sent.iter().position(|s| s.from_vehicle == v);
    let (Some(fv), Some(fg)) = (first(true), first(false)) else {
        // A recording of one direction has no exchange to replay (the guard could not deliver
        // it: nobody spoke on the other side).
        eprintln!("{}: one side only, not replayed", file.display());
        return (0, 0, Vec::new());
    };
    vehicle.sock.send_to(&sent[fv].bytes, to_vehicle).expect("send");
    gcs.sock.send_to(&sent[fg].bytes, to_gcs).expect("send");
    std::thread::sleep(Duration::from_millis(300));
    vehicle.got.lock().expect("lock").clear();
    gcs.got.lock().expect("lock").clear();
    let mut seen: [HashSet<(u8, u8)>; 2] = [HashSet::new(), HashSet::new()];
    seen[1].insert(sender(&sent[fv]));
    seen[0].insert(sender(&sent[fg]));
    let sent = &sent[fv.max(fg) + 1..];
    let mut expected: [Vec<Vec<u8>>; 2] = [Vec::new(), Vec::new()];
    let mut unrouted = 0usize;
    let mut problems = Vec::new();
    let (mut from_vehicle, mut from_gcs) = (0usize, 0usize);
    let mut last_side = None;
    let mut run = 0usize;
    for s in sent {
        run += 1;
        // Also every few frames within a run: loopback UDP drops what overflows a receive
        // buffer, and a loss here would be the test's, not the guard's.
        if last_side != Some(s.from_vehicle) || run.is_multiple_of(16) {
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
        seen[usize::from(s.from_vehicle)].insert(sender(s));
        if routed(s, &seen) {
            expected[usize::from(s.from_vehicle)].push(s.bytes.clone());
        } else {
            unrouted += 1;
        }
        let r = if s.from_vehicle {
            from_vehicle = expected[1].len();
            vehicle.sock.send_to(&s.bytes, to_vehicle)
        } else {
            from_gcs = expected[0].len();
            gcs.sock.send_to(&s.bytes, to_gcs)
        };
        r.expect("send");
    }
    if unrouted > 0 {
        eprintln!(
            "{}: {unrouted} frames addressed to ids never seen on the other side",
            file.display()
        );
    }
    wait_for(&vehicle, from_gcs, Duration::from_secs(3));
    wait_for(&gcs, from_vehicle, Duration::from_secs(3));
    stop.store(true, Ordering::Relaxed);
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
    let [to_v, to_g] = expected;
    check("GCS → vehicle", &vehicle, to_v, &mut problems);
    check("vehicle → GCS", &gcs, to_g, &mut problems);
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
    "tlogs_wild2/arducopter_sitl_mavproxy_script_2020_csun_guided.tlog",
    "tlogs_wild2/arducopter_sitl_mavproxy_missionplanner_2023_dronemission.tlog",
];

#[test]
fn recordings_replayed_through_the_enforcing_guard_arrive_whole() {
    let Some(dir) = vouch_testkit::shared("mavlink", "tlogs_wild2/README.md") else { return };
    let Ok(d) = Dialect::default_dialect() else {
        let _: Option<()> =
            vouch_testkit::missing(vouch_testkit::Need::Shared, "no default dialect");
        return;
    };
    // `VOUCH_MAV_REPLAY=all` replays every recording of both sets (minutes, not seconds).
    let all = std::env::var("VOUCH_MAV_REPLAY").is_ok_and(|v| v == "all");
    let mut list: Vec<String> = RECORDINGS.iter().map(|s| s.to_string()).collect();
    if all {
        list.clear();
        for set in ["tlogs", "tlogs_wild2"] {
            let mut names: Vec<String> = std::fs::read_dir(dir.join(set))
                .expect("recordings")
                .filter_map(|e| e.ok()?.file_name().into_string().ok())
                .filter(|n| n.ends_with(".tlog"))
                .map(|n| format!("{set}/{n}"))
                .collect();
            names.sort();
            list.extend(names);
        }
    }
    let mut problems = Vec::new();
    for rel in &list {
        let path: PathBuf = dir.join(rel);
        let t = Instant::now();
        let (g, v, p) = replay(&path, &d);
        eprintln!("{rel}: {g} GCS + {v} vehicle frames in {:.1} s", t.elapsed().as_secs_f64());
        problems.extend(p);
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
