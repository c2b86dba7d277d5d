//! The white-box trace of a NavFn search, in the text format of the oracle contract
//! (docs/navfn-campaign.md, "Oracle contract"):
//!
//! ```text
//! CYCLE k c thr=XXXXXXXX cur=N:HHHHHHHHHHHHHHHH[:i,j,…] next=… over=…
//! PROPEND k cycles=C end=queues_empty|start_reached|cycle_limit thr=XXXXXXXX
//! POT k XXXXXXXX XXXXXXXX …
//! ```
//!
//! `k` = case number, `c` = cycle number from 0, `thr` = float32 bits of `curT`; each buffer is
//! `length:FNV-1a-64 of its cell indices (4 bytes little-endian each, buffer order)`, optionally
//! followed by `:` and the comma-separated cell indices (`cells` detail). One `CYCLE` line per
//! propagation cycle, taken where the paper's debugger breakpoints sat: at the top of the cycle,
//! before the "current and next both empty" exit test (so a run that ends with empty queues
//! shows that last, empty cycle too) and before the current buffer is processed.
//! `PROPEND` says how the loop ended: `cycles` = loop index at exit.

use std::fmt::Write as _;

use crate::core::numeric::{FNV_OFFSET, Fnv1a};
use crate::core::{CycleView, PropagationEnd, PropagationEndView, SearchObserver};

/// How much of each buffer a trace keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceDetail {
    /// Length and hash only (compact; enough to find the first diverging cycle).
    Hash,
    /// Length, hash and the ordered cell list (pinpoints the first diverging cell).
    Cells,
}

/// One priority buffer at one cycle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BufRecord {
    pub len: u32,
    pub hash: u64,
    pub cells: Option<Vec<i32>>,
}

impl BufRecord {
    pub fn of(cells: &[i32], detail: TraceDetail) -> Self {
        BufRecord {
            len: cells.len() as u32,
            hash: buffer_hash(cells),
            cells: (detail == TraceDetail::Cells).then(|| cells.to_vec()),
        }
    }
}

/// FNV-1a-64 over cell indices as 4-byte little-endian integers.
pub fn buffer_hash(cells: &[i32]) -> u64 {
    let mut h = Fnv1a(FNV_OFFSET);
    for c in cells {
        h.bytes(&c.to_le_bytes());
    }
    h.0
}

/// The state at the top of one cycle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CycleRecord {
    pub cycle: u32,
    pub threshold_bits: u32,
    /// current, next, overflow.
    pub bufs: [BufRecord; 3],
}

pub const BUFFER_NAMES: [&str; 3] = ["cur", "next", "over"];

/// How propagation ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EndRecord {
    pub cycles: u32,
    pub end: String,
    pub threshold_bits: u32,
}

pub fn end_name(e: PropagationEnd) -> &'static str {
    match e {
        PropagationEnd::QueuesEmpty => "queues_empty",
        PropagationEnd::StartReached => "start_reached",
        PropagationEnd::CycleLimit => "cycle_limit",
    }
}

/// A whole per-case trace.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Trace {
    pub cycles: Vec<CycleRecord>,
    pub end: Option<EndRecord>,
}

/// A [`SearchObserver`] that records a [`Trace`].
pub struct TraceRecorder {
    pub detail: TraceDetail,
    pub trace: Trace,
}

impl TraceRecorder {
    pub fn new(detail: TraceDetail) -> Self {
        TraceRecorder { detail, trace: Trace::default() }
    }
}

impl SearchObserver for TraceRecorder {
    fn on_cycle(&mut self, v: &CycleView<'_>) {
        let d = self.detail;
        self.trace.cycles.push(CycleRecord {
            cycle: v.cycle as u32,
            threshold_bits: v.threshold.to_bits(),
            bufs: [
                BufRecord::of(v.current, d),
                BufRecord::of(v.next, d),
                BufRecord::of(v.overflow, d),
            ],
        });
    }
    fn on_propagation_end(&mut self, v: &PropagationEndView<'_>) {
        self.trace.end = Some(EndRecord {
            cycles: v.cycles as u32,
            end: end_name(v.end).to_string(),
            threshold_bits: v.threshold.to_bits(),
        });
    }
}

fn write_buf(out: &mut String, name: &str, b: &BufRecord) {
    let _ = write!(out, " {name}={}:{:016x}", b.len, b.hash);
    if let Some(cells) = &b.cells {
        out.push(':');
        for (i, c) in cells.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            let _ = write!(out, "{c}");
        }
    }
}

