//! The proxy core: per-frame admission (signing, inspector), byte-exact forwarding, enforce-mode
//! answers, STATUSTEXT alerts, violations log, tlog recording, counters and events.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use serde_json::json;

use super::config::GuardConfig;
use super::counters::{CounterSnapshot, Counters};
use super::events::{within_rate, Events, GuardEvent};
use super::link::{self, Egress, Peer, Received};
use super::messages::{statustext, SEVERITY_WARNING};
use super::Inspector;
use crate::codec::split::{split_datagram, split_datagram_resync, Piece};
use crate::codec::FrameRef;
use crate::monitor::{Reply, Verdict, Violation};
use crate::side::Side;
use crate::signing::state::{resume, StateSaver};
use crate::signing::{timestamp_now, Signer, Verifier, SETUP_SIGNING_ID};

/// Most STATUSTEXT alerts per second: a violation flood must not flood the pilot's link too.
const MAX_ALERTS_PER_SECOND: u64 = 5;
/// Most signing rejections written to the violations log (all are counted).
const MAX_LOGGED_SIG_REJECTS: u64 = 100;

struct Core {
    enforce: bool,
    alert_gcs: bool,
    inspector: Mutex<Box<dyn Inspector>>,
    verifier: Option<Arc<Mutex<Verifier>>>,
    /// Signs what the guard sends toward the vehicle: its own replies whenever a key is set,
    /// forwarded frames too with `sign_forwarded` (`--sign-to-vehicle`).
    signer: Option<Mutex<Signer>>,
    sign_forwarded: bool,
    egress: [OnceLock<Arc<Egress>>; 2],
    counters: Counters,
    log: Option<Mutex<BufWriter<File>>>,
    tlog: Option<Mutex<BufWriter<File>>>,
    own_seq: AtomicU8,
    /// Vehicle (sysid, compid) from its first HEARTBEAT, packed as sysid << 8 | compid + 1
    /// (0 = not seen yet); alerts are sent in the vehicle's name so GCSs display them.
    vehicle_ids: AtomicU64,
    alert_window: Mutex<(Instant, u64)>,
    events: Events,
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

fn unix_micros() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_micros() as u64).unwrap_or(0)
}

/// Accepted byte ranges of one datagram; contiguous ranges merge so that a datagram whose frames
/// are all accepted is sent once, exactly as received. The first range is stored inline: the
/// common case (everything accepted) allocates nothing.
#[derive(Default)]
struct Ranges {
    first: Option<(usize, usize)>,
    more: Vec<(usize, usize)>,
}

impl Ranges {
    fn push(&mut self, a: usize, b: usize) {
        let last = if self.more.is_empty() { self.first.as_mut() } else { self.more.last_mut() };
        match last {
            Some(last) if last.1 == a => last.1 = b,
            Some(_) => self.more.push((a, b)),
            None => self.first = Some((a, b)),
        }
    }

    fn iter(&self) -> impl Iterator<Item = &(usize, usize)> {
        self.first.iter().chain(self.more.iter())
    }
}

/// What [`Core::admit`] decided for one candidate frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Admission {
    Forward,
    Drop,
    /// Corrupt: not a frame at all. Datagrams and streams resynchronise after its start marker;
    /// its bytes are then junk (forwarded only where junk passes).
    NotAFrame,
}

impl Core {
    fn out(&self, side: Side) -> Option<&Arc<Egress>> {
        self.egress[side.index()].get()
    }

    /// Handles one received piece; `false` = a stream candidate was no frame (resynchronise).
    fn on_received(&self, side: Side, peer: Peer, rx: Received<'_>) -> bool {
        match rx {
            Received::Datagram(d) => self.on_datagram(side, peer, d),
            Received::StreamFrame(f) => match self.admit(side, peer, f) {
                Admission::Forward => self.forward(side, f, true),
                Admission::Drop => {}
                // its bytes come back as junk (or inside later frames) from the stream splitter
                Admission::NotAFrame => return false,
            },
            Received::Oversized(n) => {
                self.counters.junk_bytes.fetch_add(n as u64, Ordering::Relaxed);
            }
            Received::StreamJunk(j) => {
                self.counters.junk_bytes.fetch_add(j.len() as u64, Ordering::Relaxed);
                if self.junk_passes(side) {
                    self.forward(side, j, false);
                }
            }
        }
        true
    }

