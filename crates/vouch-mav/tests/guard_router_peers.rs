//! The router with real peers from PyPI at once, on loopback: MAVProxy 1.8.75 and a pymavlink
//! ground station on two ground endpoints, a pymavlink companion on a third, two pymavlink
//! vehicles with system ids 1 and 2 (one over UDP, one over TCP). Who receives what: the mission
//! upload to vehicle 1 never reaches vehicle 2 or the companion, both ground stations and the
//! companion hear both vehicles, a parachute release from one ground station is blocked and
//! answered while MAVProxy's upload goes on, and a TCP vehicle that restarts is reconnected.
//!
//! Needs `VOUCH_PYTHON` (set by scripts/test.sh from `.venv`); without it every test prints why
//! and returns, or fails under `VOUCH_REQUIRE_PEERS=1`.

mod guard_support;

use std::io::{BufRead, BufReader};
use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use guard_support::{KillOnDrop, read_summary, standard_inspector, tempdir, write_mission};
use serde_json::Value;
use vouch_mav::Side;
use vouch_mav::dialect::Dialect;
use vouch_mav::guard::{EndpointConfig, GuardConfig, RoutingOptions, start};

fn python() -> Option<PathBuf> {
    vouch_testkit::python_with(&["pymavlink", "MAVProxy"]).map(PathBuf::from)
}

fn script(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop").join(name)
}

fn free_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

fn spawn(py: &Path, args: &[String]) -> KillOnDrop {
    let child: Child = Command::new(py)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("peer starts");
    KillOnDrop(child)
}

fn vehicle(py: &Path, url: String, sysid: u8, dir: &Path, tag: &str) -> (KillOnDrop, PathBuf) {
    let summary = dir.join(format!("{tag}.json"));
    let args = [
        script("pymavlink_vehicle.py").display().to_string(),
        "--url".into(),
        url,
        "--sysid".into(),
        sysid.to_string(),
        "--duration".into(),
        "40".into(),
        "--summary".into(),
        summary.display().to_string(),
        "--stop-file".into(),
        dir.join("stop").display().to_string(),
    ];
    (spawn(py, &args), summary)
}