/// Append the `CYCLE` and `PROPEND` lines of case `k`.
pub fn write_trace(out: &mut String, k: usize, t: &Trace) {
    for c in &t.cycles {
        let _ = write!(out, "CYCLE {k} {} thr={:08x}", c.cycle, c.threshold_bits);
        for (name, b) in BUFFER_NAMES.iter().zip(&c.bufs) {
            write_buf(out, name, b);
        }
        out.push('\n');
    }
    if let Some(e) = &t.end {
        let _ = writeln!(
            out,
            "PROPEND {k} cycles={} end={} thr={:08x}",
            e.cycles, e.end, e.threshold_bits
        );
    }
}

/// Append the `POT` line of case `k`.
pub fn write_pot(out: &mut String, k: usize, pot: &[f32]) {
    let _ = write!(out, "POT {k}");
    for p in pot {
        let _ = write!(out, " {:08x}", p.to_bits());
    }
    out.push('\n');
}

fn parse_hex32(s: &str) -> Result<u32, String> {
    u32::from_str_radix(s, 16).map_err(|_| format!("bad 32-bit hex `{s}`"))
}

fn field<'a>(tok: &'a str, key: &str) -> Result<&'a str, String> {
    tok.strip_prefix(key)
        .and_then(|r| r.strip_prefix('='))
        .ok_or_else(|| format!("expected `{key}=…`, found `{tok}`"))
}

fn parse_buf(s: &str) -> Result<BufRecord, String> {
    let mut parts = s.splitn(3, ':');
    let len = parts
        .next()
        .unwrap_or("")
        .parse::<u32>()
        .map_err(|_| format!("bad buffer length in `{s}`"))?;
    let hash = u64::from_str_radix(parts.next().unwrap_or(""), 16)
        .map_err(|_| format!("bad buffer hash in `{s}`"))?;
    let cells = match parts.next() {
        None => None,
        Some("") => Some(Vec::new()),
        Some(list) => Some(
            list.split(',')
                .map(|c| c.parse::<i32>().map_err(|_| format!("bad cell `{c}`")))
                .collect::<Result<Vec<_>, _>>()?,
        ),
    };
    Ok(BufRecord { len, hash, cells })
}

/// Parse the fields after `CYCLE` (`k c thr=… cur=… next=… over=…`).
pub fn parse_cycle(rest: &[&str]) -> Result<(usize, CycleRecord), String> {
    let [k, c, thr, cur, next, over] = rest else {
        return Err(format!("CYCLE needs 6 fields, found {}", rest.len()));
    };
    let k = k.parse().map_err(|_| format!("bad case number `{k}`"))?;
    let cycle = c.parse().map_err(|_| format!("bad cycle number `{c}`"))?;
    let threshold_bits = parse_hex32(field(thr, "thr")?)?;
    let bufs = [
        parse_buf(field(cur, "cur")?)?,
        parse_buf(field(next, "next")?)?,
        parse_buf(field(over, "over")?)?,
    ];
    Ok((k, CycleRecord { cycle, threshold_bits, bufs }))
}

/// Parse the fields after `PROPEND`.
pub fn parse_propend(rest: &[&str]) -> Result<(usize, EndRecord), String> {
    let [k, cycles, end, thr] = rest else {
        return Err(format!("PROPEND needs 4 fields, found {}", rest.len()));
    };
    let k = k.parse().map_err(|_| format!("bad case number `{k}`"))?;
    let cycles = field(cycles, "cycles")?.parse().map_err(|_| "bad cycles".to_string())?;
    Ok((
        k,
        EndRecord {
            cycles,
            end: field(end, "end")?.to_string(),
            threshold_bits: parse_hex32(field(thr, "thr")?)?,
        },
    ))
}

/// Parse the fields after `POT`.
pub fn parse_pot(rest: &[&str]) -> Result<(usize, Vec<u32>), String> {
    let (k, vals) = rest.split_first().ok_or("POT needs a case number")?;
    let k = k.parse().map_err(|_| format!("bad case number `{k}`"))?;
    Ok((k, vals.iter().map(|v| parse_hex32(v)).collect::<Result<Vec<_>, _>>()?))
}

/// Where two traces first differ.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TraceDivergence {
    pub cycle: u32,
    /// `thr`, `cycle_count`, `end`, or a buffer name.
    pub what: String,
    /// Position in the buffer of the first differing cell, and the two cells (when cell lists
    /// are available on both sides; `None` past the end of a list).
    pub position: Option<usize>,
    pub ours: Option<i32>,
    pub theirs: Option<i32>,
    pub detail: String,
}

