//! `vouch mav bench`: the guard against a direct path and a do-nothing relay (`socat`), measured
//! side by side in one run on loopback.
//!
//! * latency: one message in flight at a time (ping-pong in one thread, so send and receive
//!   instants come from one clock): a 100-waypoint upload exchange repeated, and single
//!   telemetry frames; reported as p50/p99 one-way µs and as µs added over the direct path;
//! * a paced telemetry stream (default 100 k msg/s) vehicle → GCS: delivered share and latency;
//! * saturation throughput: frames/s delivered when the sender blasts, with the relay process
//!   pinned to one core (the bench pins itself to the other);
//! * peak RSS (VmHWM) of the relay process.
//!
//! Every loop is bounded in count and time; only 127.0.0.1 is used.

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::messages::encode_v2;

#[derive(Clone, Debug)]
pub struct BenchArgs {
    /// Repetitions of the 100-waypoint upload per path (202 messages each).
    pub uploads: usize,
    /// Single telemetry pings per path.
    pub pings: usize,
    /// Paced stream rate (msg/s) and duration.
    pub rate: u32,
    pub seconds: f64,
    /// The `vouch` executable that runs the guard (normally the current one).
    pub vouch_exe: PathBuf,
    /// Extra arguments for the guard under test, e.g. `--enforce`.
    pub guard_args: Vec<String>,
    pub json: bool,
}

#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct PathResult {
    pub path: String,
    pub upload_p50_us: f64,
    pub upload_p99_us: f64,
    pub ping_p50_us: f64,
    pub ping_p99_us: f64,
    pub stream_rate: u32,
    pub stream_delivered_pct: f64,
    pub stream_p50_us: f64,
    pub stream_p99_us: f64,
    pub saturation_msgs_per_s: f64,
    /// Frames delivered per CPU-second the relay process used during saturation: its capacity
    /// on one core, much less sensitive to other load on the machine than wall-clock rates.
    pub msgs_per_cpu_second: Option<f64>,
    /// VmHWM right after start-up (includes parsing the dialect), VmHWM during the measured
    /// traffic (reset through /proc/PID/clear_refs after start-up), and VmRSS at the end.
    pub startup_peak_rss_kb: Option<u64>,
    pub peak_rss_kb: Option<u64>,
    pub end_rss_kb: Option<u64>,
}

const WAIT: Duration = Duration::from_millis(500);

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

fn pin_to_cpu(cpu: usize) {
    // SAFETY: cpu_set_t is plain data; sched_setaffinity(0, …) affects only the calling thread.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(cpu, &mut set);
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set);
    }
}

fn status_kb(pid: u32, key: &str) -> Option<u64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = s.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// User + system CPU seconds used so far by process `pid` (all threads).
fn cpu_seconds(pid: u32) -> Option<f64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let rest = &s[s.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // fields after the command name start at field 3 (state): utime is field 14, stime 15
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    // SAFETY: sysconf has no preconditions.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    Some(ticks / hz.max(1.0))
}

// --- the messages of the exchange (MAVLink 2, CRC_EXTRA from common.xml) -------------------

struct Seqs(u8);
impl Seqs {
    fn next(&mut self) -> u8 {
        self.0 = self.0.wrapping_add(1);
        self.0
    }
}

