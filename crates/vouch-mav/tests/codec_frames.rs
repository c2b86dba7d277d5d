//! Codec: CRC_EXTRA and layouts against the values of PROTOCOL_FACTS.md (cross-checked there with
//! pymavlink), zero truncation, MAVLink 1/2 round trips, and malformed input.

mod common;
use common::*;
use vouch_mav::codec::{FrameSplitter, MessageBuilder, MessageView, TlogReader, Version};

/// (name, id, CRC_EXTRA, base length, max length) from ../shared/mavlink/PROTOCOL_FACTS.md §1.
const FACTS: &[(&str, u32, u8, u16, u16)] = &[
    ("HEARTBEAT", 0, 50, 9, 9),
    ("PARAM_REQUEST_READ", 20, 214, 20, 20),
    ("PARAM_REQUEST_LIST", 21, 159, 2, 2),
    ("PARAM_VALUE", 22, 220, 25, 25),
    ("PARAM_SET", 23, 168, 23, 23),
    ("MISSION_REQUEST_PARTIAL_LIST", 37, 212, 6, 7),
    ("MISSION_WRITE_PARTIAL_LIST", 38, 9, 6, 7),
    ("MISSION_ITEM", 39, 254, 37, 38),
    ("MISSION_REQUEST", 40, 230, 4, 5),
    ("MISSION_SET_CURRENT", 41, 28, 4, 4),
    ("MISSION_REQUEST_LIST", 43, 132, 2, 3),
    ("MISSION_CLEAR_ALL", 45, 232, 2, 3),
    ("MISSION_ITEM_REACHED", 46, 11, 2, 2),
    ("MISSION_REQUEST_INT", 51, 196, 4, 5),
    ("MISSION_ITEM_INT", 73, 38, 37, 38),
    ("COMMAND_INT", 75, 158, 35, 35),
    ("COMMAND_LONG", 76, 152, 33, 33),
    ("PARAM_EXT_SET", 323, 78, 147, 147),
    ("PARAM_EXT_ACK", 324, 132, 146, 146),
];

#[test]
fn crc_extra_and_lengths_match_the_facts_table() {
    let Some(d) = dialect() else { return };
    for &(name, id, crc, base, max) in FACTS {
        let m = d.by_name(name).unwrap_or_else(|| panic!("{name} missing"));
        assert_eq!(m.id, id, "{name} id");
        assert_eq!(m.crc_extra, crc, "{name} CRC_EXTRA");
        assert_eq!(m.base_len, base, "{name} base length");
        assert_eq!(m.max_len, max, "{name} max length");
    }
    // Wire order: HEARTBEAT puts custom_mode (u32) first; MISSION_ITEM_INT has x, y after params.
    let hb = d.by_name("HEARTBEAT").unwrap();
    assert_eq!(hb.fields[0].name, "custom_mode");
    let it = d.by_name("MISSION_ITEM_INT").unwrap();
    let order: Vec<&str> = it.fields.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(
        &order[..9],
        &["param1", "param2", "param3", "param4", "x", "y", "z", "seq", "command"]
    );
    assert_eq!(order.last(), Some(&"mission_type"));
    assert!(it.field("mission_type").unwrap().is_extension);
}

#[test]
fn enums_resolve_by_name() {
    let Some(d) = dialect() else { return };
    assert_eq!(d.enum_entry("MAV_MISSION_INVALID_SEQUENCE"), Some(("MAV_MISSION_RESULT", 13)));
    assert_eq!(d.enum_entry("MAV_CMD_DO_PARACHUTE"), Some(("MAV_CMD", 208)));
    assert_eq!(d.enum_entry("COPTER_MODE_FLIP"), Some(("COPTER_MODE", 14)));
    assert_eq!(d.enum_value_name("MAV_MISSION_TYPE", 2), Some("MAV_MISSION_TYPE_RALLY"));
}

#[test]
fn zero_truncation_matches_the_measured_frame() {
    let Some(d) = dialect() else { return };
    // PROTOCOL_FACTS: MISSION_COUNT{count=100, mission_type=0, opaque_id=0} is a 16-byte frame
    // with a 4-byte payload.
    let b = MessageBuilder::new(&d, "MISSION_COUNT")
        .unwrap()
        .set("count", 100)
        .unwrap()
        .set("target_system", 1)
        .unwrap()
        .set("target_component", 1)
        .unwrap();
    let f = b.frame_v2(0, 255, 190);
    assert_eq!(f.len(), 16);
    assert_eq!(f[1], 4);
    let mut sp = FrameSplitter::new();
    let mut pos = 0;
    let (range, frame) = sp.next(&f, &mut pos, &d, true).expect("frame");
    assert_eq!(range, 0..16);
    let v = MessageView::of_frame(&frame, &d).unwrap();
    assert_eq!(v.get_f64("count"), Some(100.0));
    assert_eq!(v.get_f64("mission_type"), Some(0.0), "truncated extension reads as 0");
    assert_eq!(v.get_f64("opaque_id"), Some(0.0));
    assert_eq!(v.get_enum_name("mission_type", &d), Some("MAV_MISSION_TYPE_MISSION"));
}

