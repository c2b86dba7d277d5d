//! The benchmark behind `vouch mav bench`: the guard against a direct path and a do-nothing
//! relay (`socat`), measured side by side in one run on loopback. A harness, not part of the
//! guard or the monitor (nothing else in the crate uses it); it returns figures and prints
//! nothing.
//!
//! * latency: one message in flight at a time (ping-pong in one thread, so send and receive
//!   instants come from one clock): a 100-waypoint upload exchange repeated, and single
//!   telemetry frames; reported as p50/p99 one-way µs;
//! * a paced telemetry stream (default 100 k msg/s) vehicle → GCS: delivered share and latency;
//! * saturation throughput: frames/s delivered when the sender blasts, with the relay process
//!   pinned to one core (the bench pins itself to the other);
//! * peak RSS of the relay process (Linux `/proc`).
//!
//! The router scenario (`router.rs`) runs the guard with four endpoints and measures latency,
//! *delivered* throughput and memory against the same baselines.
//!
//! Every loop is bounded in count and time; only 127.0.0.1 is used.

mod router;
mod traffic;

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::guard::sys::process;
pub use router::RouterResult;
use traffic::{WAIT, handshake, ping_latencies, stream, upload_latencies};

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

/// The figures of one path.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct PathResult {
    /// `direct`, `socat`, `guard relay-only`, `guard monitor`, `guard enforce`.
    pub path: String,
    /// One-way latency of the upload messages, µs, median.
    pub upload_p50_us: f64,
    /// … 99th percentile.
    pub upload_p99_us: f64,
    /// One-way latency of single telemetry frames, µs, median.
    pub ping_p50_us: f64,
    /// … 99th percentile.
    pub ping_p99_us: f64,
    /// Rate of the paced stream, msg/s.
    pub stream_rate: u32,
    /// Share of the paced stream delivered, %.
    pub stream_delivered_pct: f64,
    /// Latency in the paced stream, µs, median.
    pub stream_p50_us: f64,
    /// … 99th percentile.
    pub stream_p99_us: f64,
    /// Frames per second delivered when the sender blasts.
    pub saturation_msgs_per_s: f64,
    /// Frames delivered per CPU-second the relay process used during saturation: its capacity
    /// on one core, much less sensitive to other load on the machine than wall-clock rates.
    pub msgs_per_cpu_second: Option<f64>,
    /// Peak RSS right after start-up (includes loading the dialect), kB.
    pub startup_peak_rss_kb: Option<u64>,
    /// Peak RSS during the measured traffic only, kB.
    pub peak_rss_kb: Option<u64>,
    /// RSS at the end, kB.
    pub end_rss_kb: Option<u64>,
}

/// Everything one run measured.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct BenchReport {
    /// Proxy scenario: one entry per path that ran, `direct` first.
    pub paths: Vec<PathResult>,
    /// Router scenario: one entry per path that ran, `direct` first.
    pub router: Vec<RouterResult>,
    /// Paths that could not run, with the reason (e.g. `socat` not installed).
    pub skipped: Vec<(String, String)>,
    /// The machine's load averages (1, 5, 15 min) at the end, when known.
    pub load_average: Option<String>,
}

fn sock() -> io::Result<UdpSocket> {
    let s = UdpSocket::bind("127.0.0.1:0")?;
    s.set_read_timeout(Some(WAIT))?;
    Ok(s)
}

fn free_port() -> io::Result<u16> {
    Ok(UdpSocket::bind("127.0.0.1:0")?.local_addr()?.port())
}

