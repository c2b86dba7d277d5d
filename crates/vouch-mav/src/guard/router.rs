//! The router core: every frame received on an endpoint is admitted once at the trust boundary
//! it crosses (`admit.rs`), learned as reachable through the connection it came from, and routed
//! by its target to the other connections (`routing.rs`), byte for byte; what a receive batch
//! produces leaves at the batch's end (`outbox.rs`).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::Inspector;
use super::admit::Admission;
use super::config::{GuardConfig, side_word};
use super::counters::{CounterSnapshot, Counters};
use super::dedup::Dedup;
use super::endpoint::Endpoint;
use super::events::{Events, GuardEvent};
use super::link::{self, LinkEvent, Peer, Received, Sink};
use super::outbox;
use super::routing::{FrameInfo, RouteMask, Routes, Targets, indices};
use super::state::{Core, EndpointState, lock};
use crate::codec::FrameRef;
use crate::codec::split::{Piece, split_datagram, split_datagram_resync};
use crate::side::Side;
use crate::signing::state::{StateSaver, resume};
use crate::signing::{Signer, Verifier, timestamp_now};

/// Most endpoints of one router.
pub const MAX_ENDPOINTS: usize = 64;

/// Byte ranges of one received datagram with where each goes; contiguous ranges with the same
/// destinations merge, so that a datagram whose frames all go the same way leaves whole. The
/// first range is stored inline: the common case allocates nothing.
#[derive(Default)]
struct Runs {
    first: Option<Run>,
    more: Vec<Run>,
}

/// Bytes `a..b` holding `frames` frames, for the routes of `mask`.
#[derive(Clone, Copy)]
struct Run {
    a: usize,
    b: usize,
    mask: RouteMask,
    frames: u64,
}

impl Runs {
    fn push(&mut self, a: usize, b: usize, mask: RouteMask, frames: u64) {
        if mask == 0 {
            return;
        }
        let last = if self.more.is_empty() { self.first.as_mut() } else { self.more.last_mut() };
        match last {
            Some(last) if last.b == a && last.mask == mask => {
                last.b = b;
                last.frames += frames;
            }
            Some(_) => self.more.push(Run { a, b, mask, frames }),
            None => self.first = Some(Run { a, b, mask, frames }),
        }
    }

    fn iter(&self) -> impl Iterator<Item = &Run> {
        self.first.iter().chain(self.more.iter())
    }
}

impl Core {
    /// Where an admitted frame from route `from` goes; learns its sender on `from` and counts.
    fn route(&self, from: usize, fr: &FrameRef<'_>) -> RouteMask {
        let info = FrameInfo::of(fr, self.targets.as_ref());
        let (mask, filtered) = {
            let mut routes = lock(&self.routes);
            routes.learn(from, info.sysid, info.compid);
            let (mask, filtered) = routes.route(from, &info);
            (mask, self.endpoints_of(&routes, filtered))
        };
        let c = &self.counters;
        for e in indices(filtered) {
            c.endpoints[e].filtered_out.fetch_add(1, Ordering::Relaxed);
        }
        if mask == 0 {
            c.unrouted.fetch_add(1, Ordering::Relaxed);
        }
        mask
    }

    /// The endpoints (as a mask of endpoint indices) that the routes of `mask` belong to.
    fn endpoints_of(&self, routes: &Routes, mask: RouteMask) -> RouteMask {
        indices(mask).fold(0, |m, i| m | 1 << routes.get(i).endpoint)
    }

    fn on_datagram(&self, ep: usize, from: usize, d: &[u8]) {
        let side = self.endpoints[ep].side;
        let mut runs = Runs::default();
        // A candidate the inspector finds corrupt is bytes, not a frame: the splitter rescans
        // from the byte after its start marker, so it cannot swallow the frames behind it.
        split_datagram_resync(d, |p| match p {
            Piece::Frame(a, b) => match self.admit(ep, from, &d[a..b]) {
                // Admission checked the frame's length; a frame that does not cut is dropped,
                // never forwarded (fail closed).
                Admission::Forward => match FrameRef::new(&d[a..b]) {
                    Some(fr) => {
                        runs.push(a, b, self.route(from, &fr), 1);
                        true
                    }
                    None => true,
                },
                Admission::Drop => true,
                Admission::NotAFrame => false,
            },
            Piece::Garbage(a, b) => {
                self.counters.junk_bytes.fetch_add((b - a) as u64, Ordering::Relaxed);
                if self.junk_passes(side) {
                    runs.push(a, b, lock(&self.routes).of_side(side.other()), 0);
                }
                true
            }
        });
        for r in runs.iter() {
            self.forward(side, r.mask, &d[r.a..r.b], r.frames);
        }
    }