/// Compare two traces cycle by cycle; `None` if they agree.
pub fn first_divergence(ours: &Trace, theirs: &Trace) -> Option<TraceDivergence> {
    for (a, b) in ours.cycles.iter().zip(&theirs.cycles) {
        let mk = |what: &str, detail: String| TraceDivergence {
            cycle: a.cycle,
            what: what.to_string(),
            position: None,
            ours: None,
            theirs: None,
            detail,
        };
        if a.cycle != b.cycle {
            return Some(mk("cycle_number", format!("cycle numbers {} vs {}", a.cycle, b.cycle)));
        }
        if a.threshold_bits != b.threshold_bits {
            let (x, y) = (f32::from_bits(a.threshold_bits), f32::from_bits(b.threshold_bits));
            return Some(mk(
                "thr",
                format!(
                    "threshold {x} ({:08x}) vs {y} ({:08x})",
                    a.threshold_bits, b.threshold_bits
                ),
            ));
        }
        for (i, name) in BUFFER_NAMES.iter().enumerate() {
            let (x, y) = (&a.bufs[i], &b.bufs[i]);
            if x.len == y.len && x.hash == y.hash {
                continue;
            }
            let mut d = mk(
                name,
                format!(
                    "{name}: {} cells (hash {:016x}) vs {} cells (hash {:016x})",
                    x.len, x.hash, y.len, y.hash
                ),
            );
            if let (Some(cx), Some(cy)) = (&x.cells, &y.cells) {
                let pos =
                    cx.iter().zip(cy).position(|(p, q)| p != q).unwrap_or(cx.len().min(cy.len()));
                d.position = Some(pos);
                d.ours = cx.get(pos).copied();
                d.theirs = cy.get(pos).copied();
            }
            return Some(d);
        }
    }
    let last = ours.cycles.len().min(theirs.cycles.len()) as u32;
    if ours.cycles.len() != theirs.cycles.len() {
        return Some(TraceDivergence {
            cycle: last,
            what: "cycle_count".into(),
            position: None,
            ours: None,
            theirs: None,
            detail: format!("{} cycles vs {}", ours.cycles.len(), theirs.cycles.len()),
        });
    }
    if let (Some(a), Some(b)) = (&ours.end, &theirs.end)
        && a != b
    {
        return Some(TraceDivergence {
            cycle: a.cycles,
            what: "end".into(),
            position: None,
            ours: None,
            theirs: None,
            detail: format!(
                "end {} after {} cycles vs {} after {}",
                a.end, a.cycles, b.end, b.cycles
            ),
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trace_lines_round_trip() {
        let t = Trace {
            cycles: vec![CycleRecord {
                cycle: 0,
                threshold_bits: 254f32.to_bits(),
                bufs: [
                    BufRecord::of(&[7, 5, 11], TraceDetail::Cells),
                    BufRecord::of(&[], TraceDetail::Cells),
                    BufRecord::of(&[3], TraceDetail::Cells),
                ],
            }],
            end: Some(EndRecord {
                cycles: 1,
                end: "start_reached".into(),
                threshold_bits: 254f32.to_bits(),
            }),
        };
        let mut s = String::new();
        write_trace(&mut s, 4, &t);
        let mut lines = s.lines();
        let l1: Vec<&str> = lines.next().unwrap_or("").split_whitespace().collect();
        assert_eq!(l1[0], "CYCLE");
        let (k, c) = parse_cycle(&l1[1..]).expect("parses");
        assert_eq!(k, 4);
        assert_eq!(c, t.cycles[0]);
        let l2: Vec<&str> = lines.next().unwrap_or("").split_whitespace().collect();
        let (_, e) = parse_propend(&l2[1..]).expect("parses");
        assert_eq!(Some(e), t.end);
        assert!(first_divergence(&t, &t).is_none());
    }

    #[test]
    fn divergence_names_the_first_cell() {
        let a = Trace {
            cycles: vec![CycleRecord {
                cycle: 0,
                threshold_bits: 1,
                bufs: [
                    BufRecord::of(&[1, 2, 3], TraceDetail::Cells),
                    BufRecord::of(&[], TraceDetail::Cells),
                    BufRecord::of(&[], TraceDetail::Cells),
                ],
            }],
            end: None,
        };
        let mut b = a.clone();
        b.cycles[0].bufs[0] = BufRecord::of(&[1, 9, 3], TraceDetail::Cells);
        let d = first_divergence(&a, &b).expect("differs");
        assert_eq!(
            (d.cycle, d.what.as_str(), d.position, d.ours, d.theirs),
            (0, "cur", Some(1), Some(2), Some(9))
        );
        // An empty buffer hashes to the FNV offset basis.
        assert_eq!(buffer_hash(&[]), FNV_OFFSET);
    }
}