    /// Monitor mode is a transparent relay: bytes that are no frame pass as well, except from the
    /// GCS when signing is checked (only authenticated frames may come in from there).
    fn junk_passes(&self, side: Side) -> bool {
        !self.enforce && (self.verifier.is_none() || side == Side::Vehicle)
    }

    fn on_datagram(&self, side: Side, peer: Peer, d: &[u8]) {
        let mut keep = Ranges::default();
        // A candidate the inspector finds corrupt is bytes, not a frame: the splitter rescans
        // from the byte after its start marker, so it cannot swallow the frames behind it.
        split_datagram_resync(d, |p| match p {
            Piece::Frame(a, b) => match self.admit(side, peer, &d[a..b]) {
                Admission::Forward => {
                    keep.push(a, b);
                    true
                }
                Admission::Drop => true,
                Admission::NotAFrame => false,
            },
            Piece::Garbage(a, b) => {
                self.counters.junk_bytes.fetch_add((b - a) as u64, Ordering::Relaxed);
                if self.junk_passes(side) {
                    keep.push(a, b);
                }
                true
            }
        });
        let resign = side == Side::Gcs && self.sign_forwarded;
        for &(a, b) in keep.iter() {
            self.forward(side, &d[a..b], resign);
        }
    }

    /// Sends bytes received on `from` to the other side; `framed` says they are whole frames
    /// (re-signed toward the vehicle when configured), counted per frame.
    fn forward(&self, from: Side, bytes: &[u8], framed: bool) {
        let Some(out) = self.out(from.other()) else { return };
        if from == Side::Gcs && framed && self.sign_forwarded {
            if let Some(signer) = &self.signer {
                let mut buf = Vec::with_capacity(bytes.len() + 16 * 13);
                let mut one = Vec::with_capacity(280);
                let mut s = lock(signer);
                split_datagram(bytes, |p| {
                    if let Piece::Frame(a, b) = p {
                        if let Some(fr) = FrameRef::new(&bytes[a..b]) {
                            if s.sign_into(&fr, timestamp_now(), &mut one) {
                                buf.extend_from_slice(&one);
                            }
                        }
                    }
                });
                drop(s);
                if !buf.is_empty() {
                    out.send_all(&buf);
                }
                return;
            }
        }
        out.send_all(bytes);
    }

    /// Decides whether one length-cut candidate frame goes on. Side effects: counters, log, tlog,
    /// alerts, enforce-mode answers. `NotAFrame` (bad checksum, unknown incompatibility flag) is
    /// counted as malformed and leaves the forwarding of its bytes to the caller (as garbage).
    fn admit(&self, side: Side, peer: Peer, bytes: &[u8]) -> Admission {
        let c = &self.counters;
        let Some(fr) = FrameRef::new(bytes) else { return Admission::NotAFrame };
        let verify = if side == Side::Gcs { self.verifier.as_ref() } else { None };
        // With signing, integrity is checked before the signature so that a corrupt frame is
        // resynchronised over (not counted as a forgery); otherwise the inspector checks it.
        // Counted and recorded in the tlog once known to be a frame: a rejected candidate's bytes
        // are scanned again, and its good frames must not appear twice.
        let recorded = verify.is_some();
        if recorded {
            if !lock(&self.inspector).is_intact(fr) {
                return self.not_a_frame();
            }
            self.record(side, bytes);
        }
        {
            if let Some(v) = verify {
                if let Err(why) = lock(v).check(&fr, timestamp_now()) {
                    let n = c.signing_rejected.fetch_add(1, Ordering::Relaxed);
                    if n < MAX_LOGGED_SIG_REJECTS {
                        self.log_line(json!({"t_us": unix_micros(), "from": side.as_str(), "action": "dropped",
                            "kind": "signing", "reason": why.as_str(), "sysid": fr.sysid(), "compid": fr.compid(),
                            "msgid": fr.msgid()}));
                    }
                    return Admission::Drop;
                }
            }
        }
        if fr.is_v2() && fr.msgid() == SETUP_SIGNING_ID {
            // It carries a secret key: never forwarded, whatever the mode (MAVLink signing spec).
            c.setup_signing_dropped.fetch_add(1, Ordering::Relaxed);
            if !recorded {
                self.record(side, bytes);
            }
            return Admission::Drop;
        }
        let Ok(verdict) = lock(&self.inspector).inspect(side, fr) else {
            return self.not_a_frame();
        };
        if !recorded {
            self.record(side, bytes);
        }
        if side == Side::Vehicle && fr.msgid() == 0 && self.vehicle_ids.load(Ordering::Relaxed) == 0
        {
            let packed = (u64::from(fr.sysid()) << 8 | u64::from(fr.compid())) + 1;
            self.vehicle_ids.store(packed, Ordering::Relaxed);
        }
        match verdict {
            Verdict::Accept | Verdict::Ignore => {
                c.forwarded[side.other().index()].fetch_add(1, Ordering::Relaxed);
                Admission::Forward
            }
            Verdict::Unverifiable(_) => {
                c.unverifiable.fetch_add(1, Ordering::Relaxed);
                c.forwarded[side.other().index()].fetch_add(1, Ordering::Relaxed);
                Admission::Forward
            }
            Verdict::Violation(v) => self.on_violation(side, peer, fr, &v),
        }
    }

