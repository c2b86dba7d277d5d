//! The benchmark behind `vouch mav bench`: the guard against a direct path and a do-nothing
//! relay (`socat`), measured side by side in one run on loopback. A harness, not part of the
//! guard or the monitor (nothing else in the crate uses it); it returns figures and prints
//! nothing.
//!
//! * latency: one message in flight at a time (ping-pong in one thread, so send and receive
//!   instants come from one clock): a 100-waypoint upload exchange repeated, and single
//!   telemetry frames; reported as one-way µs, the median with its spread ([`Latency`]);
//! * a paced telemetry stream (default 100 k msg/s) vehicle → GCS: delivered share and latency;
//! * saturation throughput: frames/s delivered when the sender blasts, with the relay process
//!   pinned to one core (the bench pins itself to the other);
//! * peak RSS of the relay process (Linux `/proc`).
//!
//! The router scenario (`router.rs`) runs the guard with four endpoints and measures latency,
//! *delivered* throughput and memory against the same baselines.
//!
//! The caller follows the run through a [`Step`] callback (one call per phase) and gets the
//! figures as a [`BenchReport`] (serialised as the `--json` document, rendered by [`table`]).
//!
//! Every loop is bounded in count and time; only 127.0.0.1 is used.

mod router;
mod stats;
mod table;
mod traffic;

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde::Serialize;

use crate::guard::sys::process;
pub use router::RouterResult;
pub use stats::Latency;
pub use table::table;
use traffic::{WAIT, handshake, ping_latencies, stream, upload_latencies};

/// The version of the JSON document ([`BenchReport`]); 2: paths named by [`PathKind`],
/// latencies as [`Latency`] objects, skipped paths as objects, no differences of medians.
pub const REPORT_VERSION: u32 = 2;

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Repetitions of the 100-waypoint upload per path (202 messages each).
    pub uploads: usize,
    /// Single telemetry pings per path.
    pub pings: usize,
    /// Paced stream rate (msg/s).
    pub rate: u32,
    /// Paced stream duration (s).
    pub seconds: f64,
    /// The `vouch` executable that runs the guard (normally the current one).
    pub vouch_exe: PathBuf,
    /// Extra arguments for the guard in enforce mode, e.g. `--protocol FILE`.
    pub guard_args: Vec<String>,
    /// Run the proxy scenario (one GCS, one vehicle: direct, socat, guard modes).
    pub proxy: bool,
    /// Run the router scenario (four endpoints: direct, socat, guard router).
    pub router: bool,
}

/// A path through which the bench sends its traffic.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PathKind {
    /// No relay: the peers send to each other (the floor of the machine).
    Direct,
    /// socat relaying datagrams (the floor of a do-nothing relay process).
    Socat,
    /// The guard checking nothing (`--relay-only`): its own floor.
    GuardRelayOnly,
    /// The guard in monitor mode with the standard protocols.
    GuardMonitor,
    /// The guard in enforce mode with the standard protocols.
    GuardEnforce,
    /// The guard routing between four endpoints, checking nothing.
    GuardRouterRelayOnly,
    /// The guard routing between four endpoints with the standard protocols.
    GuardRouter,
}

impl PathKind {
    /// The name tables and notes use.
    pub fn label(self) -> &'static str {
        match self {
            PathKind::Direct => "direct",
            PathKind::Socat => "socat",
            PathKind::GuardRelayOnly => "guard relay-only",
            PathKind::GuardMonitor => "guard monitor",
            PathKind::GuardEnforce => "guard enforce",
            PathKind::GuardRouterRelayOnly => "guard router relay-only",
            PathKind::GuardRouter => "guard router",
        }
    }
}

/// The figures of one path of the proxy scenario.
#[derive(Clone, Debug, Serialize)]
pub struct PathResult {
    /// Which path.
    pub path: PathKind,
    /// One-way latency of the messages of the 100-waypoint uploads.
    pub upload: Latency,
    /// One-way latency of single telemetry frames.
    pub telemetry: Latency,
    /// Rate of the paced stream, msg/s.
    pub stream_rate: u32,
    /// Share of the paced stream delivered, %.
    pub stream_delivered_pct: f64,
    /// Latency in the paced stream.
    pub stream: Latency,
    /// Frames per second delivered when the sender floods.
    pub flood_delivered_per_s: f64,
    /// Frames delivered per CPU-second the relay process used during the flood: its capacity
    /// on one core, much less sensitive to other load on the machine than wall-clock rates.
    pub frames_per_cpu_second: Option<f64>,
    /// Peak RSS right after start-up (includes loading the dialect), kB.
    pub startup_peak_rss_kb: Option<u64>,
    /// Peak RSS during the measured traffic only, kB.
    pub peak_rss_kb: Option<u64>,
    /// RSS at the end, kB.
    pub end_rss_kb: Option<u64>,
}

