//! Interop with real peers from PyPI, through the guard on loopback: MAVProxy 1.8.75 (headless
//! GCS) uploads a 100-waypoint mission to a pymavlink 2.4.50 vehicle and to a MAVSDK 4.1
//! MissionRawServer vehicle; a vehicle that ACKs after 60 of 100 items; a DO_PARACHUTE command
//! from a pymavlink GCS while the vehicle is disarmed.
//!
//! Needs `VOUCH_PYTHON` (set by scripts/test.sh from `.venv`, made by scripts/install-peers.sh);
//! without it every test prints why and returns, or fails under `VOUCH_REQUIRE_PEERS=1`.

mod guard_support;

use std::io::{BufRead, BufReader};
use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use guard_support::{read_summary, standard_inspector, tempdir, write_mission};
use serde_json::Value;
use vouch_mav::guard::{CounterSnapshot, GuardConfig, RunningGuard, SigningConfig, start};
use vouch_mav::signing::SigningKey;

/// The peer venv's interpreter with pymavlink, MAVProxy and MAVSDK (a skip, or a failure under
/// `VOUCH_REQUIRE_PEERS=1`, without them).
fn python() -> Option<PathBuf> {
    vouch_testkit::python_with(&["pymavlink", "MAVProxy", "mavsdk"]).map(PathBuf::from)
}

fn script(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop").join(name)
}

