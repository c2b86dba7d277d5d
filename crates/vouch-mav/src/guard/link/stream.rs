//! Byte-stream endpoints: a TCP server (each accepted client is a connection of its own), a TCP
//! client that reconnects after its retry time, and a serial port. One reader thread per
//! connection cuts the stream into frames.

use std::io::{self, Read};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use super::serial;
use super::writer::Writer;
use super::{
    Egress, EgressKind, FIXED_STREAM, LinkEvent, MAX_TCP_CLIENTS, OpenedLink, POLL_INTERVAL, Peer,
    ReaderCtx, Received, is_transient,
};
use crate::codec::split::StreamSplitter;

/// How long one connection attempt of a TCP client may take.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(2);

fn streams() -> Arc<Egress> {
    Arc::new(Egress { kind: EgressKind::Streams { conns: Mutex::new(vec![]) } })
}

fn prepare(s: &TcpStream) -> io::Result<TcpStream> {
    s.set_nonblocking(false)?;
    s.set_nodelay(true)?;
    s.set_read_timeout(Some(POLL_INTERVAL))?;
    s.try_clone()
}

pub(super) fn open_tcp_server(rc: ReaderCtx, addr: SocketAddr) -> io::Result<OpenedLink> {
    let listener = TcpListener::bind(addr)?;
    let local = listener.local_addr()?;
    listener.set_nonblocking(true)?;
    let egress = streams();
    let eg = egress.clone();
    let t = thread::Builder::new().name(format!("{}-accept", rc.name)).spawn(move || {
        let mut next_id = 0u64;
        let mut readers: Vec<JoinHandle<()>> = vec![];
        while !rc.stop.load(Ordering::Relaxed) {
            match listener.accept() {
                Ok((s, from)) if eg.stream_count() < MAX_TCP_CLIENTS => {
                    let id = next_id;
                    next_id += 1;
                    let Ok(reader) = prepare(&s) else { continue };
                    if eg.add_stream(id, s, &rc.name).is_err() {
                        continue;
                    }
                    let peer = Peer::Stream(id);
                    rc.sink.link(rc.ep, peer, LinkEvent::Opened { what: from.to_string() });
                    let (rc2, eg2) = (rc.clone(), eg.clone());
                    let spawned =
                        thread::Builder::new().name(format!("{}-tcp", rc.name)).spawn(move || {
                            let why = read_stream(&rc2, reader, peer, true);
                            eg2.remove_stream(id);
                            let ev = LinkEvent::Closed { reason: why, reconnect_in: None };
                            rc2.sink.link(rc2.ep, peer, ev);
                        });
                    if let Ok(r) = spawned {
                        readers.push(r);
                    }
                }
                Ok(_) => {} // over the client limit: dropping the stream closes it
                Err(_) => thread::sleep(POLL_INTERVAL / 4),
            }
            readers.retain(|r| !r.is_finished());
        }
        readers.into_iter().for_each(|r| {
            let _ = r.join();
        });
    })?;
    Ok(OpenedLink { egress, local_addr: Some(local), threads: vec![t] })
}

/// A TCP client: connects, reads until the connection drops, waits `retry` and connects again
/// (`None`: gives up after the first failure or drop). Never fails to open: a server that is not
/// there yet is tried again in the background.
pub(super) fn open_tcp_client(
    rc: ReaderCtx,
    peer_addr: SocketAddr,
    retry: Option<Duration>,
) -> OpenedLink {
    let egress = streams();
    let eg = egress.clone();
    let t = thread::Builder::new().name(format!("{}-tcp", rc.name)).spawn(move || {
        loop {
            let why = match TcpStream::connect_timeout(&peer_addr, CONNECT_TIMEOUT) {
                Ok(s) => match prepare(&s)
                    .and_then(|r| eg.add_stream(FIXED_STREAM, s, &rc.name).map(|()| r))
                {
                    Ok(reader) => {
                        let what = peer_addr.to_string();
                        rc.sink.link(rc.ep, Peer::Fixed, LinkEvent::Opened { what });
                        let why = read_stream(&rc, reader, Peer::Fixed, true);
                        eg.remove_stream(FIXED_STREAM);
                        let again = retry.filter(|_| !rc.stop.load(Ordering::Relaxed));
                        let ev = LinkEvent::Closed { reason: why, reconnect_in: again };
                        rc.sink.link(rc.ep, Peer::Fixed, ev);
                        None
                    }
                    Err(e) => Some(e.to_string()),
                },
                Err(e) => Some(e.to_string()),
            };
            if let Some(reason) = why {
                let ev = LinkEvent::ConnectFailed { reason, reconnect_in: retry };
                rc.sink.link(rc.ep, Peer::Fixed, ev);
            }
            let Some(wait) = retry else { return };
            let until = Instant::now() + wait;
            while Instant::now() < until {
                if rc.stop.load(Ordering::Relaxed) {
                    return;
                }
                thread::sleep(POLL_INTERVAL.min(until.saturating_duration_since(Instant::now())));
            }
            if rc.stop.load(Ordering::Relaxed) {
                return;
            }
        }
    });
    let threads = t.into_iter().collect();
    OpenedLink { egress, local_addr: None, threads }
}

pub(super) fn open_serial(
    rc: ReaderCtx,
    device: &str,
    baud: u32,
    flow_control: bool,
) -> io::Result<OpenedLink> {
    let port = serial::open(device, baud, flow_control)?;
    let reader = port.try_clone().map_err(io::Error::from)?;
    let out = Writer::spawn(format!("{}-write", rc.name), serial::Output(port), None, || {})?;
    let egress = Arc::new(Egress { kind: EgressKind::Serial { out } });
    let t = thread::Builder::new().name(format!("{}-serial", rc.name)).spawn(move || {
        read_stream(&rc, reader, Peer::Fixed, false);
    })?;
    Ok(OpenedLink { egress, local_addr: None, threads: vec![t] })
}

/// Reads until the stop flag, end of stream or an error; returns why it stopped.
fn read_stream<R: Read>(rc: &ReaderCtx, mut reader: R, peer: Peer, zero_is_eof: bool) -> String {
    let mut buf = vec![0u8; 4096];
    let mut splitter = StreamSplitter::default();
    while !rc.stop.load(Ordering::Relaxed) {
        match reader.read(&mut buf) {
            // TCP: 0 = peer closed. Serial: 0 = nothing yet (a timeout is `TimedOut`).
            Ok(0) if zero_is_eof => return "closed by the peer".into(),
            Ok(0) => {}
            Ok(n) => {
                splitter.push_resync(&buf[..n], |piece, is_frame| {
                    let rx = if is_frame {
                        Received::StreamFrame(piece)
                    } else {
                        Received::StreamJunk(piece)
                    };
                    rc.sink.received(rc.ep, peer, rx)
                });
                rc.sink.end_batch();
            }
            Err(e) if is_transient(&e) => {}
            Err(e) => return e.to_string(),
        }
    }
    "guard stopped".into()
}