impl PathResult {
    fn new(path: PathKind, stream_rate: u32) -> PathResult {
        PathResult {
            path,
            upload: Latency::default(),
            telemetry: Latency::default(),
            stream_rate,
            stream_delivered_pct: 0.0,
            stream: Latency::default(),
            flood_delivered_per_s: 0.0,
            frames_per_cpu_second: None,
            startup_peak_rss_kb: None,
            peak_rss_kb: None,
            end_rss_kb: None,
        }
    }
}

/// A path that could not run, and why.
#[derive(Clone, Debug, Serialize)]
pub struct Skipped {
    /// `proxy` or `router`.
    pub scenario: &'static str,
    /// Which path.
    pub path: PathKind,
    /// Why (e.g. `socat` not installed).
    pub reason: String,
}

/// Everything one run measured: the `--json` document.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    /// [`REPORT_VERSION`].
    pub version: u32,
    /// Proxy scenario: one entry per path that ran, `direct` first.
    pub proxy: Vec<PathResult>,
    /// Router scenario: one entry per path that ran, `direct` first.
    pub router: Vec<RouterResult>,
    /// Paths that could not run.
    pub skipped: Vec<Skipped>,
    /// The machine's load averages (1, 5, 15 min) at the end, when known.
    pub load_average: Option<String>,
}

/// The start of one phase of the run, for a progress display.
#[derive(Clone, Debug)]
pub struct Step {
    /// Phases done before this one.
    pub done: u64,
    /// Phases of the whole run.
    pub total: u64,
    /// What runs now, e.g. `proxy, guard monitor: upload latency`.
    pub what: String,
}

/// Announces phases to the caller's callback.
struct Steps<'a> {
    done: u64,
    total: u64,
    scenario: &'static str,
    callback: &'a mut dyn FnMut(Step),
}

impl Steps<'_> {
    fn start(&mut self, path: PathKind, phase: &str) {
        let what = format!("{}, {}: {phase}", self.scenario, path.label());
        (self.callback)(Step { done: self.done, total: self.total, what });
        self.done += 1;
    }

    /// Counts the phases of a path that could not run as done.
    fn skip(&mut self, phases: u64) {
        self.done = (self.done + phases).min(self.total);
    }
}

fn sock() -> io::Result<UdpSocket> {
    let s = UdpSocket::bind("127.0.0.1:0")?;
    s.set_read_timeout(Some(WAIT))?;
    Ok(s)
}

fn free_port() -> io::Result<u16> {
    Ok(UdpSocket::bind("127.0.0.1:0")?.local_addr()?.port())
}

enum Relay {
    Direct,
    Process { child: Child, entry: SocketAddr },
}

fn spawn_relay(cmd: &mut Command, entry: SocketAddr) -> io::Result<Relay> {
    let child = cmd.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::null()).spawn()?;
    std::thread::sleep(Duration::from_millis(300));
    Ok(Relay::Process { child, entry })
}

/// Phases of one path of the proxy scenario.
const PROXY_PHASES: u64 = 4;

fn measure(
    path: PathKind,
    relay: &mut Relay,
    vehicle: UdpSocket,
    a: &BenchConfig,
    steps: &mut Steps<'_>,
) -> io::Result<PathResult> {
    let gcs = sock()?;
    let (entry, pid) = match relay {
        Relay::Direct => (vehicle.local_addr()?, None),
        Relay::Process { entry, child } => (*entry, Some(child.id())),
    };
    let rig = handshake(gcs, vehicle, entry)?;
    let mut r = PathResult::new(path, a.rate);
    if let Some(pid) = pid {
        r.startup_peak_rss_kb = process::peak_rss_kb(pid);
        // so that the peak read after the traffic covers the traffic only
        process::reset_peak_rss(pid);
    }
    steps.start(path, "upload latency");
    let mut up = vec![];
    upload_latencies(&rig, a.uploads, &mut up)?;
    r.upload = Latency::of(up);
    steps.start(path, "telemetry latency");
    let mut ping = vec![];
    ping_latencies(&rig, a.pings, &mut ping)?;
    r.telemetry = Latency::of(ping);
    steps.start(path, "paced stream");
    let n = (f64::from(a.rate) * a.seconds) as u32;
    let (got, lat, _) = stream(&rig, n, a.rate, false)?;
    r.stream_delivered_pct = 100.0 * got as f64 / f64::from(n.max(1));
    r.stream = Latency::of(lat);
    steps.start(path, "flood");
    if let Some(pid) = pid {
        process::pin_process(pid, 0);
    }
    let cpu0 = pid.and_then(process::cpu_seconds);
    let (got, _, secs) = stream(&rig, 300_000, 0, true)?;
    process::unpin_current_thread();
    r.flood_delivered_per_s = got as f64 / secs;
    if let (Some(pid), Some(c0)) = (pid, cpu0) {
        r.frames_per_cpu_second =
            process::cpu_seconds(pid).map(|c1| got as f64 / (c1 - c0).max(0.01));
        r.peak_rss_kb = process::peak_rss_kb(pid);
        r.end_rss_kb = process::rss_kb(pid);
    }
    Ok(r)
}