    /// Counts, logs, reports and (in enforce mode) answers a violation.
    fn on_violation(&self, side: Side, peer: Peer, fr: FrameRef<'_>, v: &Violation) -> Admission {
        let c = &self.counters;
        c.violations.fetch_add(1, Ordering::Relaxed);
        let summary = v.summary();
        let action = if self.enforce { "dropped" } else { "forwarded" };
        self.log_line(json!({"t_us": unix_micros(), "from": side.as_str(), "action": action,
            "kind": "violation", "summary": summary, "sysid": fr.sysid(), "compid": fr.compid(),
            "msgid": fr.msgid(), "frame": hex(fr.bytes), "violation": v}));
        if self.alert_gcs {
            self.alert(&summary);
        }
        let dropped = self.enforce;
        self.events.emit(|| GuardEvent::Violation { from: side, dropped, summary });
        if self.enforce {
            c.dropped_violations.fetch_add(1, Ordering::Relaxed);
            for r in v.replies() {
                self.send_reply(r, side, peer);
            }
            Admission::Drop
        } else {
            c.forwarded[side.other().index()].fetch_add(1, Ordering::Relaxed);
            Admission::Forward
        }
    }

    /// Counts a received frame and appends it to the tlog.
    fn record(&self, side: Side, bytes: &[u8]) {
        self.counters.rx[side.index()].fetch_add(1, Ordering::Relaxed);
        if let Some(t) = &self.tlog {
            let mut t = lock(t);
            let _ = t.write_all(&unix_micros().to_be_bytes()).and_then(|_| t.write_all(bytes));
        }
    }

    fn not_a_frame(&self) -> Admission {
        self.counters.malformed.fetch_add(1, Ordering::Relaxed);
        if self.enforce {
            self.counters.dropped_malformed.fetch_add(1, Ordering::Relaxed);
        }
        Admission::NotAFrame
    }

    /// Sends a guard-made message. An answer to the side the violating frame came from goes back
    /// to exactly that peer; one to the other side goes to all its peers.
    fn send_reply(&self, r: &Reply, from: Side, peer: Peer) {
        let Some(out) = self.out(r.to) else { return };
        let seq = self.own_seq.fetch_add(1, Ordering::Relaxed);
        let mut frame = r.encode_v2(seq);
        if r.to == Side::Vehicle {
            if let Some(signer) = &self.signer {
                let mut signed = Vec::with_capacity(frame.len() + 13);
                if let Some(fr) = FrameRef::new(&frame) {
                    if lock(signer).sign_into(&fr, timestamp_now(), &mut signed) {
                        frame = signed;
                    }
                }
            }
        }
        let ok = if r.to == from { out.send_to(peer, &frame) } else { out.send_all(&frame) > 0 };
        if ok {
            self.counters.replies_sent.fetch_add(1, Ordering::Relaxed);
        }
    }

    fn alert(&self, summary: &str) {
        if !within_rate(&self.alert_window, MAX_ALERTS_PER_SECOND) {
            self.counters.alerts_suppressed.fetch_add(1, Ordering::Relaxed);
            return;
        }
        let packed = self.vehicle_ids.load(Ordering::Relaxed);
        let (sysid, compid) =
            if packed == 0 { (1, 1) } else { (((packed - 1) >> 8) as u8, (packed - 1) as u8) };
        let r = statustext(SEVERITY_WARNING, &format!("vouch: {summary}"), sysid, compid);
        let Some(out) = self.out(Side::Gcs) else { return };
        let seq = self.own_seq.fetch_add(1, Ordering::Relaxed);
        if out.send_all(&r.encode_v2(seq)) > 0 {
            self.counters.alerts_sent.fetch_add(1, Ordering::Relaxed);
        }
    }