    /// Monitor mode is a transparent relay: bytes that are no frame pass as well (to the other
    /// side's connections: they name no sender to route by), except from the ground when signing
    /// is checked (only authenticated frames may come in from there).
    fn junk_passes(&self, side: Side) -> bool {
        !self.enforce && (self.verifier.is_none() || side == Side::Vehicle)
    }

    /// Queues received bytes (`frames` whole frames, and junk) for the routes of `mask`; frames
    /// from the ground are re-signed toward vehicle routes when configured. Counts frames per
    /// endpoint.
    fn forward(&self, from_side: Side, mask: RouteMask, bytes: &[u8], frames: u64) {
        let resign = from_side == Side::Gcs && self.sign_forwarded && self.signer.is_some();
        let routes = lock(&self.routes);
        let mut vehicle_mask = 0;
        if resign {
            vehicle_mask = indices(mask)
                .filter(|&i| routes.get(i).side == Side::Vehicle)
                .fold(0, |m, i| m | 1 << i);
        }
        let c = &self.counters;
        for e in indices(self.endpoints_of(&routes, mask)) {
            c.endpoints[e].frames_out.fetch_add(frames, Ordering::Relaxed);
            c.forwarded[self.endpoints[e].side.index()].fetch_add(frames, Ordering::Relaxed);
        }
        self.push_locked(&routes, mask & !vehicle_mask, bytes);
        drop(routes);
        if vehicle_mask != 0
            && let Some(signed) = self.resign_all(bytes)
        {
            let routes = lock(&self.routes);
            self.push_locked(&routes, vehicle_mask, &signed);
        }
    }

    /// Queues guard-made bytes for the routes of `mask`; whether any route takes them.
    pub(super) fn push(&self, mask: RouteMask, bytes: &[u8]) -> bool {
        let routes = lock(&self.routes);
        self.push_locked(&routes, mask, bytes);
        mask != 0
    }

    fn push_locked(&self, routes: &Routes, mask: RouteMask, bytes: &[u8]) {
        if mask == 0 || bytes.is_empty() {
            return;
        }
        outbox::with(|o| {
            for i in indices(mask) {
                let r = routes.get(i);
                let datagram = self.egress[r.endpoint].get().is_none_or(|e| e.is_datagram());
                o.push(r.endpoint, r.peer, datagram, bytes);
            }
        });
    }

    /// A signed copy of one guard-made frame, when the guard signs toward the vehicle.
    pub(super) fn sign(&self, frame: &[u8]) -> Option<Vec<u8>> {
        let signer = self.signer.as_ref()?;
        let fr = FrameRef::new(frame)?;
        let mut signed = Vec::with_capacity(frame.len() + 13);
        lock(signer).sign_into(&fr, timestamp_now(), &mut signed).then_some(signed)
    }

    /// The frames of `bytes`, each (re)signed.
    fn resign_all(&self, bytes: &[u8]) -> Option<Vec<u8>> {
        let signer = self.signer.as_ref()?;
        let mut buf = Vec::with_capacity(bytes.len() + 16 * 13);
        let mut one = Vec::with_capacity(280);
        let mut s = lock(signer);
        split_datagram(bytes, |p| {
            if let Piece::Frame(a, b) = p
                && let Some(fr) = FrameRef::new(&bytes[a..b])
                && s.sign_into(&fr, timestamp_now(), &mut one)
            {
                buf.extend_from_slice(&one);
            }
        });
        (!buf.is_empty()).then_some(buf)
    }

    fn route_of(&self, ep: usize, peer: Peer) -> Option<usize> {
        lock(&self.routes).open(ep, peer)
    }

    fn send(&self, ep: usize, peer: Peer, bytes: &[u8]) -> bool {
        let c = &self.counters.endpoints[ep];
        let sent = self.egress[ep].get().is_some_and(|e| e.send(peer, bytes));
        if sent {
            c.bytes_out.fetch_add(bytes.len() as u64, Ordering::Relaxed);
        } else {
            c.send_errors.fetch_add(1, Ordering::Relaxed);
        }
        sent
    }

    fn names(&self) -> Vec<(String, Side, String)> {
        self.endpoints.iter().map(|e| (e.name.clone(), e.side, e.link.to_string())).collect()
    }
}