fn mission_count(n: u16, s: u8) -> Vec<u8> {
    let c = n.to_le_bytes();
    encode_v2(44, 221, &[c[0], c[1], 1, 1, 0], 255, 190, s)
}
fn mission_request_int(seq: u16, s: u8) -> Vec<u8> {
    let q = seq.to_le_bytes();
    encode_v2(51, 196, &[q[0], q[1], 255, 190, 0], 1, 1, s)
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
    encode_v2(73, 38, &p, 255, 190, s)
}
fn mission_ack(s: u8) -> Vec<u8> {
    encode_v2(47, 153, &[255, 190, 0, 0], 1, 1, s)
}
/// ATTITUDE with the sample index in `time_boot_ms`, so the receiver can match send instants.
fn attitude(index: u32, s: u8) -> Vec<u8> {
    let mut p = vec![0u8; 28];
    p[..4].copy_from_slice(&index.to_le_bytes());
    p[4..8].copy_from_slice(&0.1f32.to_le_bytes());
    encode_v2(30, 39, &p, 1, 1, s)
}
fn heartbeat_gcs(s: u8) -> Vec<u8> {
    encode_v2(0, 50, &[0, 0, 0, 0, 6, 8, 0, 0, 3], 255, 190, s)
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

struct Rig {
    gcs: UdpSocket,
    vehicle: UdpSocket,
    entry: SocketAddr,
    back: SocketAddr,
}

/// Makes the vehicle learn where the path's far end is (the relay's sending socket).
fn handshake(gcs: UdpSocket, vehicle: UdpSocket, entry: SocketAddr) -> io::Result<Rig> {
    let mut buf = [0u8; 512];
    let mut seqs = Seqs(0);
    let end = Instant::now() + Duration::from_secs(5);
    vehicle.set_read_timeout(Some(Duration::from_millis(50)))?;
    while Instant::now() < end {
        gcs.send_to(&heartbeat_gcs(seqs.next()), entry)?;
        if let Some((_, from)) = recv(&vehicle, &mut buf) {
            // drain what else is in flight
            while recv(&vehicle, &mut buf).is_some() {}
            vehicle.set_read_timeout(Some(WAIT))?;
            return Ok(Rig { gcs, vehicle, entry, back: from });
        }
    }
    Err(io::Error::new(io::ErrorKind::TimedOut, "path did not deliver a heartbeat within 5 s"))
}

fn upload_latencies(rig: &Rig, uploads: usize, out: &mut Vec<f64>) -> io::Result<()> {
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

fn ping_latencies(rig: &Rig, pings: usize, out: &mut Vec<f64>) -> io::Result<()> {
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
fn stream(rig: &Rig, count: u32, rate: u32, pin: bool) -> io::Result<(u64, Vec<f64>, f64)> {
    let gcs = rig.gcs.try_clone()?;
    gcs.set_read_timeout(Some(Duration::from_millis(200)))?;
    let base = Instant::now();
    let sent_ns: Arc<Vec<AtomicU64>> = Arc::new((0..count).map(|_| AtomicU64::new(0)).collect());
    let done = Arc::new(AtomicBool::new(false));
    let (s2, d2) = (sent_ns.clone(), done.clone());
    let rx = std::thread::spawn(move || {
        if pin {
            pin_to_cpu(1);
        }
        let mut lat = Vec::with_capacity(count as usize);
        let mut got = 0u64;
        let mut last = base;
        let mut buf = [0u8; 2048];
        loop {
            match gcs.recv_from(&mut buf) {
                Ok((n, _)) => {
                    let now = base.elapsed().as_nanos() as u64;
                    last = Instant::now();
                    got += 1;
                    if let Some(i) = attitude_index(&buf[..n]) {
                        if let Some(t) = s2.get(i as usize) {
                            let t = t.load(Ordering::Relaxed);
                            if t > 0 && now >= t {
                                lat.push((now - t) as f64 / 1000.0);
                            }
                        }
                    }
                }
                Err(_) if d2.load(Ordering::Relaxed) => break,
                Err(_) => {}
            }
        }
        (got, lat, last)
    });
    if pin {
        pin_to_cpu(1);
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

enum Relay {
    Direct,
    Process { child: Child, entry: SocketAddr },
}

fn spawn_relay(cmd: &mut Command, entry: SocketAddr) -> io::Result<Relay> {
    let child = cmd.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::null()).spawn()?;
    std::thread::sleep(Duration::from_millis(300));
    Ok(Relay::Process { child, entry })
}

/// Lets the calling thread run on every CPU again (after a saturation phase).
fn unpin() {
    // SAFETY: as in pin_to_cpu.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        for c in 0..libc::CPU_SETSIZE as usize {
            libc::CPU_SET(c, &mut set);
        }
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set);
    }
}

fn pin_child(pid: u32, cpu: usize) {
    // SAFETY: as in pin_to_cpu; the pid is our own child. Pin every thread of it.
    if let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) {
        for t in tasks.flatten() {
            if let Ok(tid) = t.file_name().to_string_lossy().parse::<i32>() {
                unsafe {
                    let mut set: libc::cpu_set_t = std::mem::zeroed();
                    libc::CPU_SET(cpu, &mut set);
                    libc::sched_setaffinity(tid, std::mem::size_of::<libc::cpu_set_t>(), &set);
                }
            }
        }
    }
}