fn pct(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn percentiles(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    (pct(&v, 0.5), pct(&v, 0.99))
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

fn measure(
    label: &str,
    relay: &mut Relay,
    vehicle: UdpSocket,
    a: &BenchConfig,
) -> io::Result<PathResult> {
    let gcs = sock()?;
    let (entry, pid) = match relay {
        Relay::Direct => (vehicle.local_addr()?, None),
        Relay::Process { entry, child } => (*entry, Some(child.id())),
    };
    let rig = handshake(gcs, vehicle, entry)?;
    let mut r = PathResult { path: label.to_string(), stream_rate: a.rate, ..Default::default() };
    if let Some(pid) = pid {
        r.startup_peak_rss_kb = process::peak_rss_kb(pid);
        // so that the peak read after the traffic covers the traffic only
        process::reset_peak_rss(pid);
    }
    let mut up = vec![];
    upload_latencies(&rig, a.uploads, &mut up)?;
    (r.upload_p50_us, r.upload_p99_us) = percentiles(up);
    let mut ping = vec![];
    ping_latencies(&rig, a.pings, &mut ping)?;
    (r.ping_p50_us, r.ping_p99_us) = percentiles(ping);
    let n = (f64::from(a.rate) * a.seconds) as u32;
    let (got, lat, _) = stream(&rig, n, a.rate, false)?;
    r.stream_delivered_pct = 100.0 * got as f64 / f64::from(n.max(1));
    (r.stream_p50_us, r.stream_p99_us) = percentiles(lat);
    if let Some(pid) = pid {
        process::pin_process(pid, 0);
    }
    let cpu0 = pid.and_then(process::cpu_seconds);
    let (got, _, secs) = stream(&rig, 300_000, 0, true)?;
    process::unpin_current_thread();
    r.saturation_msgs_per_s = got as f64 / secs;
    if let (Some(pid), Some(c0)) = (pid, cpu0) {
        r.msgs_per_cpu_second =
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

/// The paths of one run: label and how to start its relay (`None` = direct).
fn paths(a: &BenchConfig, socat: bool) -> Vec<(&'static str, Option<Vec<String>>)> {
    let mut paths: Vec<(&'static str, Option<Vec<String>>)> = vec![("direct", None)];
    if socat {
        paths.push(("socat", Some(vec![])));
    }
    paths.push(("guard relay-only", Some(vec!["--relay-only".into()])));
    paths.push(("guard monitor", Some(vec![])));
    let mut enforce = vec!["--enforce".to_string()];
    enforce.extend(a.guard_args.iter().cloned());
    paths.push(("guard enforce", Some(enforce)));
    paths
}

/// Runs every path in turn. A path that cannot run is listed in [`BenchReport::skipped`]; only
/// failing to open loopback sockets is an error.
pub fn run(a: &BenchConfig) -> io::Result<BenchReport> {
    let mut report = BenchReport::default();
    let socat = Command::new("socat")
        .arg("-V")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok();
    if !socat {
        report.skipped.push(("socat".into(), "socat not found".into()));
    }
    let proxy_paths = if a.proxy { paths(a, socat) } else { vec![] };
    for (label, extra) in proxy_paths {
        let vehicle = sock()?;
        let v_addr = vehicle.local_addr()?;
        let entry_port = free_port()?;
        let entry = SocketAddr::from(([127, 0, 0, 1], entry_port));
        let relay = match (label, &extra) {
            (_, None) => Ok(Relay::Direct),
            ("socat", _) => spawn_relay(
                Command::new("socat")
                    .arg("-b65536")
                    .arg(format!("UDP4-LISTEN:{entry_port},bind=127.0.0.1,reuseaddr"))
                    .arg(format!("UDP4:{v_addr}")),
                entry,
            ),
            (_, Some(x)) => spawn_relay(
                Command::new(&a.vouch_exe)
                    .args(["mav", "guard", "--gcs", &format!("udpin:{entry}")])
                    .args(["--vehicle", &format!("udpout:{v_addr}")])
                    .args(x),
                entry,
            ),
        };
        let result = relay.and_then(|mut relay| {
            let r = measure(label, &mut relay, vehicle, a);
            stop(relay);
            r
        });
        match result {
            Ok(r) => report.paths.push(r),
            Err(e) => report.skipped.push((label.to_string(), e.to_string())),
        }
    }
    if a.router {
        let (done, skipped) = router::run(a, socat);
        report.router = done;
        report.skipped.extend(skipped);
    }
    report.load_average = process::load_average();
    Ok(report)
}