#[test]
fn v1_and_v2_round_trip_every_field_type() {
    let Some(d) = dialect() else { return };
    let b = MessageBuilder::new(&d, "MISSION_ITEM_INT")
        .unwrap()
        .set("param1", 1.5)
        .unwrap()
        .set("x", -473_977_420)
        .unwrap()
        .set("y", 85_455_940)
        .unwrap()
        .set("z", 123.25)
        .unwrap()
        .set("seq", 65_000)
        .unwrap()
        .set("command", 16)
        .unwrap()
        .set("frame", 6)
        .unwrap()
        .set("mission_type", 2)
        .unwrap();
    for (frame, ver) in
        [(b.frame_v2(7, 255, 190), Version::V2), (b.frame_v1(7, 255, 190).unwrap(), Version::V1)]
    {
        let mut sp = FrameSplitter::new();
        let mut pos = 0;
        let (_, f) = sp.next(&frame, &mut pos, &d, true).expect("frame decodes");
        assert_eq!(f.version, ver);
        assert_eq!((f.seq, f.sysid, f.compid, f.msgid), (7, 255, 190, 73));
        let v = MessageView::of_frame(&f, &d).unwrap();
        assert_eq!(v.get_f64("param1"), Some(1.5));
        assert_eq!(v.get_f64("x"), Some(-473_977_420.0));
        assert_eq!(v.get_f64("y"), Some(85_455_940.0));
        assert_eq!(v.get_f64("z"), Some(123.25));
        assert_eq!(v.get_f64("seq"), Some(65_000.0));
        // MAVLink 1 cannot carry extensions.
        let mt = if ver == Version::V1 { 0.0 } else { 2.0 };
        assert_eq!(v.get_f64("mission_type"), Some(mt));
    }
    // Text fields.
    let p = MessageBuilder::new(&d, "PARAM_SET")
        .unwrap()
        .set_str("param_id", "CHUTE_ALT_MIN")
        .unwrap()
        .set("param_value", 12.5)
        .unwrap();
    let fr = p.frame_v2(0, 255, 190);
    let mut pos = 0;
    let (_, f) = FrameSplitter::new().next(&fr, &mut pos, &d, true).unwrap();
    let v = MessageView::of_frame(&f, &d).unwrap();
    assert_eq!(v.get_str("param_id").as_deref(), Some("CHUTE_ALT_MIN"));
    // A 16-character id has no NUL terminator.
    let p = MessageBuilder::new(&d, "PARAM_SET")
        .unwrap()
        .set_str("param_id", "ABCDEFGHIJKLMNOP")
        .unwrap();
    let fr = p.frame_v2(0, 255, 190);
    let mut pos = 0;
    let (_, f) = FrameSplitter::new().next(&fr, &mut pos, &d, true).unwrap();
    assert_eq!(
        MessageView::of_frame(&f, &d).unwrap().get_str("param_id").as_deref(),
        Some("ABCDEFGHIJKLMNOP")
    );
}

fn frame(d: &vouch_mav::Dialect, seq: u8) -> Vec<u8> {
    MessageBuilder::new(d, "HEARTBEAT")
        .unwrap()
        .set("type", 2)
        .unwrap()
        .set("custom_mode", 5)
        .unwrap()
        .frame_v2(seq, 1, 1)
}

