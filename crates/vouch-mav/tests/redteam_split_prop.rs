//! Property test of the guard's per-datagram decision in enforce mode, with the real inspector
//! (standard protocols, embedded dialect): any interleaving of good frames and garbage — random
//! bytes, stray start markers, headers of unknown message ids claiming any length (also the bytes
//! of the frames behind them), frames of known ids with a bad checksum, cut-off frames — delivers
//! every good frame, byte for byte and in order, and nothing else. This is the proxy's datagram
//! path: the codec's resynchronising scan, with the inspector judging each length-cut candidate
//! (not a frame → rescan after its start marker; violation → dropped; else forwarded) and garbage
//! dropped.

use proptest::prelude::*;
use vouch_mav::codec::encode::frame_v2_truncated;
use vouch_mav::codec::split::{Piece, split_datagram_resync};
use vouch_mav::codec::{FrameRef, Parse, parse_frame};
use vouch_mav::dialect::Dialect;
use vouch_mav::guard::{Inspector, MonitorInspector};
use vouch_mav::monitor::{Monitor, MonitorSpec, Verdict};
use vouch_mav::{MessageBuilder, Side};

fn dialect() -> Option<Dialect> {
    match Dialect::default_dialect() {
        Ok(d) => Some(d),
        Err(e) => vouch_testkit::missing(vouch_testkit::Need::Shared, &format!("{e}")),
    }
}

/// A fresh inspector with the standard protocols (compiled once).
fn standard() -> MonitorInspector {
    static M: std::sync::OnceLock<Monitor> = std::sync::OnceLock::new();
    let m = M.get_or_init(|| MonitorSpec::default().build().expect("standard monitor"));
    MonitorInspector::new(m.fresh())
}

/// Good frames a GCS sends that no protocol refuses: heartbeats, telemetry requests, harmless
/// commands and parameter reads, in MAVLink 1 and 2 (zero-truncated).
fn good_frame(d: &Dialect, kind: u8, n: u8, v1: bool) -> Vec<u8> {
    let b = match kind % 4 {
        0 => MessageBuilder::new(d, "HEARTBEAT")
            .and_then(|b| b.set("type", 6))
            .and_then(|b| b.set("autopilot", 8)),
        1 => MessageBuilder::new(d, "REQUEST_DATA_STREAM")
            .and_then(|b| b.set("target_system", 1))
            .and_then(|b| b.set("req_message_rate", f64::from(n))),
        2 => MessageBuilder::new(d, "COMMAND_LONG")
            .and_then(|b| b.set("target_system", 1))
            .and_then(|b| b.set("command", 512))
            .and_then(|b| b.set("param1", f64::from(n))),
        _ => MessageBuilder::new(d, "PARAM_REQUEST_READ")
            .and_then(|b| b.set("target_system", 1))
            .and_then(|b| b.set("param_index", f64::from(n))),
    }
    .expect("message fields");
    if v1 { b.frame_v1(n, 255, 190).expect("v1") } else { b.frame_v2(n, 255, 190) }
}

#[derive(Clone, Debug)]
enum Junk {
    Bytes(Vec<u8>),
    /// A MAVLink 2 header of an unknown id (from a range no dialect uses) claiming `len`
    /// payload bytes, then `tail` bytes.
    UnknownHeader {
        id: u32,
        len: u8,
        tail: Vec<u8>,
    },
    /// A whole frame of an unknown id with a plausible checksum.
    UnknownFrame {
        id: u32,
        payload: Vec<u8>,
    },
    /// A good frame of a known id with one byte changed (bad checksum).
    Corrupted {
        kind: u8,
        at: usize,
    },
    /// The first `keep` bytes of a good frame.
    Cut {
        kind: u8,
        keep: usize,
    },
}

fn junk() -> impl Strategy<Value = Junk> {
    let byte = prop_oneof![Just(0xFDu8), Just(0xFEu8), any::<u8>()];
    let unknown_id = 0x00C0_0000u32..0x00FF_FFFF;
    prop_oneof![
        prop::collection::vec(byte, 1..12).prop_map(Junk::Bytes),
        (unknown_id.clone(), any::<u8>(), prop::collection::vec(any::<u8>(), 0..8))
            .prop_map(|(id, len, tail)| Junk::UnknownHeader { id, len, tail }),
        (unknown_id, prop::collection::vec(any::<u8>(), 0..40))
            .prop_map(|(id, payload)| Junk::UnknownFrame { id, payload }),
        (any::<u8>(), 1usize..40).prop_map(|(kind, at)| Junk::Corrupted { kind, at }),
        (any::<u8>(), 1usize..30).prop_map(|(kind, keep)| Junk::Cut { kind, keep }),
    ]
}

