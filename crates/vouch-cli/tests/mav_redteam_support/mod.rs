//! Harness of the red-team tests: the real `vouch mav guard` binary between a scripted pymavlink
//! vehicle (`crates/vouch-mav/tests/redteam/vehicle.py`) and a pymavlink ground station that plays
//! the attacker (`gcs.py`), over real sockets on 127.0.0.1. What is asserted is what the vehicle
//! peer logged as received (every datagram, decoded by pymavlink) and what the ground station got
//! back; the guard's own counters are checked only beside that.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// The peer venv's interpreter with pymavlink (a skip, or a failure under
/// `VOUCH_REQUIRE_PEERS=1`, without it).
pub fn python() -> Option<PathBuf> {
    vouch_testkit::python_with(&["pymavlink"]).map(PathBuf::from)
}

pub fn script(name: &str) -> PathBuf {
    vouch_testkit::repo_root().join("crates/vouch-mav/tests/redteam").join(name)
}

pub fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0").expect("bind").local_addr().expect("addr").port()
}

pub fn free_tcp_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").expect("bind").local_addr().expect("addr").port()
}

/// A fresh scratch folder for one test.
pub fn scratch(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mav_redteam").join(tag);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

/// Kills a process this test started (and only that one) when the test ends, pass or fail.
pub struct Proc(pub Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn read_json(p: &Path, who: &str) -> Value {
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        if let Ok(s) = std::fs::read_to_string(p)
            && let Ok(v) = serde_json::from_str(&s)
        {
            return v;
        }
        assert!(Instant::now() < end, "{who} wrote no summary at {}", p.display());
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The scripted vehicle, listening on a UDP port of its own.
pub struct Vehicle {
    proc: Proc,
    pub port: u16,
    summary: PathBuf,
    stop: PathBuf,
}

impl Vehicle {
    /// Starts `vehicle.py` with extra arguments (state, parameters).
    pub fn start(py: &Path, dir: &Path, args: &[&str]) -> Vehicle {
        Self::start_script(py, dir, "vehicle.py", args)
    }

    /// Starts the vehicle script `name` (`vehicle.py`, `chute_vehicle.py`) with extra arguments.
    pub fn start_script(py: &Path, dir: &Path, name: &str, args: &[&str]) -> Vehicle {
        let port = free_udp_port();
        let summary = dir.join("vehicle.json");
        let stop = dir.join("vehicle.stop");
        let child = Command::new(py)
            .arg(script(name))
            .args(["--port", &port.to_string()])
            .arg("--summary")
            .arg(&summary)
            .arg("--stop-file")
            .arg(&stop)
            .args(args)
            .stdin(Stdio::null())
            .spawn()
            .expect("vehicle.py starts");
        Vehicle { proc: Proc(child), port, summary, stop }
    }

    /// Stops the vehicle and returns its summary: every datagram it received (hex), the
    /// messages pymavlink decoded from them, and what it did with them.
    pub fn finish(mut self) -> Value {
        std::fs::write(&self.stop, b"stop").expect("stop file");
        let end = Instant::now() + Duration::from_secs(10);
        while self.proc.0.try_wait().ok().flatten().is_none() && Instant::now() < end {
            std::thread::sleep(Duration::from_millis(20));
        }
        read_json(&self.summary, "vehicle.py")
    }
}

/// The guard binary, run as an operator runs it.
pub struct Guard {
    proc: Proc,
    /// The GCS-side endpoint as pymavlink spells it (`udpout:…` or `tcp:…`).
    pub gcs_url: String,
    stdout: PathBuf,
    stderr: PathBuf,
}

impl Guard {
    /// `vouch mav guard --gcs udpin:127.0.0.1:P --vehicle udpout:127.0.0.1:<vehicle> --json ARGS`,
    /// with its state directory (`XDG_STATE_HOME`) inside `dir`.
    pub fn start(dir: &Path, vehicle_port: u16, args: &[&str]) -> Guard {
        Self::start_on(dir, &format!("udpin:127.0.0.1:{}", free_udp_port()), vehicle_port, args)
    }

    /// The same with a given GCS-side endpoint (`udpin:…` or `tcpin:…`).
    pub fn start_on(dir: &Path, gcs: &str, vehicle_port: u16, args: &[&str]) -> Guard {
        let n = std::fs::read_dir(dir).map(|d| d.count()).unwrap_or(0);
        let stdout = dir.join(format!("guard{n}.out"));
        let stderr = dir.join(format!("guard{n}.err"));
        let child = Command::new(env!("CARGO_BIN_EXE_vouch"))
            .args(["mav", "guard", "--gcs", gcs])
            .args(["--vehicle", &format!("udpout:127.0.0.1:{vehicle_port}")])
            .arg("--json")
            .args(args)
            .env("XDG_STATE_HOME", dir.join("state"))
            .env_remove("STATE_DIRECTORY")
            .stdin(Stdio::null())
            .stdout(std::fs::File::create(&stdout).expect("stdout file"))
            .stderr(std::fs::File::create(&stderr).expect("stderr file"))
            .spawn()
            .expect("the vouch binary starts");
        let (scheme, addr) = gcs.split_once(':').expect("SCHEME:ADDR:PORT");
        let gcs_url = match scheme {
            "tcpin" => format!("tcp:{addr}"),
            _ => format!("udpout:{addr}"),
        };
        let guard = Guard { proc: Proc(child), gcs_url, stdout, stderr };
        guard.wait_bound(scheme == "tcpin", addr);
        guard
    }

    /// Waits until the guard holds its GCS-side port (binding it fails), so that nothing sent
    /// right after start-up is lost before the guard listens.
    fn wait_bound(&self, tcp: bool, addr: &str) {
        let end = Instant::now() + Duration::from_secs(10);
        loop {
            let taken = if tcp {
                std::net::TcpStream::connect(addr).is_ok()
            } else {
                UdpSocket::bind(addr).is_err()
            };
            if taken {
                return;
            }
            assert!(Instant::now() < end, "the guard did not bind {addr}: {}", self.log());
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// What the guard printed on stderr so far (events, notes), for assertion messages.
    pub fn log(&self) -> String {
        std::fs::read_to_string(&self.stderr).unwrap_or_default()
    }

    /// Stops the guard with SIGTERM (as systemd or Ctrl-C would) and returns its final counters
    /// (`--json`).
    pub fn stop(mut self) -> Value {
        let pid = self.proc.0.id().to_string();
        let _ = Command::new("kill").args(["-TERM", &pid]).status();
        let end = Instant::now() + Duration::from_secs(10);
        let status = loop {
            if let Some(s) = self.proc.0.try_wait().expect("wait") {
                break s;
            }
            assert!(Instant::now() < end, "the guard did not stop on SIGTERM: {}", self.log());
            std::thread::sleep(Duration::from_millis(20));
        };
        assert!(status.success(), "guard exit {status}: {}", self.log());
        let out = std::fs::read_to_string(&self.stdout).expect("guard stdout");
        serde_json::from_str(out.lines().last().unwrap_or("")).unwrap_or_else(|e| {
            panic!("guard counters not JSON ({e}): {out:?}; stderr: {}", self.log())
        })
    }

    /// The guard's peak resident set so far (Linux `/proc`), in kB.
    pub fn peak_rss_kb(&self) -> Option<u64> {
        let s = std::fs::read_to_string(format!("/proc/{}/status", self.proc.0.id())).ok()?;
        s.lines().find(|l| l.starts_with("VmHWM:"))?.split_whitespace().nth(1)?.parse().ok()
    }

    /// Kills the guard with SIGKILL (no shutdown code runs: a crash or power loss).
    pub fn kill(mut self) {
        let _ = self.proc.0.kill();
        let _ = self.proc.0.wait();
    }
}

/// Runs `gcs.py --scenario NAME ARGS` against the guard and returns its summary.
pub fn gcs(py: &Path, dir: &Path, guard: &Guard, scenario: &str, args: &[&str]) -> Value {
    gcs_at(py, dir, &guard.gcs_url, scenario, args, &guard.log())
}

/// Runs `gcs.py --scenario NAME ARGS` against `url` (the guard, or a vehicle directly) and
/// returns its summary; `context` goes into the failure message.
pub fn gcs_at(
    py: &Path,
    dir: &Path,
    url: &str,
    scenario: &str,
    args: &[&str],
    context: &str,
) -> Value {
    let summary = dir.join(format!("gcs-{scenario}.json"));
    let _ = std::fs::remove_file(&summary);
    let status = Command::new(py)
        .arg(script("gcs.py"))
        .args(["--guard", url, "--scenario", scenario])
        .arg("--summary")
        .arg(&summary)
        .args(args)
        .stdin(Stdio::null())
        .status()
        .expect("gcs.py runs");
    assert!(status.success(), "gcs.py {scenario} failed ({status}); {context}");
    read_json(&summary, "gcs.py")
}

/// What one attack left behind: the attacker's summary, the guard's final counters, and what the
/// vehicle received.
pub struct Outcome {
    pub gcs: Value,
    pub counters: Value,
    pub vehicle: Value,
}

/// One attack against a fresh guard (UDP): the vehicle started with `vehicle_args`, the guard
/// with `guard_args`, then `gcs.py --scenario scenario gcs_args`.
pub fn attack(
    py: &Path,
    tag: &str,
    vehicle_args: &[&str],
    guard_args: &[&str],
    scenario: &str,
    gcs_args: &[&str],
) -> Outcome {
    let dir = scratch(tag);
    let vehicle = Vehicle::start(py, &dir, vehicle_args);
    let guard = Guard::start(&dir, vehicle.port, guard_args);
    let gcs = gcs(py, &dir, &guard, scenario, gcs_args);
    let counters = guard.stop();
    Outcome { gcs, counters, vehicle: vehicle.finish() }
}

/// The messages of type `ty` the vehicle decoded.
pub fn received<'a>(vehicle: &'a Value, ty: &str) -> Vec<&'a Value> {
    vehicle["messages"].as_array().expect("messages").iter().filter(|m| m["type"] == ty).collect()
}

/// Every message type the vehicle decoded, in order.
pub fn types(vehicle: &Value) -> Vec<String> {
    vehicle["messages"]
        .as_array()
        .expect("messages")
        .iter()
        .map(|m| m["type"].as_str().unwrap_or("?").to_string())
        .collect()
}

/// The datagrams the vehicle received, as bytes.
pub fn datagrams(vehicle: &Value) -> Vec<Vec<u8>> {
    vehicle["datagrams"]
        .as_array()
        .expect("datagrams")
        .iter()
        .map(|h| hex(h.as_str().expect("hex")))
        .collect()
}

pub fn hex(s: &str) -> Vec<u8> {
    (0..s.len() / 2).map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).expect("hex")).collect()
}

/// ArduPilot-like vehicle state in which a parachute release is unsafe: armed, 50 m above home
/// but climbing at 2 m/s; PX4-like pitch gains (MC_PITCHRATE_MAX must stay below 6.5 × 0.5).
pub const UNSAFE_VEHICLE: &[&str] = &[
    "--armed",
    "1",
    "--alt",
    "50",
    "--climb",
    "2",
    "--param",
    "CHUTE_ALT_MIN=10",
    "--param",
    "MC_PITCH_P=6.5",
    "--param",
    "MC_PITCHRATE_FF=0.5",
    "--param",
    "MC_PITCHRATE_MAX=3",
];

/// The markers (param2) of the harmless MAV_CMD_REQUEST_MESSAGE commands the vehicle received,
/// in order.
pub fn markers_received(v: &Value) -> Vec<f64> {
    received(v, "COMMAND_LONG")
        .iter()
        .filter(|m| m["fields"]["command"] == 512)
        .map(|m| m["fields"]["param2"].as_f64().expect("param2"))
        .collect()
}

/// Runs MAVProxy (a real ground station) against the guard: waits for the vehicle, types
/// `commands` one per second, and returns what it printed once every text in `expect` appeared
/// (or after `timeout`).
pub fn mavproxy(
    py: &Path,
    dir: &Path,
    guard: &Guard,
    commands: &[&str],
    expect: &[&str],
    timeout: Duration,
) -> String {
    let (_mp, mut stdin, rx) = spawn_mavproxy(py, dir, guard, &[]);
    let end = Instant::now() + timeout;
    let mut text = String::new();
    let mut pending: Vec<&str> = commands.to_vec();
    let mut next_at: Option<Instant> = None;
    while Instant::now() < end && !expect.iter().all(|e| text.contains(e)) {
        if let Ok(line) = rx.recv_timeout(Duration::from_millis(50)) {
            text += &line;
            text.push('\n');
        }
        if next_at.is_none() && text.contains("Detected vehicle") {
            next_at = Some(Instant::now() + Duration::from_secs(2));
        }
        if next_at.is_some_and(|t| Instant::now() >= t) && !pending.is_empty() {
            let c = pending.remove(0);
            let _ = writeln!(stdin, "{c}");
            let _ = stdin.flush();
            next_at = Some(Instant::now() + Duration::from_secs(1));
        }
    }
    let _ = writeln!(stdin, "exit");
    text
}

/// MAVProxy (target 1/1) with the guard as its master and `extra` arguments: the process, its
/// standard input and its console lines as they come.
fn spawn_mavproxy(
    py: &Path,
    dir: &Path,
    guard: &Guard,
    extra: &[String],
) -> (Proc, std::process::ChildStdin, std::sync::mpsc::Receiver<String>) {
    let mavproxy = py.parent().expect("venv bin").join("mavproxy.py");
    let mut child = Command::new(py)
        .arg(mavproxy)
        .arg(format!("--master={}", guard.gcs_url))
        .args(extra)
        .args(["--target-system=1", "--target-component=1"])
        .arg(format!("--state-basedir={}", dir.join("mavproxy").display()))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("MAVProxy starts");
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    let out = child.stdout.take().expect("stdout");
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let stdin = child.stdin.take().expect("stdin");
    (Proc(child), stdin, rx)
}

/// MAVProxy (a real ground station) connected to the guard as its master and relaying to a
/// client on `out` (`udpout:…`), running until dropped. Its console lines arrive on the channel.
pub struct MavProxyRelay {
    _proc: Proc,
    /// Kept open: MAVProxy ends at the end of its input.
    _stdin: std::process::ChildStdin,
    lines: std::sync::mpsc::Receiver<String>,
    text: String,
}

impl MavProxyRelay {
    pub fn start(py: &Path, dir: &Path, guard: &Guard, out: &str) -> Option<MavProxyRelay> {
        let (proc, stdin, lines) = spawn_mavproxy(py, dir, guard, &[format!("--out={out}")]);
        let mut relay = MavProxyRelay { _proc: proc, _stdin: stdin, lines, text: String::new() };
        relay.wait_for("Detected vehicle", Duration::from_secs(30)).then_some(relay)
    }

    /// Reads console lines until one contains `what` (true) or `timeout` passes (false).
    pub fn wait_for(&mut self, what: &str, timeout: Duration) -> bool {
        let end = Instant::now() + timeout;
        while Instant::now() < end {
            if self.text.contains(what) {
                return true;
            }
            if let Ok(line) = self.lines.recv_timeout(Duration::from_millis(50)) {
                self.text += &line;
                self.text.push('\n');
            }
        }
        self.text.contains(what)
    }

    /// Everything MAVProxy printed so far.
    pub fn text(&self) -> &str {
        &self.text
    }
}