#[test]
fn splitter_counts_garbage_bad_crc_truncation_unknown_ids_and_forwards_exact_bytes() {
    let Some(d) = dialect() else { return };
    let good1 = frame(&d, 1);
    let good2 = frame(&d, 2);
    let mut bad_crc = frame(&d, 3);
    let n = bad_crc.len();
    bad_crc[n - 1] ^= 0xFF;
    // Unknown id 0xABCDEF, 3-byte payload, arbitrary checksum.
    let unknown = vec![0xFD, 3, 0, 0, 9, 1, 1, 0xEF, 0xCD, 0xAB, 1, 2, 3, 0x11, 0x22];
    let mut stream = Vec::new();
    stream.extend_from_slice(b"garbage\x00\xFD"); // includes a stray magic byte
    stream.extend_from_slice(&good1);
    stream.extend_from_slice(&bad_crc);
    stream.extend_from_slice(&unknown);
    stream.extend_from_slice(&good2);
    stream.extend_from_slice(&good1[..7]); // truncated at the end
    let mut sp = FrameSplitter::new();
    let mut pos = 0;
    let mut got = Vec::new();
    while let Some((range, f)) = sp.next(&stream, &mut pos, &d, true) {
        assert_eq!(&stream[range.clone()], f.bytes);
        got.push((range, f.msgid, f.msg.is_some()));
    }
    // an unknown id cannot be verified: it is counted and skipped like a bad checksum
    assert_eq!(got.len(), 2, "{got:?}");
    assert_eq!(&stream[got[0].0.clone()], &good1[..]);
    assert_eq!(&stream[got[1].0.clone()], &good2[..]);
    assert!(got.iter().all(|g| g.2));
    let s = sp.stats;
    assert_eq!(s.frames, 2);
    assert_eq!(s.bad_crc, 1);
    assert_eq!(s.unknown_id, 1);
    assert_eq!(s.truncated, 1);
    assert!(s.garbage_bytes >= 9 + (bad_crc.len() + unknown.len()) as u64);
    assert_eq!(pos, stream.len());
}

#[test]
fn splitter_waits_for_the_rest_of_a_stream() {
    let Some(d) = dialect() else { return };
    let f = frame(&d, 1);
    let mut sp = FrameSplitter::new();
    let mut pos = 0;
    assert!(sp.next(&f[..10], &mut pos, &d, false).is_none());
    assert_eq!(pos, 0, "incomplete frame kept for the next read");
    assert!(sp.next(&f, &mut pos, &d, false).is_some());
    assert_eq!(sp.stats.truncated, 0);
}

#[test]
fn signed_frames_keep_their_signature() {
    let Some(d) = dialect() else { return };
    let mut f = frame(&d, 1);
    f[2] |= 1; // incompat: signed — the CRC does not cover flags? it does: recompute below
    let body_end = f.len() - 2;
    let def = d.by_name("HEARTBEAT").unwrap();
    let crc = vouch_mav::crc::frame_crc(&f[1..body_end], def.crc_extra);
    f[body_end..].copy_from_slice(&crc.to_le_bytes());
    f.extend_from_slice(&[7; 13]);
    let mut sp = FrameSplitter::new();
    let mut pos = 0;
    let (r, fr) = sp.next(&f, &mut pos, &d, true).expect("signed frame");
    assert_eq!(r.len(), f.len());
    assert!(fr.is_signed());
    assert_eq!(fr.signature(), Some(&[7u8; 13][..]));
    // An unknown incompatibility flag must be dropped.
    let mut g = frame(&d, 1);
    g[2] = 0x04;
    let mut sp = FrameSplitter::new();
    let mut pos = 0;
    assert!(sp.next(&g, &mut pos, &d, true).is_none());
    assert_eq!(sp.stats.bad_incompat, 1);
}

#[test]
fn tlog_reader_survives_broken_records_and_truncation() {
    let Some(mut c) = Craft::new() else { return };
    c.heartbeats(true, 5);
    let good_len = c.bytes.len();
    // A record holding one stray byte (as in the Rover recording), a frame with a bad CRC,
    // then a good record, then a truncated record.
    let t = 1_700_000_001_000_000u64;
    c.bytes.extend_from_slice(&t.to_be_bytes());
    c.bytes.push(0x0A);
    let mut broken = frame(&c.d, 9);
    broken[12] ^= 0x55;
    c.bytes.extend_from_slice(&t.to_be_bytes());
    c.bytes.extend_from_slice(&broken);
    c.heartbeats(true, 5);
    let full = c.bytes.clone();
    c.bytes.truncate(full.len() - 5);
    let d = c.d.clone();
    let mut r = TlogReader::new(&c.bytes, &d);
    let n = r.by_ref().count();
    assert_eq!(n, 3, "2 + 1 good records before the truncated one");
    let s = r.stats();
    assert_eq!(s.bad_crc, 1);
    assert_eq!(s.truncated, 1);
    assert!(r.skipped_records >= 1);
    assert!(good_len > 0);
    // Every prefix of a recording reads without panicking.
    for cut in (0..full.len()).step_by(7) {
        let _ = TlogReader::new(&full[..cut], &d).count();
    }
}