impl Sink for Core {
    fn received(&self, ep: usize, peer: Peer, rx: Received<'_>) -> bool {
        let Some(from) = self.route_of(ep, peer) else { return true };
        let side = self.endpoints[ep].side;
        match rx {
            Received::Datagram(d) => self.on_datagram(ep, from, d),
            Received::StreamFrame(f) => match self.admit(ep, from, f) {
                Admission::Forward => {
                    // Admission checked the frame's length; one that does not cut is dropped.
                    if let Some(fr) = FrameRef::new(f) {
                        let mask = self.route(from, &fr);
                        self.forward(side, mask, f, 1);
                    }
                }
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
                    let mask = lock(&self.routes).of_side(side.other());
                    self.forward(side, mask, j, 0);
                }
            }
        }
        true
    }

    fn end_batch(&self) {
        outbox::with(|o| o.flush(|ep, peer, bytes| self.send(ep, peer, bytes)));
    }

    fn link(&self, ep: usize, peer: Peer, ev: LinkEvent) {
        let c = &self.counters.endpoints[ep];
        let endpoint = self.endpoints[ep].name.clone();
        match ev {
            LinkEvent::Opened { what } => {
                if peer != Peer::Fixed {
                    lock(&self.routes).open(ep, peer);
                }
                c.connections.fetch_add(1, Ordering::Relaxed);
                c.connects.fetch_add(1, Ordering::Relaxed);
                self.events.link(|| GuardEvent::Connected { endpoint, peer: what });
            }
            LinkEvent::Closed { reason, reconnect_in } => {
                if peer != Peer::Fixed {
                    lock(&self.routes).close(ep, peer);
                }
                let _ = c
                    .connections
                    .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| n.checked_sub(1));
                self.disconnected(endpoint, peer, reason, reconnect_in);
            }
            LinkEvent::ConnectFailed { reason, reconnect_in } => {
                self.disconnected(endpoint, peer, reason, reconnect_in);
            }
        }
    }
}

impl Core {
    fn disconnected(&self, endpoint: String, peer: Peer, reason: String, retry: Option<Duration>) {
        let reconnect_in_s = retry.map(|d| d.as_secs_f64());
        let peer = peer.to_string();
        self.events.link(|| GuardEvent::Disconnected { endpoint, peer, reason, reconnect_in_s });
    }
}

/// A guard that is running; dropping it without [`RunningGuard::stop`] leaves threads running
/// until process exit.
pub struct RunningGuard {
    core: Arc<Core>,
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
    saver: Option<StateSaver>,
    /// Local address of the first ground endpoint (useful with port 0).
    pub gcs_addr: Option<SocketAddr>,
    /// Local address of the first vehicle endpoint.
    pub vehicle_addr: Option<SocketAddr>,
    addrs: Vec<Option<SocketAddr>>,
}

impl RunningGuard {
    /// The counters now.
    pub fn counters(&self) -> CounterSnapshot {
        self.core.counters.snapshot(&self.core.names())
    }

    /// The local address endpoint `name` is bound to (UDP sockets, TCP servers).
    pub fn local_addr(&self, name: &str) -> Option<SocketAddr> {
        let i = self.core.endpoints.iter().position(|e| e.name == name)?;
        self.addrs[i]
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
        self.core.counters.snapshot(&self.core.names())
    }
}

