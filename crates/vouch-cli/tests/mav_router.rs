//! `vouch mav guard` as an operator starts it where mavlink-router was: a mavlink-router
//! `main.conf` (one vehicle endpoint, three ground endpoints) runs unchanged and routes; a key it
//! does not know is an error at its `file:line:col`; the shipped example configuration is
//! accepted by `--check`.

use std::net::{SocketAddr, TcpListener, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn vouch() -> Command {
    Command::new(env!("CARGO_BIN_EXE_vouch"))
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mav_router");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    dir.join(name)
}

fn free_udp() -> u16 {
    UdpSocket::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// HEARTBEAT from the vehicle 1/1 (pymavlink `heartbeat_encode(2, 3, 0, 0, 4)`).
const VEHICLE_HEARTBEAT: &str = "fd0900000001010000000000000002030004034ad7";
/// COMMAND_LONG DO_PARACHUTE (208) RELEASE to 1/1 from 255/230 (pymavlink).
const PARACHUTE_RELEASE: &str =
    "fd20000000ffe64c000000000040000000000000000000000000000000000000000000000000d0000101a15d";

fn hex(s: &str) -> Vec<u8> {
    (0..s.len()).step_by(2).map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap()).collect()
}

/// Datagrams received within `wait`, and who sent the last one.
fn recv(s: &UdpSocket, wait: Duration) -> (Vec<Vec<u8>>, Option<SocketAddr>) {
    s.set_read_timeout(Some(Duration::from_millis(20))).unwrap();
    let end = Instant::now() + wait;
    let (mut out, mut from) = (vec![], None);
    let mut buf = [0u8; 2048];
    while Instant::now() < end {
        if let Ok((n, a)) = s.recv_from(&mut buf) {
            out.push(buf[..n].to_vec());
            from = Some(a);
        }
    }
    (out, from)
}

#[test]
fn a_mavlink_router_main_conf_runs_unchanged_and_routes() {
    let (fcu, gcs1, gcs2) = (
        free_udp(),
        UdpSocket::bind("127.0.0.1:0").unwrap(),
        UdpSocket::bind("127.0.0.1:0").unwrap(),
    );
    let logger = TcpListener::bind("127.0.0.1:0").unwrap();
    let conf = format!(
        "[General]\nTcpServerPort = 0\nReportStats = false\nMavlinkDialect = auto\n\n\
         [UdpEndpoint fcu]\nMode = Server\nAddress = 127.0.0.1\nPort = {fcu}\n\n\
         [UdpEndpoint qgc]\nMode = Normal\nAddress = 127.0.0.1\nPort = {}\n\n\
         [UdpEndpoint gcs2]\nMode = Normal\nAddress = 127.0.0.1\nPort = {}\n\n\
         [TcpEndpoint logger]\nAddress = 127.0.0.1\nPort = {}\nRetryTimeout = 1\n",
        gcs1.local_addr().unwrap().port(),
        gcs2.local_addr().unwrap().port(),
        logger.local_addr().unwrap().port()
    );
    let path = tmp("main.conf");
    std::fs::write(&path, conf).unwrap();
    let child = vouch()
        .args(["mav", "guard", "-c"])
        .arg(&path)
        .args(["--duration", "4", "--enforce", "--json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("vouch starts");
    let (mut tcp, _) = logger.accept().expect("the logger endpoint connects");
    tcp.set_read_timeout(Some(Duration::from_millis(100))).unwrap();
    let vehicle = UdpSocket::bind("127.0.0.1:0").unwrap();
    let to_fcu = SocketAddr::from(([127, 0, 0, 1], fcu));
    std::thread::sleep(Duration::from_millis(300));
    // the vehicle's heartbeat reaches both ground stations and the logger, byte for byte
    vehicle.send_to(&hex(VEHICLE_HEARTBEAT), to_fcu).unwrap();
    let (got, guard_qgc) = recv(&gcs1, Duration::from_millis(500));
    assert_eq!(got, vec![hex(VEHICLE_HEARTBEAT)]);
    assert_eq!(recv(&gcs2, Duration::from_millis(200)).0, vec![hex(VEHICLE_HEARTBEAT)]);
    let mut buf = [0u8; 64];
    let n = std::io::Read::read(&mut tcp, &mut buf).expect("logger gets the heartbeat");
    assert_eq!(&buf[..n], &hex(VEHICLE_HEARTBEAT)[..]);
    // a parachute release from QGroundControl to the disarmed vehicle, sent back to the address
    // the guard sends from: dropped (enforce); a heartbeat from gcs2 goes through
    let guard_qgc = SocketAddr::from(([127, 0, 0, 1], guard_qgc.expect("sender").port()));
    gcs1.send_to(&hex(PARACHUTE_RELEASE), guard_qgc).unwrap();
    assert!(recv(&vehicle, Duration::from_millis(500)).0.is_empty(), "the vehicle gets nothing");
    let out = child.wait_with_output().expect("vouch ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let c: serde_json::Value = serde_json::from_slice(&out.stdout).expect("counters as JSON");
    assert_eq!(c["endpoints"][0]["name"], "fcu");
    assert_eq!(c["endpoints"][0]["side"], "vehicle", "the one UDP server is the vehicle");
    assert_eq!(c["endpoints"][1]["frames_out"], 1, "{c}");
    assert_eq!(
        (c["violations"].as_u64(), c["dropped_violations"].as_u64()),
        (Some(1), Some(1)),
        "{c}"
    );
    assert!(stderr.contains("fcu") && stderr.contains("vehicle"), "{stderr}");
}

#[test]
fn an_unknown_key_is_an_error_at_its_line() {
    let path = tmp("typo.conf");
    std::fs::write(
        &path,
        "[General]\nTcpServerPort = 0\n\n[UdpEndpoint qgc]\nMode = Normal\nAdress = 127.0.0.1\n",
    )
    .unwrap();
    let out = vouch()
        .args(["--message-format", "short", "mav", "guard", "-c"])
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("typo.conf:6:1: error[mav::G003]: unknown key `Adress`"), "{err}");
    let out = vouch().args(["mav", "guard", "-c", "/nonexistent/main.conf"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    // no endpoint for the vehicle: a usage error that says how to name it
    let path = tmp("novehicle.conf");
    std::fs::write(&path, "[General]\nTcpServerPort = 0\n[UdpEndpoint a]\nMode = Normal\nAddress = 127.0.0.1\nPort = 9\n").unwrap();
    let out = vouch().args(["mav", "guard", "-c"]).arg(&path).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("Side = vehicle"));
}

#[test]
fn the_shipped_example_configuration_is_accepted() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../packaging/guard.conf.example");
    let out = vouch().args(["mav", "guard", "-c"]).arg(&example).arg("--check").output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let listed = String::from_utf8_lossy(&out.stdout);
    assert!(listed.contains("autopilot\tvehicle\tserial:/dev/ttyACM0:115200"), "{listed}");
    assert!(listed.contains("qgc\tground\tudpout:192.168.1.20:14550"), "{listed}");
    assert!(listed.contains("tcp-server\tground\ttcpin:0.0.0.0:5760"), "{listed}");
}