fn measure(
    label: &str,
    relay: &mut Relay,
    vehicle: UdpSocket,
    a: &BenchArgs,
) -> io::Result<PathResult> {
    let gcs = sock()?;
    let entry = match relay {
        Relay::Direct => vehicle.local_addr()?,
        Relay::Process { entry, .. } => *entry,
    };
    let rig = handshake(gcs, vehicle, entry)?;
    let mut r = PathResult { path: label.to_string(), stream_rate: a.rate, ..Default::default() };
    if let Relay::Process { child, .. } = relay {
        r.startup_peak_rss_kb = status_kb(child.id(), "VmHWM:");
        // "5" resets the peak RSS counter (Linux ≥ 4.0), so VmHWM below covers the traffic only
        let _ = std::fs::write(format!("/proc/{}/clear_refs", child.id()), "5");
    }
    let mut up = vec![];
    upload_latencies(&rig, a.uploads, &mut up)?;
    up.sort_by(f64::total_cmp);
    (r.upload_p50_us, r.upload_p99_us) = (pct(&up, 0.5), pct(&up, 0.99));
    let mut ping = vec![];
    ping_latencies(&rig, a.pings, &mut ping)?;
    ping.sort_by(f64::total_cmp);
    (r.ping_p50_us, r.ping_p99_us) = (pct(&ping, 0.5), pct(&ping, 0.99));
    let n = (f64::from(a.rate) * a.seconds) as u32;
    let (got, mut lat, _) = stream(&rig, n, a.rate, false)?;
    lat.sort_by(f64::total_cmp);
    r.stream_delivered_pct = 100.0 * got as f64 / f64::from(n.max(1));
    (r.stream_p50_us, r.stream_p99_us) = (pct(&lat, 0.5), pct(&lat, 0.99));
    let sat_n = 300_000u32;
    let pid = match relay {
        Relay::Process { child, .. } => Some(child.id()),
        Relay::Direct => None,
    };
    if let Some(pid) = pid {
        pin_child(pid, 0);
    }
    let cpu0 = pid.and_then(cpu_seconds);
    let (got, _, secs) = stream(&rig, sat_n, 0, true)?;
    unpin();
    r.saturation_msgs_per_s = got as f64 / secs;
    if let (Some(pid), Some(c0)) = (pid, cpu0) {
        r.msgs_per_cpu_second = cpu_seconds(pid).map(|c1| got as f64 / (c1 - c0).max(0.01));
        r.peak_rss_kb = status_kb(pid, "VmHWM:");
        r.end_rss_kb = status_kb(pid, "VmRSS:");
    }
    Ok(r)
}