    fn log_line(&self, v: serde_json::Value) {
        if let Some(l) = &self.log {
            let mut l = lock(l);
            // one complete line per record, flushed: a killed guard leaves a readable log
            let mut line = v.to_string();
            line.push('\n');
            let _ = l.write_all(line.as_bytes()).and_then(|_| l.flush());
        }
    }
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// A guard that is running; dropping it without [`RunningGuard::stop`] leaves threads running
/// until process exit.
pub struct RunningGuard {
    core: Arc<Core>,
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
    saver: Option<StateSaver>,
    /// Local address of the GCS endpoint (useful with port 0).
    pub gcs_addr: Option<SocketAddr>,
    /// Local address of the vehicle endpoint.
    pub vehicle_addr: Option<SocketAddr>,
}

impl RunningGuard {
    /// The counters now.
    pub fn counters(&self) -> CounterSnapshot {
        self.core.counters.snapshot()
    }

    /// Stops the readers (within one poll interval), flushes the logs and returns the counters.
    pub fn stop(self) -> CounterSnapshot {
        self.stop.store(true, Ordering::Relaxed);
        for t in self.threads {
            let _ = t.join();
        }
        if self.saver.is_some_and(|s| s.finish().is_err()) {
            self.core.counters.signing_state_failures.fetch_add(1, Ordering::Relaxed);
        }
        for w in [&self.core.tlog, &self.core.log].into_iter().flatten() {
            let _ = lock(w).flush();
        }
        self.core.counters.snapshot()
    }
}

/// Opens both endpoints and starts forwarding.
pub fn start(cfg: GuardConfig, inspector: Box<dyn Inspector>) -> io::Result<RunningGuard> {
    let create = |p: &Option<PathBuf>| -> io::Result<Option<Mutex<BufWriter<File>>>> {
        p.as_ref().map(|p| File::create(p).map(|f| Mutex::new(BufWriter::new(f)))).transpose()
    };
    // With a state file, signed frames accepted before a restart stay refused after it.
    let verifier = match &cfg.signing {
        Some(s) => Some(Arc::new(Mutex::new(match &s.state_file {
            Some(p) => resume(s.key.clone(), p).map_err(|e| io::Error::other(e.to_string()))?,
            None => Verifier::new(s.key.clone()),
        }))),
        None => None,
    };
    let core = Arc::new(Core {
        enforce: cfg.enforce,
        alert_gcs: cfg.alert_gcs,
        inspector: Mutex::new(inspector),
        verifier: verifier.clone(),
        signer: cfg.signing.as_ref().map(|s| Mutex::new(Signer::new(s.key.clone(), s.link_id))),
        sign_forwarded: cfg.signing.as_ref().is_some_and(|s| s.sign_to_vehicle),
        egress: [OnceLock::new(), OnceLock::new()],
        counters: Counters::default(),
        log: create(&cfg.log_path)?,
        tlog: create(&cfg.tlog_path)?,
        own_seq: AtomicU8::new(0),
        vehicle_ids: AtomicU64::new(0),
        alert_window: Mutex::new((Instant::now(), 0)),
        events: Events::new(cfg.events.clone()),
    });
    let saver = match (&verifier, cfg.signing.as_ref().and_then(|s| s.state_file.clone())) {
        (Some(v), Some(path)) => {
            let c = core.clone();
            let failed = move |_: &_| {
                c.counters.signing_state_failures.fetch_add(1, Ordering::Relaxed);
            };
            Some(StateSaver::start(v.clone(), path, failed)?)
        }
        _ => None,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let mut threads = vec![];
    let mut addrs = [None, None];
    for (side, ep) in [(Side::Gcs, &cfg.gcs), (Side::Vehicle, &cfg.vehicle)] {
        let c = core.clone();
        let handler: link::Handler = Arc::new(move |peer, rx| c.on_received(side, peer, rx));
        let opened = match link::open(ep, side.as_str(), handler, stop.clone()) {
            Ok(o) => o,
            Err(e) => {
                stop.store(true, Ordering::Relaxed);
                threads.into_iter().for_each(|t: JoinHandle<()>| {
                    let _ = t.join();
                });
                return Err(io::Error::new(
                    e.kind(),
                    format!("{} endpoint {ep}: {e}", side.as_str()),
                ));
            }
        };
        let _ = core.egress[side.index()].set(opened.egress);
        addrs[side.index()] = opened.local_addr;
        threads.extend(opened.threads);
    }
    Ok(RunningGuard { core, stop, threads, saver, gcs_addr: addrs[0], vehicle_addr: addrs[1] })
}