/// Kills the peer process (only the one this test started) when the test ends, pass or fail.
struct Peer(Child);
impl Drop for Peer {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

enum Vehicle {
    Pymavlink { ack_after: Option<u32> },
    Mavsdk,
}

struct Outcome {
    mavproxy: String,
    vehicle: Value,
    counters: CounterSnapshot,
    log: String,
}

/// Runs one MAVProxy `wp load` of 100 items through a guard to the given vehicle.
/// A guard with the standard protocols between a GCS on an ephemeral loopback port and the
/// vehicle at `vport`, alerting the GCS.
fn loopback_guard(
    vport: u16,
    enforce: bool,
    log_path: Option<PathBuf>,
    signing: Option<SigningConfig>,
) -> RunningGuard {
    let cfg = GuardConfig {
        enforce,
        alert_gcs: true,
        log_path,
        signing,
        ..GuardConfig::new(
            "udpin:127.0.0.1:0".parse().unwrap(),
            format!("udpout:127.0.0.1:{vport}").parse().unwrap(),
        )
    };
    let inspector = standard_inspector().expect("standard protocols");
    start(cfg, inspector).expect("guard starts")
}

fn upload_through_guard(py: &Path, tag: &str, vehicle: Vehicle, enforce: bool) -> Outcome {
    upload(py, tag, vehicle, Some(enforce), None)
}

/// MAVLink 2 signing: the guard requires `guard_pass`; MAVProxy signs with `mavproxy_pass`
/// (`signing setup`, key = SHA-256 of the passphrase) or not at all.
struct Signing {
    guard_pass: &'static str,
    mavproxy_pass: Option<&'static str>,
    /// How long to let MAVProxy try when the upload is expected to fail.
    give_up_after: Duration,
}

/// `guard`: None = MAVProxy talks to the vehicle directly (baseline of the peers themselves).
fn upload(
    py: &Path,
    tag: &str,
    vehicle: Vehicle,
    guard: Option<bool>,
    signing: Option<Signing>,
) -> Outcome {
    let dir = tempdir(tag);
    let mission = write_mission(&dir);
    let vport = free_port();
    let summary = dir.join("vehicle.json");
    let mut cmd = Command::new(py);
    match vehicle {
        Vehicle::Pymavlink { ack_after } => {
            cmd.arg(script("pymavlink_vehicle.py"))
                .arg("--url")
                .arg(format!("udpin:127.0.0.1:{vport}"));
            if let Some(k) = ack_after {
                cmd.arg("--ack-after").arg(k.to_string());
            }
        }
        Vehicle::Mavsdk => {
            cmd.arg(script("mavsdk_vehicle.py"))
                .arg("--url")
                .arg(format!("udpin://127.0.0.1:{vport}"));
        }
    }
    cmd.args(["--duration", "40", "--exit-after-upload", "--summary"]).arg(&summary);
    if matches!(vehicle, Vehicle::Pymavlink { .. }) {
        cmd.arg("--stop-file").arg(dir.join("stop"));
    }
    let _vehicle =
        Peer(cmd.stdout(Stdio::null()).stderr(Stdio::null()).spawn().expect("start vehicle peer"));

    let log = dir.join("violations.jsonl");
    let guard = guard.map(|enforce| {
        let signing = signing.as_ref().map(|s| SigningConfig {
            key: SigningKey::from_passphrase(s.guard_pass),
            sign_to_vehicle: false,
            link_id: 0,
            state_file: None,
        });
        loopback_guard(vport, enforce, Some(log.clone()), signing)
    });
    let gport = guard.as_ref().map_or(vport, |g| g.gcs_addr.unwrap().port());

    let mavproxy = py.parent().unwrap().join("mavproxy.py");
    let mut mp = Command::new(py);
    mp.arg(&mavproxy)
        .arg(format!("--master=udpout:127.0.0.1:{gport}"))
        .args(["--daemon", "--non-interactive", "--target-system=1", "--target-component=1"])
        .arg(format!("--state-basedir={}", dir.join("mps").display()))
        .arg(match signing.as_ref().and_then(|s| s.mavproxy_pass) {
            Some(pass) => format!("--cmd=signing setup {pass}; wp load {}", mission.display()),
            None => format!("--cmd=wp load {}", mission.display()),
        })
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    let mut mp = Peer(mp.spawn().expect("start MAVProxy"));
    let (tx, rx) = mpsc::channel();
    let out = mp.0.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let mut text = String::new();
    let end =
        Instant::now() + signing.as_ref().map_or(Duration::from_secs(45), |s| s.give_up_after);
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
    drop(mp);
    std::fs::write(dir.join("stop"), b"").unwrap();
    let vehicle = read_summary(&summary);
    let counters = guard.map(|g| g.stop()).unwrap_or_default();
    let log = std::fs::read_to_string(&log).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    Outcome { mavproxy: text, vehicle, counters, log }
}

#[test]
fn baseline_mavproxy_uploads_100_to_pymavlink_vehicle_directly() {
    let Some(py) = python() else { return };
    let o = upload(&py, "direct", Vehicle::Pymavlink { ack_after: None }, None, None);
    assert!(o.mavproxy.contains("Sent all 100 waypoints"), "MAVProxy output:\n{}", o.mavproxy);
    assert_eq!(o.vehicle["uploads"][0]["received"], 100, "{}", o.vehicle);
}

#[test]
fn mavproxy_uploads_100_to_pymavlink_vehicle_through_guard() {
    let Some(py) = python() else { return };
    let o = upload_through_guard(&py, "pym", Vehicle::Pymavlink { ack_after: None }, true);
    assert!(o.mavproxy.contains("Sent all 100 waypoints"), "MAVProxy output:\n{}", o.mavproxy);
    assert!(
        o.mavproxy.contains("MISSION_ACK: TYPE_MISSION: ACCEPTED"),
        "MAVProxy output:\n{}",
        o.mavproxy
    );
    assert_eq!(o.vehicle["uploads"][0]["received"], 100, "{}", o.vehicle);
    assert_eq!(o.counters.violations, 0, "violations:\n{}", o.log);
    assert!(
        o.counters.forwarded_to_vehicle >= 101 && o.counters.forwarded_to_gcs >= 101,
        "{:?}",
        o.counters
    );
}

#[test]
fn mavproxy_uploads_100_to_mavsdk_vehicle_through_guard() {
    let Some(py) = python() else { return };
    let o = upload_through_guard(&py, "sdk", Vehicle::Mavsdk, true);
    assert!(o.mavproxy.contains("Sent all 100 waypoints"), "MAVProxy output:\n{}", o.mavproxy);
    assert!(o.mavproxy.contains("ACCEPTED"), "MAVProxy output:\n{}", o.mavproxy);
    assert_eq!(o.vehicle["uploads"][0]["items"], 100, "{}", o.vehicle);
    assert_eq!(o.counters.violations, 0, "violations:\n{}", o.log);
}

#[test]
fn early_ack_after_60_of_100_is_reported_in_monitor_mode() {
    let Some(py) = python() else { return };
    let o = upload_through_guard(&py, "ack60m", Vehicle::Pymavlink { ack_after: Some(60) }, false);
    assert_eq!(o.vehicle["uploads"][0]["received"], 60, "{}", o.vehicle);
    // forwarded: MAVProxy sees the (wrong) ACCEPTED, as it would without the guard
    assert!(
        o.mavproxy.contains("MISSION_ACK: TYPE_MISSION: ACCEPTED"),
        "MAVProxy output:\n{}",
        o.mavproxy
    );
    assert!(!o.mavproxy.contains("Sent all 100"), "MAVProxy output:\n{}", o.mavproxy);
    assert!(o.counters.violations >= 1, "{:?}", o.counters);
    assert_eq!(o.counters.dropped_violations, 0);
    let first: Value =
        serde_json::from_str(o.log.lines().next().expect("a violation line")).unwrap();
    assert_eq!(first["msgid"], 47, "the early MISSION_ACK is the violating message: {first}");
    assert_eq!(first["action"], "forwarded");
}

#[test]
fn early_ack_after_60_of_100_is_dropped_and_answered_in_enforce_mode() {
    let Some(py) = python() else { return };
    let o = upload_through_guard(&py, "ack60e", Vehicle::Pymavlink { ack_after: Some(60) }, true);
    assert_eq!(o.vehicle["uploads"][0]["received"], 60, "{}", o.vehicle);
    assert!(o.counters.dropped_violations >= 1, "{:?}", o.counters);
    assert!(o.counters.replies_sent >= 1, "{:?}", o.counters);
    // MAVProxy gets the guard's error ACK instead of ACCEPTED, so it does not report success
    assert!(o.mavproxy.contains("Got MISSION_ACK"), "MAVProxy output:\n{}", o.mavproxy);
    assert!(!o.mavproxy.contains("ACCEPTED"), "MAVProxy output:\n{}", o.mavproxy);
    let first: Value =
        serde_json::from_str(o.log.lines().next().expect("a violation line")).unwrap();
    assert_eq!(first["action"], "dropped");
}

/// A pymavlink GCS sends DO_PARACHUTE RELEASE to a disarmed pymavlink vehicle through the guard.
fn parachute_through_guard(py: &Path, tag: &str, enforce: bool) -> (Value, Value, CounterSnapshot) {
    let dir = tempdir(tag);
    let vport = free_port();
    let vsum = dir.join("vehicle.json");
    let _vehicle = Peer(
        Command::new(py)
            .arg(script("pymavlink_vehicle.py"))
            .arg("--url")
            .arg(format!("udpin:127.0.0.1:{vport}"))
            .args(["--duration", "30", "--summary"])
            .arg(&vsum)
            .arg("--stop-file")
            .arg(dir.join("stop"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("vehicle"),
    );
    let guard = loopback_guard(vport, enforce, None, None);
    let gsum = dir.join("gcs.json");
    let status = Command::new(py)
        .arg(script("pymavlink_gcs.py"))
        .arg("--url")
        .arg(format!("udpout:127.0.0.1:{}", guard.gcs_addr.unwrap().port()))
        .args(["--duration", "20", "--summary"])
        .arg(&gsum)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .expect("gcs");
    assert!(status.success());
    let gcs = read_summary(&gsum);
    std::fs::write(dir.join("stop"), b"").unwrap();
    let vehicle = read_summary(&vsum);
    let c = guard.stop();
    let _ = std::fs::remove_dir_all(&dir);
    (gcs, vehicle, c)
}

#[test]
fn parachute_while_disarmed_is_blocked_in_enforce_mode() {
    let Some(py) = python() else { return };
    let (gcs, vehicle, c) = parachute_through_guard(&py, "chute-e", true);
    assert_eq!(gcs["heartbeat"], true, "{gcs}");
    assert_eq!(vehicle["parachute_commands"], 0, "the vehicle never saw the command: {vehicle}");
    assert!(c.dropped_violations >= 1, "{c:?}");
    // the GCS is not left waiting: it gets an answer that is not ACCEPTED, and an alert
    assert!(gcs["command_ack"].as_u64().is_some_and(|r| r != 0), "{gcs}");
    assert!(
        gcs["statustext"]
            .as_array()
            .is_some_and(|a| a.iter().any(|t| t.as_str().unwrap_or("").contains("vouch"))),
        "{gcs}"
    );
}

#[test]
fn parachute_while_disarmed_is_reported_in_monitor_mode() {
    let Some(py) = python() else { return };
    let (gcs, vehicle, c) = parachute_through_guard(&py, "chute-m", false);
    assert_eq!(vehicle["parachute_commands"], 1, "{vehicle}");
    assert_eq!(gcs["command_ack"], 0, "the vehicle's own ACCEPTED is forwarded: {gcs}");
    assert!(c.violations >= 1 && c.dropped_violations == 0, "{c:?}");
}

#[test]
fn mavproxy_signed_upload_passes_a_guard_that_requires_signing() {
    let Some(py) = python() else { return };
    let signing = Signing {
        guard_pass: "vouch-interop",
        mavproxy_pass: Some("vouch-interop"),
        give_up_after: Duration::from_secs(45),
    };
    let o =
        upload(&py, "signed", Vehicle::Pymavlink { ack_after: None }, Some(true), Some(signing));
    assert!(o.mavproxy.contains("Sent all 100 waypoints"), "MAVProxy output:\n{}", o.mavproxy);
    assert_eq!(o.vehicle["uploads"][0]["received"], 100, "{}", o.vehicle);
    assert_eq!(o.counters.violations, 0, "{}", o.log);
    // MAVProxy's own SETUP_SIGNING goes out unsigned: rejected, never forwarded
    assert!(o.counters.signing_rejected >= 1, "{:?}", o.counters);
    assert!(o.counters.forwarded_to_vehicle >= 101, "{:?}", o.counters);
}

#[test]
fn mavproxy_with_the_wrong_key_gets_nothing_through() {
    let Some(py) = python() else { return };
    let signing = Signing {
        guard_pass: "vouch-interop",
        mavproxy_pass: Some("not-the-key"),
        give_up_after: Duration::from_secs(8),
    };
    let o =
        upload(&py, "wrongkey", Vehicle::Pymavlink { ack_after: None }, Some(true), Some(signing));
    assert!(!o.mavproxy.contains("Sent all"), "MAVProxy output:\n{}", o.mavproxy);
    assert_eq!(o.vehicle["uploads"].as_array().map(Vec::len), Some(0), "{}", o.vehicle);
    assert_eq!(o.counters.forwarded_to_vehicle, 0, "{:?}", o.counters);
    assert!(o.counters.signing_rejected >= 3, "{:?}", o.counters);
}
