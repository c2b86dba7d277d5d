//! What the guard tests share: loopback sockets with bounded waits, and frames produced by
//! pymavlink 2.4.50 (MAVLINK20=1) so that the expected bytes do not come from the code under test.
#![allow(dead_code)]

use std::net::{SocketAddr, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::Child;
use std::time::{Duration, Instant};

use vouch_mav::guard::{Inspector, MonitorInspector, RunningGuard};
use vouch_mav::monitor::MonitorSpec;
use vouch_testkit::Need;

/// The monitor with the standard library on the embedded dialect, as the guard runs it by
/// default; a skip (a failure under `VOUCH_REQUIRE_SHARED=1`) when the build has no dialect.
pub fn standard_inspector() -> Option<Box<dyn Inspector>> {
    match MonitorSpec::default().build() {
        Ok(m) => Some(Box::new(MonitorInspector::new(m))),
        Err(e) => vouch_testkit::missing(Need::Shared, &format!("no standard monitor ({e})")),
    }
}

/// Kills a peer process this test started when the test ends, pass or fail.
pub struct KillOnDrop(pub Child);

impl Drop for KillOnDrop {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// HEARTBEAT from 255/230 (type 6 GCS, autopilot 8), unsigned, seq 0: pymavlink
/// `heartbeat_encode(6, 8, 0, 0, 0)`.
pub const GCS_HEARTBEAT: &str = "fd09000000ffe60000000000000006080000038751";
/// STATUSTEXT{4, "vouch: hi"} from 1/191: pymavlink `statustext_encode(4, b"vouch: hi")`.
pub const STATUSTEXT_FRAME: &str = "fd0a00000001bffd000004766f7563683a20686985e7";
/// Signed frames, key bytes 0..=31, link id 7, timestamps 300000000000 and +1 (pymavlink signing).
pub const SIGNED_MISSION_COUNT: &str = "fd04010000ffe62c000064000101f8be0700b864d94500f16e608ca27f";
pub const SIGNED_HEARTBEAT: &str =
    "fd09010000ffe600000000000000060800000360a90701b864d945008f9956aa9a36";

pub fn hex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("test hex"))
        .collect()
}

pub fn key_0_to_31() -> [u8; 32] {
    let mut k = [0u8; 32];
    for (i, b) in k.iter_mut().enumerate() {
        *b = i as u8;
    }
    k
}

pub fn udp() -> UdpSocket {
    let s = UdpSocket::bind("127.0.0.1:0").expect("bind loopback");
    s.set_read_timeout(Some(Duration::from_millis(50))).expect("timeout");
    s
}

/// The guard binds `0.0.0.0:port` for udpout sockets; tests always talk to 127.0.0.1.
pub fn loopback(a: SocketAddr) -> SocketAddr {
    SocketAddr::from(([127, 0, 0, 1], a.port()))
}

/// Receives datagrams for at most `wait`, returning all of them.
pub fn drain(s: &UdpSocket, wait: Duration) -> Vec<Vec<u8>> {
    let end = Instant::now() + wait;
    let mut out = vec![];
    let mut buf = [0u8; 2048];
    while Instant::now() < end {
        if let Ok((n, _)) = s.recv_from(&mut buf) {
            out.push(buf[..n].to_vec());
        }
    }
    out
}

/// Receives one datagram within `wait`.
pub fn recv_one(s: &UdpSocket, wait: Duration) -> Option<Vec<u8>> {
    let end = Instant::now() + wait;
    let mut buf = [0u8; 2048];
    while Instant::now() < end {
        if let Ok((n, _)) = s.recv_from(&mut buf) {
            return Some(buf[..n].to_vec());
        }
    }
    None
}
/// COMMAND_LONG DO_PARACHUTE (208) RELEASE (param1 = 2) to 1/1 from 255/230:
/// pymavlink `command_long_encode(1, 1, 208, 0, 2, 0, 0, 0, 0, 0, 0)`.
pub const PARACHUTE_RELEASE: &str =
    "fd20000000ffe64c000000000040000000000000000000000000000000000000000000000000d0000101a15d";
/// HEARTBEAT from the vehicle 1/1 (quadrotor, ArduPilot): `heartbeat_encode(2, 3, 0, 0, 4)`.
pub const VEHICLE_HEARTBEAT: &str = "fd0900000001010000000000000002030004034ad7";

/// Waits until endpoint `name` has one open connection and `connects` connections so far: a
/// TCP peer's connect or accept returns before the guard has registered the connection.
pub fn connected(guard: &RunningGuard, name: &str, connects: u64) {
    let until = Instant::now() + Duration::from_secs(5);
    while guard
        .counters()
        .endpoint(name)
        .is_none_or(|e| (e.connects, e.connections) != (connects, 1))
    {
        assert!(Instant::now() < until, "the guard never registered {name}'s connection");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// A fresh directory for one test's files.
pub fn tempdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vouch-guard-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A QGC WPL 110 file: item 0 = home, items 1..99 NAV_WAYPOINT (16) in frame 3.
pub fn write_mission(dir: &Path) -> PathBuf {
    let mut s = String::from("QGC WPL 110\n");
    for i in 0..100 {
        let (cur, frame) = if i == 0 { (1, 0) } else { (0, 3) };
        s += &format!(
            "{i}\t{cur}\t{frame}\t16\t0\t0\t0\t0\t{:.7}\t{:.7}\t{:.1}\t1\n",
            -35.36 + f64::from(i) * 1e-4,
            149.16 + f64::from(i) * 1e-4,
            100.0 + f64::from(i)
        );
    }
    let p = dir.join("mission100.txt");
    std::fs::write(&p, s).unwrap();
    p
}

/// The JSON summary a peer script writes when it ends (waits up to 8 s for it).
pub fn read_summary(p: &Path) -> serde_json::Value {
    let end = Instant::now() + Duration::from_secs(8);
    while Instant::now() < end {
        if let Ok(s) = std::fs::read_to_string(p)
            && let Ok(v) = serde_json::from_str(&s)
        {
            return v;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    panic!("peer wrote no summary at {}", p.display());
}
