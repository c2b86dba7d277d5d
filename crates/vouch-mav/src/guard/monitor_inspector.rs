//! Plugs the protocol monitor (`crate::monitor`) into the proxy as its [`Inspector`].
//!
//! The proxy cuts datagrams by length only; here each cut frame is re-read with the dialect-aware
//! codec (checksum with CRC_EXTRA, incompatibility flags) and handed to the monitor with the side
//! it arrived on. Replies the protocol asks for are turned into guard [`Reply`]s routed back to
//! the peer they address.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{SystemTime, UNIX_EPOCH};

use super::{Finding, FrameRef, Inspector, Reply, Side, Verdict};
use crate::codec::{parse_frame, FrameSplitter, Parse};
use crate::dialect::{load_dialect_file, Dialect};
use crate::monitor::{self, Monitor, Origin};

pub struct MonitorInspector {
    monitor: Monitor,
    dialect: Arc<Dialect>,
    splitter: FrameSplitter,
}

fn now_us() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_micros() as u64).unwrap_or(0)
}

impl Inspector for MonitorInspector {
    fn is_intact(&mut self, frame: FrameRef<'_>) -> bool {
        matches!(parse_frame(frame.bytes, &self.dialect, true), Parse::Frame(f) if f.bytes.len() == frame.bytes.len())
    }

    fn inspect(&mut self, from: Side, frame: FrameRef<'_>) -> Verdict {
        let bytes = frame.bytes;
        let mut pos = 0;
        let Some((range, f)) = self.splitter.next(bytes, &mut pos, &self.dialect, true) else {
            return Verdict::Malformed("checksum, length or incompatibility flags");
        };
        if range.start != 0 || range.end != bytes.len() {
            // bytes before the frame the codec found were not a frame: the cut was wrong
            return Verdict::Malformed("not a frame at the cut position");
        }
        let origin = match from {
            Side::Gcs => Origin::Gcs,
            Side::Vehicle => Origin::Vehicle,
        };
        match self.monitor.on_frame(&f, origin, now_us()) {
            monitor::Verdict::Accept | monitor::Verdict::Ignore => Verdict::Accept,
            monitor::Verdict::Violation(v) => {
                let mut replies = vec![];
                if let Some(r) = &v.reply {
                    let encoded = r.encode_v2(&self.dialect, 0);
                    let def = self.dialect.message(r.msg);
                    if let Some(fr) = FrameRef::new(&encoded) {
                        // the answer goes to whichever side the addressed system sits on
                        let to = if r.to_sys == frame.sysid() { from } else { from.other() };
                        replies.push(Reply {
                            to,
                            msgid: fr.msgid(),
                            crc_extra: def.crc_extra,
                            payload: fr.payload().to_vec(),
                            sysid: r.from_sys,
                            compid: r.from_comp,
                        });
                    }
                }
                // Short enough for STATUSTEXT's 50 bytes in the common cases:
                // "MISSION_ACK: curr == n (curr=60, n=100)"; the log has the full report.
                let msg = v.message.split_whitespace().next().unwrap_or("message");
                let why = v.predicate.clone().unwrap_or_else(|| v.reason.clone());
                let vals: Vec<String> = v.values.iter().map(|(n, x)| format!("{n}={x}")).collect();
                let summary = if vals.is_empty() {
                    format!("{msg}: {why}")
                } else {
                    format!("{msg}: {why} ({})", vals.join(", "))
                };
                let record = serde_json::to_value(&*v).unwrap_or_default();
                Verdict::Violation(Finding { summary, record, replies })
            }
        }
    }
}

fn parse_consts(consts: &[String]) -> Result<Vec<(String, f64)>, String> {
    consts
        .iter()
        .map(|c| {
            let (n, v) =
                c.split_once('=').ok_or_else(|| format!("--set `{c}`: expected NAME=VALUE"))?;
            let v: f64 =
                v.trim().parse().map_err(|_| format!("--set `{c}`: `{v}` is not a number"))?;
            Ok((n.trim().to_string(), v))
        })
        .collect()
}

/// Why the inspector could not be built: unreadable input (exit 2) or a rejected protocol (exit 1).
#[derive(Debug)]
pub enum BuildError {
    Io(String),
    Rejected(String),
}

impl std::fmt::Display for BuildError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BuildError::Io(s) | BuildError::Rejected(s) => f.write_str(s),
        }
    }
}

/// Builds the monitor inspector: the standard library when `protocols` is empty (or
/// `with_stdlib`), plus the given protocol files; `set` holds `NAME=VALUE` constant overrides.
/// Returns it with a one-line description for the start-up banner.
pub fn build(
    dialect: Option<&Path>,
    protocols: &[PathBuf],
    with_stdlib: bool,
    set: &[String],
) -> Result<(Box<dyn Inspector>, String), BuildError> {
    let d = match dialect {
        Some(p) => load_dialect_file(p),
        None => Dialect::default_dialect(),
    }
    .map_err(|e| BuildError::Io(e.to_string()))?;
    let d = Arc::new(d);
    let overrides = parse_consts(set).map_err(BuildError::Io)?;
    let mut sources = if protocols.is_empty() || with_stdlib {
        crate::protocol::stdlib::sources()
    } else {
        vec![]
    };
    for p in protocols {
        let text = std::fs::read_to_string(p).map_err(|e| {
            BuildError::Io(format!("cannot read protocol file {}: {e}", p.display()))
        })?;
        sources.push((p.display().to_string(), text));
    }
    let monitor = Monitor::from_sources(d.clone(), &sources, &overrides)
        .map_err(|e| BuildError::Rejected(format!("{:?}", miette::Report::new(e))))?;
    let names: Vec<String> = monitor.protocols().protocols.iter().map(|p| p.name.clone()).collect();
    let what = format!("{} protocol(s): {}", names.len(), names.join(", "));
    Ok((Box::new(MonitorInspector { monitor, dialect: d, splitter: FrameSplitter::new() }), what))
}