fn create(p: &Option<PathBuf>) -> io::Result<Option<Mutex<BufWriter<File>>>> {
    p.as_ref()
        .map(|p| {
            File::create(p)
                .map(|f| Mutex::new(BufWriter::new(f)))
                .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", p.display())))
        })
        .transpose()
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// The signature verifier; with a state file, signed frames accepted before a restart stay
/// refused after it.
fn verifier(cfg: &GuardConfig) -> io::Result<Option<Arc<Mutex<Verifier>>>> {
    let Some(s) = &cfg.signing else { return Ok(None) };
    let v = match &s.state_file {
        Some(p) => resume(s.key.clone(), p).map_err(|e| io::Error::other(e.to_string()))?,
        None => Verifier::new(s.key.clone()),
    };
    Ok(Some(Arc::new(Mutex::new(v))))
}

/// Saves the replay state every second while it changes (and at [`RunningGuard::stop`]).
fn state_saver(cfg: &GuardConfig, core: &Arc<Core>) -> io::Result<Option<StateSaver>> {
    let (Some(v), Some(path)) =
        (&core.verifier, cfg.signing.as_ref().and_then(|s| s.state_file.clone()))
    else {
        return Ok(None);
    };
    let c = core.clone();
    let failed = move |_: &_| {
        c.counters.signing_state_failures.fetch_add(1, Ordering::Relaxed);
    };
    Ok(Some(StateSaver::start(v.clone(), path, failed)?))
}

fn core(cfg: &GuardConfig, inspector: Box<dyn Inspector>) -> io::Result<Core> {
    let endpoints: Vec<EndpointState> = cfg
        .endpoints
        .iter()
        .map(|e| EndpointState {
            name: e.name.clone(),
            side: e.side,
            link: e.link.clone(),
            inbound_open: e.filters.inbound.is_empty(),
            inbound: e.filters.inbound.clone(),
            warned: AtomicBool::new(false),
        })
        .collect();
    let table: Vec<_> = cfg
        .endpoints
        .iter()
        .map(|e| (e.side, e.filters.outbound.clone(), e.group.clone()))
        .collect();
    let mut routes = Routes::new(&table, cfg.routing.sniffer_sysid);
    for (i, e) in cfg.endpoints.iter().enumerate() {
        if !matches!(e.link, Endpoint::UdpIn(_) | Endpoint::TcpIn(_)) {
            routes.open(i, Peer::Fixed);
        }
    }
    Ok(Core {
        enforce: cfg.enforce,
        alert_gcs: cfg.alert_gcs,
        inspector: Mutex::new(inspector),
        verifier: verifier(cfg)?,
        signer: cfg.signing.as_ref().map(|s| Mutex::new(Signer::new(s.key.clone(), s.link_id))),
        sign_forwarded: cfg.signing.as_ref().is_some_and(|s| s.sign_to_vehicle),
        egress: endpoints.iter().map(|_| OnceLock::new()).collect(),
        counters: Counters::new(endpoints.len()),
        endpoints,
        routes: Mutex::new(routes),
        targets: cfg.routing.dialect.clone().map(Targets::new),
        dedup: cfg.routing.dedup_period.map(|p| Mutex::new(Dedup::new(p))),
        log: create(&cfg.log_path)?,
        tlog: create(&cfg.tlog_path)?,
        own_seq: AtomicU8::new(0),
        vehicle_ids: AtomicU64::new(0),
        alert_window: Mutex::new((Instant::now(), 0)),
        events: Events::new(cfg.events.clone()),
    })
}

/// Opens every endpoint and starts routing. Fails when an endpoint cannot be opened (an address
/// in use, a serial port missing); a TCP client whose server is not there yet retries instead.
pub fn start(cfg: GuardConfig, inspector: Box<dyn Inspector>) -> io::Result<RunningGuard> {
    if cfg.endpoints.is_empty() {
        return Err(invalid("no endpoints".into()));
    }
    if cfg.endpoints.len() > MAX_ENDPOINTS {
        return Err(invalid(format!(
            "{} endpoints (at most {MAX_ENDPOINTS})",
            cfg.endpoints.len()
        )));
    }
    for (i, e) in cfg.endpoints.iter().enumerate() {
        if cfg.endpoints[..i].iter().any(|o| o.name == e.name) {
            return Err(invalid(format!("two endpoints named `{}`", e.name)));
        }
    }
    let core = Arc::new(core(&cfg, inspector)?);
    let saver = state_saver(&cfg, &core)?;
    let stop = Arc::new(AtomicBool::new(false));
    let mut threads: Vec<JoinHandle<()>> = vec![];
    let mut addrs = vec![None; cfg.endpoints.len()];
    for (i, ep) in cfg.endpoints.iter().enumerate() {
        let sink: Arc<dyn Sink> = core.clone();
        match link::open(i, ep, sink, stop.clone()) {
            Ok(opened) => {
                let _ = core.egress[i].set(opened.egress);
                addrs[i] = opened.local_addr;
                threads.extend(opened.threads);
            }
            Err(e) => {
                stop.store(true, Ordering::Relaxed);
                threads.into_iter().for_each(|t| {
                    let _ = t.join();
                });
                let side = side_word(ep.side);
                let msg = format!("{side} endpoint `{}` ({}): {e}", ep.name, ep.link);
                return Err(io::Error::new(e.kind(), msg));
            }
        }
    }
    let first =
        |side: Side| cfg.endpoints.iter().position(|e| e.side == side).and_then(|i| addrs[i]);
    Ok(RunningGuard {
        gcs_addr: first(Side::Gcs),
        vehicle_addr: first(Side::Vehicle),
        core,
        stop,
        threads,
        saver,
        addrs,
    })
}