fn stop(relay: Relay) {
    if let Relay::Process { mut child, .. } = relay {
        // SIGTERM first so the guard shuts down cleanly, then make sure it is gone.
        process::terminate(&mut child);
        let end = Instant::now() + Duration::from_secs(3);
        while Instant::now() < end {
            if let Ok(Some(_)) = child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = child.kill();
        let _ = child.wait();
    }
}

/// The paths of the proxy scenario and the guard's arguments for each (`None` = no guard).
fn paths(a: &BenchConfig, socat: bool) -> Vec<(PathKind, Option<Vec<String>>)> {
    let mut paths = vec![(PathKind::Direct, None)];
    if socat {
        paths.push((PathKind::Socat, None));
    }
    paths.push((PathKind::GuardRelayOnly, Some(vec!["--relay-only".into()])));
    paths.push((PathKind::GuardMonitor, Some(vec![])));
    let mut enforce = vec!["--enforce".to_string()];
    enforce.extend(a.guard_args.iter().cloned());
    paths.push((PathKind::GuardEnforce, Some(enforce)));
    paths
}

/// Starts the relay of one path of the proxy scenario, in front of the vehicle at `v_addr`.
fn start_relay(
    path: PathKind,
    guard_args: Option<&[String]>,
    v_addr: SocketAddr,
    a: &BenchConfig,
) -> io::Result<Relay> {
    let entry_port = free_port()?;
    let entry = SocketAddr::from(([127, 0, 0, 1], entry_port));
    match (path, guard_args) {
        (PathKind::Socat, _) => spawn_relay(
            Command::new("socat")
                .arg("-b65536")
                .arg(format!("UDP4-LISTEN:{entry_port},bind=127.0.0.1,reuseaddr"))
                .arg(format!("UDP4:{v_addr}")),
            entry,
        ),
        (_, Some(args)) => spawn_relay(
            Command::new(&a.vouch_exe)
                .args(["mav", "guard", "--gcs", &format!("udpin:{entry}")])
                .args(["--vehicle", &format!("udpout:{v_addr}")])
                .args(args),
            entry,
        ),
        (_, None) => Ok(Relay::Direct),
    }
}

fn socat_installed() -> bool {
    Command::new("socat").arg("-V").stdout(Stdio::null()).stderr(Stdio::null()).status().is_ok()
}

/// Runs every path in turn, calling `progress` at the start of each phase. A path that cannot
/// run is listed in [`BenchReport::skipped`]; only failing to open loopback sockets is an error.
pub fn run(a: &BenchConfig, progress: &mut dyn FnMut(Step)) -> io::Result<BenchReport> {
    let socat = socat_installed();
    let mut report = BenchReport {
        version: REPORT_VERSION,
        proxy: vec![],
        router: vec![],
        skipped: vec![],
        load_average: None,
    };
    let proxy_paths = if a.proxy { paths(a, socat) } else { vec![] };
    let router_paths = if a.router { router::paths(a, socat) } else { vec![] };
    for (scenario, on) in [("proxy", a.proxy), ("router", a.router)] {
        if on && !socat {
            let reason = "socat not found".to_string();
            report.skipped.push(Skipped { scenario, path: PathKind::Socat, reason });
        }
    }
    let total =
        proxy_paths.len() as u64 * PROXY_PHASES + router_paths.len() as u64 * router::ROUTER_PHASES;
    let mut steps = Steps { done: 0, total, scenario: "proxy", callback: progress };
    for (path, guard_args) in proxy_paths {
        let vehicle = sock()?;
        let v_addr = vehicle.local_addr()?;
        let before = steps.done;
        let result = start_relay(path, guard_args.as_deref(), v_addr, a).and_then(|mut relay| {
            let r = measure(path, &mut relay, vehicle, a, &mut steps);
            stop(relay);
            r
        });
        match result {
            Ok(r) => report.proxy.push(r),
            Err(e) => {
                steps.skip(PROXY_PHASES - (steps.done - before));
                let reason = e.to_string();
                report.skipped.push(Skipped { scenario: "proxy", path, reason });
            }
        }
    }
    steps.scenario = "router";
    let (done, skipped) = router::run(a, router_paths, &mut steps);
    report.router = done;
    report.skipped.extend(skipped);
    report.load_average = process::load_average();
    Ok(report)
}