fn stop(relay: Relay) {
    if let Relay::Process { mut child, .. } = relay {
        // SIGTERM first so the guard shuts down cleanly, then make sure it is gone.
        // SAFETY: kill(2) on our own child's pid.
        unsafe {
            libc::kill(child.id() as i32, libc::SIGTERM);
        }
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

/// Runs every path in turn and prints a side-by-side table (or JSON).
pub fn run_bench(a: BenchArgs) -> Result<Vec<PathResult>, String> {
    let io = |e: io::Error| e.to_string();
    let mut results = vec![];
    let socat = Command::new("socat")
        .arg("-V")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok();
    let mut paths: Vec<(String, Option<Vec<String>>)> = vec![("direct".into(), None)];
    if socat {
        paths.push(("socat".into(), Some(vec![])));
    } else {
        eprintln!("socat not found: relay floor skipped (scripts/install-peers.sh installs it)");
    }
    paths.push(("guard relay-only".into(), Some(vec!["--relay-only".into()])));
    paths.push(("guard monitor".into(), Some(vec![])));
    let mut enforce = vec!["--enforce".to_string()];
    enforce.extend(a.guard_args.iter().cloned());
    paths.push(("guard enforce".into(), Some(enforce)));
    for (label, extra) in paths {
        let vehicle = sock().map_err(io)?;
        let v_addr = vehicle.local_addr().map_err(io)?;
        let entry_port = free_port().map_err(io)?;
        let entry: SocketAddr = SocketAddr::from(([127, 0, 0, 1], entry_port));
        let mut relay = match (label.as_str(), &extra) {
            ("direct", _) => Relay::Direct,
            ("socat", _) => spawn_relay(
                Command::new("socat")
                    .arg("-b65536")
                    .arg(format!("UDP4-LISTEN:{entry_port},bind=127.0.0.1,reuseaddr"))
                    .arg(format!("UDP4:{v_addr}")),
                entry,
            )
            .map_err(io)?,
            (_, Some(x)) => spawn_relay(
                Command::new(&a.vouch_exe)
                    .args([
                        "mav",
                        "guard",
                        "--gcs",
                        &format!("udpin:{entry}"),
                        "--vehicle",
                        &format!("udpout:{v_addr}"),
                    ])
                    .args(x),
                entry,
            )
            .map_err(io)?,
            _ => Relay::Direct,
        };
        let r = measure(&label, &mut relay, vehicle, &a);
        stop(relay);
        match r {
            Ok(r) => results.push(r),
            // a path that cannot run (e.g. no protocol library) is reported, the others still run
            Err(e) => eprintln!("path `{label}` skipped: {e}"),
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&results).unwrap_or_default());
    } else {
        print_table(&results, a.rate);
    }
    Ok(results)
}

fn print_table(rs: &[PathResult], rate: u32) {
    let direct = rs.first().cloned().unwrap_or_default();
    println!(
        "{:<17} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>8} {:>9} {:>9} {:>10} {:>8} {:>8} {:>8}",
        "path",
        "upl p50",
        "upl p99",
        "ping p50",
        "ping p99",
        "+p50 vs d",
        "+p99 vs d",
        "strm ok%",
        "strm p99",
        "sat msg/s",
        "msg/CPU-s",
        "start kB",
        "peak kB",
        "end kB"
    );
    let kb = |k: Option<u64>| k.map(|k| k.to_string()).unwrap_or_else(|| "-".into());
    for r in rs {
        println!(
            "{:<17} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>9.1} {:>9.1} {:>8.2} {:>9.1} {:>9.0} {:>10} {:>8} {:>8} {:>8}",
            r.path,
            r.upload_p50_us,
            r.upload_p99_us,
            r.ping_p50_us,
            r.ping_p99_us,
            r.upload_p50_us - direct.upload_p50_us,
            r.upload_p99_us - direct.upload_p99_us,
            r.stream_delivered_pct,
            r.stream_p99_us,
            r.saturation_msgs_per_s,
            r.msgs_per_cpu_second.map(|m| format!("{m:.0}")).unwrap_or_else(|| "-".into()),
            kb(r.startup_peak_rss_kb),
            kb(r.peak_rss_kb),
            kb(r.end_rss_kb),
        );
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "(µs one-way, one message in flight; +vs d = added over direct; stream = {rate} msg/s vehicle→GCS; \
         sat = blast with the relay pinned to CPU 0; start kB = peak RSS at start-up, peak kB = peak RSS \
         during the measured traffic, end kB = RSS at the end; loadavg {})",
        load.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
    );
}