fn junk_bytes(d: &Dialect, j: &Junk) -> Vec<u8> {
    match j {
        Junk::Bytes(b) => b.clone(),
        Junk::UnknownHeader { id, len, tail } => {
            let i = id.to_le_bytes();
            let mut h = vec![0xFD, *len, 0, 0, 0, 255, 190, i[0], i[1], i[2]];
            h.extend_from_slice(tail);
            h
        }
        Junk::UnknownFrame { id, payload } => frame_v2_truncated(*id, 0x5A, payload, 0, 255, 190),
        Junk::Corrupted { kind, at } => {
            let mut f = good_frame(d, *kind, 1, false);
            let at = at % f.len();
            f[at.max(1)] ^= 0x21;
            f
        }
        Junk::Cut { kind, keep } => {
            let f = good_frame(d, *kind, 2, false);
            f[..(*keep).min(f.len() - 1)].to_vec()
        }
    }
}

/// The proxy's datagram path in enforce mode: what leaves toward the vehicle.
fn delivered(inspector: &mut MonitorInspector, datagram: &[u8]) -> Vec<(usize, usize)> {
    let mut out = vec![];
    split_datagram_resync(datagram, |p| match p {
        Piece::Frame(a, b) => {
            let fr = FrameRef::new(&datagram[a..b]).expect("length-cut");
            match inspector.inspect(Side::Gcs, fr) {
                Ok(Verdict::Violation(_)) => true,
                Ok(_) => {
                    out.push((a, b));
                    true
                }
                Err(_) => false,
            }
        }
        Piece::Garbage(..) => true,
    });
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 384, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn enforce_mode_delivers_every_good_frame_and_nothing_else(
        items in prop::collection::vec(
            prop_oneof![
                (any::<u8>(), any::<u8>(), any::<bool>()).prop_map(|(k, n, v1)| Ok((k, n, v1))),
                junk().prop_map(Err),
            ],
            1..12,
        )
    ) {
        let Some(d) = dialect() else { return Ok(()) };
        let mut datagram = vec![];
        let mut good = vec![];
        for it in &items {
            match it {
                Ok((k, n, v1)) => {
                    let f = good_frame(&d, *k, *n, *v1);
                    good.push((datagram.len(), datagram.len() + f.len()));
                    datagram.extend_from_slice(&f);
                }
                Err(j) => datagram.extend_from_slice(&junk_bytes(&d, j)),
            }
        }
        // A junk byte run that by chance is a frame of a known id with a valid checksum is a
        // frame as far as anyone can tell: such inputs are outside the property.
        let fake = (0..datagram.len()).any(|p| {
            !good.iter().any(|&(s, _)| s == p)
                && matches!(parse_frame(&datagram[p..], &d, false), Parse::Frame(_))
        });
        prop_assume!(!fake);
        let mut inspector = standard();
        prop_assert_eq!(delivered(&mut inspector, &datagram), good);
    }
}

/// The example, by hand: one datagram holding a header of unknown id 49152 whose length
/// claims the 6 bytes and the good COMMAND_LONG behind it. The command is delivered; with the
/// opt-in to pass unknown ids, the stray header is still refused, because a frame of a known id
/// that verifies starts inside it; a lone unknown frame passes only with the opt-in.
#[test]
fn a_stray_unknown_header_never_hides_the_frame_behind_it() {
    let Some(d) = dialect() else { return };
    let good = good_frame(&d, 2, 7, false);
    let claim = (6 + good.len() - 12) as u8;
    let mut datagram = vec![0xFD, claim, 0, 0, 0, 255, 190, 0x00, 0xC0, 0x00];
    datagram.extend_from_slice(&[1, 2, 3, 4, 5, 6]);
    let at = datagram.len();
    datagram.extend_from_slice(&good);
    let lone = frame_v2_truncated(49_152, 0x5A, &[1, 2, 3], 0, 255, 190);
    for pass in [false, true] {
        let mut inspector = standard().pass_unknown_ids(pass);
        assert_eq!(
            delivered(&mut inspector, &datagram),
            vec![(at, at + good.len())],
            "pass {pass}"
        );
        let lone_delivered = !delivered(&mut inspector, &lone).is_empty();
        assert_eq!(lone_delivered, pass, "a lone unknown frame passes only when opted in");
        // a stray header that ends inside the good frame, after its header: refused too
        let mut short = datagram.clone();
        short[1] = claim - 10;
        short.truncate(at + good.len());
        assert_eq!(delivered(&mut inspector, &short), vec![(at, at + good.len())], "pass {pass}");
    }
}
