//! The monitor as the guard uses it: frames with their link side, verdicts, encodable replies.

mod common;
use common::*;
use vouch_mav::Side;
use vouch_mav::codec::{FrameSplitter, MessageBuilder, MessageView};
use vouch_mav::monitor::{Monitor, Verdict};

fn frame(c: &Craft, from: (u8, u8), name: &str, fields: &[(&str, f64)]) -> Vec<u8> {
    let mut b = MessageBuilder::new(&c.d, name).unwrap();
    for (f, v) in fields {
        b = b.set(f, *v).unwrap();
    }
    b.frame_v2(0, from.0, from.1)
}

#[test]
fn verdicts_with_link_sides_and_an_encodable_reply() {
    let Some(c) = Craft::new() else { return };
    let mut m = Monitor::with_stdlib(c.d.clone(), &[]).unwrap();
    // Unknown system ids and no heartbeats: the link side decides the roles.
    let gcs = (42, 7);
    let uav = (9, 1);
    let mut t = 1_000_000u64;
    let mut feed = |m: &mut Monitor, bytes: Vec<u8>, from: Option<Side>| {
        t += 1000;
        let mut sp = FrameSplitter::new();
        let mut pos = 0;
        let (range, f) = sp.next(&bytes, &mut pos, &c.d, true).expect("frame");
        assert_eq!(range.len(), bytes.len());
        m.on_frame(&f, from, t)
    };
    let telemetry = frame(&c, uav, "ATTITUDE", &[("roll", 0.1)]);
    assert!(matches!(feed(&mut m, telemetry, Some(Side::Vehicle)), Verdict::Ignore));
    let count = frame(
        &c,
        gcs,
        "MISSION_COUNT",
        &[("count", 2.0), ("target_system", 9.0), ("target_component", 1.0)],
    );
    assert!(matches!(feed(&mut m, count, Some(Side::Gcs)), Verdict::Accept));
    let req = frame(
        &c,
        uav,
        "MISSION_REQUEST_INT",
        &[("seq", 0.0), ("target_system", 42.0), ("target_component", 7.0)],
    );
    assert!(matches!(feed(&mut m, req, Some(Side::Vehicle)), Verdict::Accept));
    let item = frame(
        &c,
        gcs,
        "MISSION_ITEM_INT",
        &[("seq", 0.0), ("target_system", 9.0), ("target_component", 1.0)],
    );
    assert!(matches!(feed(&mut m, item, Some(Side::Gcs)), Verdict::Accept));
    let early_ack = frame(
        &c,
        uav,
        "MISSION_ACK",
        &[("type", 0.0), ("target_system", 42.0), ("target_component", 7.0)],
    );
    let Verdict::Violation(v) = feed(&mut m, early_ack, Some(Side::Vehicle)) else {
        panic!("early ACK must violate")
    };
    assert_eq!(value(&v, "curr"), "1");
    let reply = v.reply.as_ref().unwrap();
    let bytes = reply.encode_v2(5);
    let mut pos = 0;
    let (_, f) = FrameSplitter::new().next(&bytes, &mut pos, &c.d, true).expect("reply decodes");
    assert_eq!((f.sysid, f.compid, f.seq), (9, 1, 5), "reply sent as the vehicle");
    let view = MessageView::of_frame(&f, &c.d).unwrap();
    assert_eq!(view.name(), "MISSION_ACK");
    assert_eq!(view.get_f64("type"), Some(15.0)); // MAV_MISSION_OPERATION_CANCELLED
    assert_eq!(view.get_f64("target_system"), Some(42.0));
    assert_eq!(view.get_f64("target_component"), Some(7.0));
    assert!(v.to_string().contains("failed: curr == n"));
    let json = serde_json::to_value(&*v).unwrap();
    assert_eq!(json["protocol"], "mission_upload");
}

#[test]
fn expire_abandons_idle_sessions() {
    let Some(mut c) = Craft::new() else { return };
    c.heartbeats(false, 0);
    c.count(3, 0);
    let mut m = Monitor::with_stdlib(c.d.clone(), &[]).unwrap();
    let d = c.d.clone();
    for rec in vouch_mav::TlogReader::new(&c.bytes, &d) {
        let v = MessageView::of_frame(&rec.frame, &d).unwrap();
        m.observe(&v, rec.frame.sysid, rec.frame.compid, None, rec.time_us);
    }
    assert_eq!(m.summary().open_sessions, 1);
    m.expire(c.t + 60_000_000);
    let s = m.summary();
    assert_eq!(s.open_sessions, 0);
    assert_eq!(s.protocol("mission_upload").unwrap().abandoned, 1);
}

#[test]
fn a_flood_of_opening_messages_keeps_a_bounded_number_of_sessions() {
    let Some(mut c) = Craft::new() else { return };
    c.heartbeats(false, 0);
    for i in 0..200 {
        c.send_full(
            GCS,
            "PARAM_REQUEST_READ",
            &[("target_system", 1.0), ("target_component", 1.0), ("param_index", -1.0)],
            &[("param_id", &format!("P{i}"))],
        );
    }
    let mut m = Monitor::with_stdlib(c.d.clone(), &[]).unwrap();
    let d = c.d.clone();
    for rec in vouch_mav::TlogReader::new(&c.bytes, &d) {
        let v = MessageView::of_frame(&rec.frame, &d).unwrap();
        assert!(
            !m.observe(&v, rec.frame.sysid, rec.frame.compid, None, rec.time_us).is_violation()
        );
    }
    let s = m.summary();
    assert_eq!(s.open_sessions as usize, vouch_mav::monitor::MAX_SESSIONS_PER_PROTOCOL);
    let pr = s.protocol("param_read").unwrap();
    assert_eq!(pr.started, 200);
    assert_eq!(pr.abandoned, 200 - vouch_mav::monitor::MAX_SESSIONS_PER_PROTOCOL as u64);
}