fn peer(py: &Path, url: String, extra: &[&str], dir: &Path, tag: &str) -> (KillOnDrop, PathBuf) {
    let summary = dir.join(format!("{tag}.json"));
    let mut args = vec![
        script("router_peer.py").display().to_string(),
        "--url".into(),
        url,
        "--duration".into(),
        "40".into(),
        "--summary".into(),
        summary.display().to_string(),
        "--stop-file".into(),
        dir.join("stop").display().to_string(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    (spawn(py, &args), summary)
}

fn count(summary: &Value, src: u8, ty: &str) -> u64 {
    summary["types"][src.to_string()][ty].as_u64().unwrap_or(0)
}

fn types(summary: &Value, ty: &str) -> u64 {
    summary["types"][ty].as_u64().unwrap_or(0)
}

fn dialect() -> Option<std::sync::Arc<Dialect>> {
    Dialect::default_dialect().ok().map(std::sync::Arc::new)
}

#[test]
fn two_ground_stations_a_companion_and_two_vehicles_at_once() {
    let Some(py) = python() else { return };
    let Some(inspector) = standard_inspector() else { return };
    let dir = tempdir("five");
    let (p1, p2, pq) = (free_port(), free_port(), free_port());
    let (_v1, v1_sum) = vehicle(&py, format!("udpin:127.0.0.1:{p1}"), 1, &dir, "v1");
    let (_v2, v2_sum) = vehicle(&py, format!("tcpin:127.0.0.1:{p2}"), 2, &dir, "v2");
    // the pymavlink ground station listens, as QGroundControl does on 14550: the guard sends first
    let (_gcs, gcs_sum) = peer(
        &py,
        format!("udpin:127.0.0.1:{pq}"),
        &["--wait-for", "1,2", "--parachute-to", "2", "--params-from", "2"],
        &dir,
        "gcs",
    );
    let ep = |n: &str, side, url: String| EndpointConfig::new(n, side, url.parse().unwrap());
    let mut v2 = ep("v2", Side::Vehicle, format!("tcpout:127.0.0.1:{p2}"));
    v2.retry = Some(Duration::from_millis(500));
    let cfg = GuardConfig {
        enforce: true,
        routing: RoutingOptions { dialect: dialect(), ..RoutingOptions::default() },
        ..GuardConfig::with_endpoints(vec![
            ep("v1", Side::Vehicle, format!("udpout:127.0.0.1:{p1}")),
            v2,
            ep("mavproxy", Side::Gcs, "udpin:127.0.0.1:0".into()),
            ep("qgc", Side::Gcs, format!("udpout:127.0.0.1:{pq}")),
            ep("companion", Side::Gcs, "tcpin:127.0.0.1:0".into()),
        ])
    };
    let guard = start(cfg, inspector).expect("guard starts");
    let comp_port = guard.local_addr("companion").unwrap().port();
    let (_comp, comp_sum) = peer(
        &py,
        format!("tcp:127.0.0.1:{comp_port}"),
        &["--sysid", "1", "--compid", "191", "--onboard"],
        &dir,
        "companion",
    );
    let mission = write_mission(&dir);
    // MAVProxy targets the first system/component whose heartbeat it hears; a companion (1/191)
    // that speaks before the autopilot would take the upload. Start it once vehicle 1 talks.
    let heard = Instant::now() + Duration::from_secs(10);
    while guard.counters().endpoint("v1").is_some_and(|e| e.frames_in == 0)
        && Instant::now() < heard
    {
        std::thread::sleep(Duration::from_millis(20));
    }
    let mp_port = guard.local_addr("mavproxy").unwrap().port();
    let mut mp = Command::new(&py);
    mp.arg(py.parent().unwrap().join("mavproxy.py"))
        .arg(format!("--master=udpout:127.0.0.1:{mp_port}"))
        .args(["--daemon", "--non-interactive", "--target-system=1", "--target-component=1"])
        .arg(format!("--state-basedir={}", dir.join("mps").display()))
        .arg(format!("--cmd=wp load {}", mission.display()))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    let mut mp = KillOnDrop(mp.spawn().expect("MAVProxy starts"));
    let text = mavproxy_output(&mut mp.0, Duration::from_secs(40));
    drop(mp);
    std::thread::sleep(Duration::from_millis(500));
    std::fs::write(dir.join("stop"), b"").unwrap();
    let (v1, v2, gcs, comp) = (
        read_summary(&v1_sum),
        read_summary(&v2_sum),
        read_summary(&gcs_sum),
        read_summary(&comp_sum),
    );
    let c = guard.stop();
    let _ = std::fs::remove_dir_all(&dir);

    // MAVProxy's upload to vehicle 1 went through, and only to vehicle 1
    assert!(text.contains("Sent all 100 waypoints"), "MAVProxy output:\n{text}");
    assert_eq!(v1["uploads"][0]["received"], 100, "{v1}");
    assert_eq!(types(&v2, "MISSION_ITEM_INT") + types(&v2, "MISSION_COUNT"), 0, "{v2}");
    for (name, s) in [("gcs", &gcs), ("companion", &comp)] {
        for src in ["1", "2", "255"] {
            let t = &s["types"][src];
            assert_eq!(t["MISSION_ITEM_INT"].as_u64().unwrap_or(0), 0, "{name} from {src}: {s}");
            assert_eq!(t["MISSION_REQUEST_INT"].as_u64().unwrap_or(0), 0, "{name} from {src}: {s}");
        }
        // both vehicles' telemetry reaches every ground endpoint
        assert!(count(s, 1, "HEARTBEAT") > 0 && count(s, 2, "HEARTBEAT") > 0, "{name}: {s}");
    }
    // the parachute release from the pymavlink GCS was blocked and answered; its parameter
    // request to vehicle 2 was answered
    assert_eq!(v2["parachute_commands"], 0, "{v2}");
    assert!(gcs["command_ack"].as_u64().is_some_and(|r| r != 0), "{gcs}");
    assert!(gcs["param_values"]["2"].as_u64().is_some_and(|n| n >= 3), "{gcs}");
    assert_eq!(v1["parachute_commands"], 0, "{v1}");
    assert!(c.dropped_violations >= 1, "{c:?}");
    assert_eq!(c.endpoint("v2").unwrap().connects, 1, "{c:?}");
}

/// MAVProxy's standard output until 2 s after its MISSION_ACK line (or `limit`).
fn mavproxy_output(child: &mut Child, limit: Duration) -> String {
    let (tx, rx) = mpsc::channel();
    let out = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let mut text = String::new();
    let end = Instant::now() + limit;
    let mut settle: Option<Instant> = None;
    while Instant::now() < end && settle.is_none_or(|s| s.elapsed() < Duration::from_secs(2)) {
        if let Ok(line) = rx.recv_timeout(Duration::from_millis(100)) {
            text += &line;
            text.push('\n');
            if line.contains("MISSION_ACK") && settle.is_none() {
                settle = Some(Instant::now());
            }
        }
    }
    text
}

#[test]
fn a_tcp_vehicle_that_restarts_is_reconnected() {
    let Some(py) = python() else { return };
    let dir = tempdir("restart");
    let (p2, pq) = (free_port(), free_port());
    let (v2, _) = vehicle(&py, format!("tcpin:127.0.0.1:{p2}"), 2, &dir, "v2-first");
    let (_gcs, gcs_sum) = peer(&py, format!("udpin:127.0.0.1:{pq}"), &[], &dir, "gcs");
    let mut v2ep =
        EndpointConfig::new("v2", Side::Vehicle, format!("tcpout:127.0.0.1:{p2}").parse().unwrap());
    v2ep.retry = Some(Duration::from_millis(300));
    let gcs =
        EndpointConfig::new("qgc", Side::Gcs, format!("udpout:127.0.0.1:{pq}").parse().unwrap());
    let cfg = GuardConfig {
        routing: RoutingOptions { dialect: dialect(), ..RoutingOptions::default() },
        ..GuardConfig::with_endpoints(vec![v2ep, gcs])
    };
    let guard = start(cfg, Box::new(vouch_mav::guard::PassThrough)).expect("guard starts");
    // Python peers take a while to start on a loaded machine: wait for what each step needs.
    let until = |what: &str, ok: &dyn Fn(&vouch_mav::guard::CounterSnapshot) -> bool| {
        let end = Instant::now() + Duration::from_secs(20);
        while !ok(&guard.counters()) {
            assert!(Instant::now() < end, "{what}: {:?}", guard.counters());
            std::thread::sleep(Duration::from_millis(50));
        }
    };
    let v2_in = |c: &vouch_mav::guard::CounterSnapshot| c.endpoint("v2").unwrap().frames_in;
    until("vehicle heard", &|c| v2_in(c) >= 10 && c.endpoint("qgc").unwrap().frames_in >= 2);
    drop(v2); // the vehicle process dies
    let killed = Instant::now();
    until("disconnect noticed", &|c| c.endpoint("v2").unwrap().connections == 0);
    std::thread::sleep(Duration::from_millis(1000));
    let (_v2_again, _) = vehicle(&py, format!("tcpin:127.0.0.1:{p2}"), 2, &dir, "v2-second");
    let restarted = killed.elapsed().as_secs_f64();
    let before = v2_in(&guard.counters());
    until("vehicle heard again", &|c| v2_in(c) >= before + 10);
    std::thread::sleep(Duration::from_millis(500));
    let c = guard.counters();
    std::fs::write(dir.join("stop"), b"").unwrap();
    let gcs = read_summary(&gcs_sum);
    guard.stop();
    let _ = std::fs::remove_dir_all(&dir);
    let v2 = c.endpoint("v2").unwrap();
    assert!(v2.connects >= 2 && v2.connections == 1, "{c:?}");
    // heartbeats of system 2 before the kill and again after the restart
    let times: Vec<f64> = gcs["heartbeats"]["2"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    let (gap_at, gap) = times
        .windows(2)
        .enumerate()
        .map(|(i, w)| (i, w[1] - w[0]))
        .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best });
    assert!(gap >= 1.0, "silent while the vehicle was down ({restarted:.1} s): {times:?}");
    assert!(times.len() - (gap_at + 1) >= 5, "heard again after the restart: {times:?}");
}
