//! Crafted mission traffic (vouch's encoder): the legitimate variants pass, each attack or bug
//! class is reported with the refinement that failed and the values it saw.

mod common;
use common::*;
use vouch_mav::monitor::ViolationKind;

const MISSION: u8 = 0;
const FENCE: u8 = 1;

#[test]
fn upload_of_100_items_passes_and_completes() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.upload(100, MISSION, false);
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_upload").unwrap().completed, 1);
}

#[test]
fn ardupilot_style_upload_with_retries_and_invalid_sequence_passes() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(5, MISSION);
    c.request(0, MISSION, true);
    c.item(0, MISSION);
    c.request(1, MISSION, true);
    c.request(1, MISSION, true); // re-request after a timeout
    c.item(1, MISSION);
    c.item(1, MISSION); // the GCS answered both requests
    c.request(2, MISSION, true);
    c.ack(13, MISSION); // MAV_MISSION_INVALID_SEQUENCE, not terminal (ArduPilot)
    c.item(2, MISSION);
    c.request(2, MISSION, true); // delayed duplicate request of the last item
    c.item(2, MISSION);
    c.transfer(3..5, MISSION, true);
    c.ack(0, MISSION);
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_upload").unwrap().completed, 1);
}

#[test]
fn clear_as_count_zero_and_error_ack_pass() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    for t in [0u8, 1, 2] {
        c.count(0, t);
        c.ack(0, t);
    }
    c.count(800, MISSION);
    c.ack(4, MISSION); // NO_SPACE ends the upload, legitimately
    c.gcs("MISSION_CLEAR_ALL", &[]);
    c.ack(0, MISSION);
    let r = c.check();
    assert_clean(&r);
    // three clears as count 0, the refused upload, and the MISSION_CLEAR_ALL
    assert_eq!(r.summary.protocol("mission_upload").unwrap().completed, 5);
}

#[test]
fn ack_accepted_after_60_of_100_items_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(100, MISSION);
    c.transfer(0..60, MISSION, false);
    c.ack(0, MISSION);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.protocol, "mission_upload");
    assert_eq!(v.kind, ViolationKind::Refinement);
    assert!(v.message.starts_with("MISSION_ACK from 1/1"), "{}", v.message);
    assert_eq!(v.predicate.as_deref(), Some("curr == n"));
    assert_eq!(value(v, "curr"), "60");
    assert_eq!(value(v, "n"), "100");
    assert!(v.step.starts_with("accepted:"), "{}", v.step);
    // Enforce mode: tell the GCS the upload did not complete.
    let reply = v.reply.as_ref().expect("mission_upload declares a reply");
    assert_eq!(reply.message, "MISSION_ACK");
    assert_eq!((reply.to_sys, reply.to_comp), (255, 190));
    assert_eq!((reply.from_sys, reply.from_comp), (1, 1));
    assert!(reply.fields.contains(&("type".to_string(), 15.0)), "{:?}", reply.fields);
}

#[test]
fn datum_case_one_187_announced_121_transferred() {
    let Some(mut c) = Craft::with_heartbeats(true, 10) else {
        return;
    };
    c.count(187, MISSION);
    c.transfer(0..121, MISSION, false);
    c.ack(0, MISSION);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(value(v, "curr"), "121");
    assert_eq!(value(v, "n"), "187");

    // The paper's own formulation (MISSION_REQUEST_INT only, ACK legal when ERROR or curr = N).
    let paper = include_str!("fixtures/datum_case1_paper.vproto");
    let r = c.check_sources(&[("datum_case1_paper.vproto".into(), paper.into())]);
    let v = only_violation(&r);
    assert_eq!(v.protocol, "datum_mission_paper");
    assert_eq!(value(v, "curr"), "121");
    // and the complete upload passes it
    let Some(mut ok) = Craft::with_heartbeats(true, 10) else {
        return;
    };
    ok.upload(187, MISSION, false);
    assert!(ok.check_sources(&[("p".into(), paper.into())]).violations.is_empty());
}

#[test]
fn skipped_request_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(10, MISSION);
    c.transfer(0..3, MISSION, false);
    c.request(4, MISSION, false); // skips seq 3
    let r = c.check();
    let v = only_violation(&r);
    assert!(v.message.starts_with("MISSION_REQUEST_INT"), "{}", v.message);
    assert_eq!(v.predicate.as_deref(), Some("x == curr"));
    assert_eq!(value(v, "x"), "4");
    assert_eq!(value(v, "curr"), "3");
}

#[test]
fn skipped_item_from_the_gcs_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(10, MISSION);
    c.request(0, MISSION, false);
    c.item(0, MISSION);
    c.request(1, MISSION, false);
    c.item(3, MISSION); // answers request 1 with item 3
    let r = c.check();
    let v = only_violation(&r);
    assert!(v.message.starts_with("MISSION_ITEM_INT from 255/190"), "{}", v.message);
    assert_eq!(v.predicate.as_deref(), Some("seq == x"));
    assert_eq!(value(v, "seq"), "3");
    assert_eq!(value(v, "x"), "1");
}

#[test]
fn duplicate_of_an_old_item_beyond_the_retry_rule_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(10, MISSION);
    c.transfer(0..5, MISSION, false);
    c.request(2, MISSION, false); // only the last item (4) may be re-requested
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.predicate.as_deref(), Some("seq == curr - 1"));
    assert_eq!(value(v, "seq"), "2");
    assert_eq!(value(v, "curr"), "5");
}

#[test]
fn too_many_rerequests_break_the_invariant() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(3, MISSION);
    c.request(0, MISSION, false);
    for _ in 0..6 {
        c.request(0, MISSION, false);
    }
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.kind, ViolationKind::Invariant);
    assert_eq!(v.predicate.as_deref(), Some("tries <= MISSION_RETRIES"));
    assert_eq!(value(v, "tries"), "6");
    assert_eq!(value(v, "MISSION_RETRIES"), "5");
}

#[test]
fn item_for_a_mission_type_never_announced_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(3, MISSION);
    c.request(0, MISSION, false);
    c.item(0, FENCE); // a fence item slipped into a mission upload
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.kind, ViolationKind::NoSession);
    assert_eq!(v.protocol, "mission_upload");
    assert!(v.reason.contains("mission_type = 1 (MAV_MISSION_TYPE_FENCE)"), "{}", v.reason);
    assert!(v.reason.contains("outside of any mission_upload session"), "{}", v.reason);

    // Legitimate: the fence is announced first, and runs next to the mission upload.
    let Some(mut ok) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    ok.upload(4, FENCE, false);
    ok.upload(3, MISSION, true);
    let r = ok.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_upload").unwrap().completed, 2);
}

#[test]
fn new_count_restarts_an_upload_and_timeout_abandons() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.count(5, MISSION);
    c.request(0, MISSION, false);
    c.item(0, MISSION);
    c.count(5, MISSION); // the GCS starts over
    c.upload(0, MISSION, false);
    c.count(5, MISSION);
    c.request(0, MISSION, false);
    c.wait_ms(20_000); // gave up
    c.heartbeats(false, 0);
    let r = c.check();
    assert_clean(&r);
    let s = r.summary.protocol("mission_upload").unwrap();
    assert_eq!(s.completed, 1);
    assert_eq!(s.abandoned, 3);
}

#[test]
fn download_with_pipelined_requests_passes_and_early_gcs_ack_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    c.gcs("MISSION_REQUEST_LIST", &[]);
    c.uav("MISSION_COUNT", &[("count", 4.0)]);
    for s in 0..4 {
        c.gcs("MISSION_REQUEST_INT", &[("seq", f64::from(s))]);
    }
    for s in 0..4 {
        c.uav("MISSION_ITEM_INT", &[("seq", f64::from(s)), ("command", 16.0)]);
    }
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_download").unwrap().completed, 1);

    let Some(mut bad) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    bad.gcs("MISSION_REQUEST_LIST", &[]);
    bad.uav("MISSION_COUNT", &[("count", 4.0)]);
    bad.gcs("MISSION_REQUEST_INT", &[("seq", 0.0)]);
    bad.uav("MISSION_ITEM_INT", &[("seq", 0.0)]);
    bad.gcs("MISSION_ACK", &[("type", 0.0)]);
    let v = only_violation(&bad.check()).clone();
    assert_eq!(v.protocol, "mission_download");
    assert_eq!(value(&v, "curr"), "1");
    assert_eq!(value(&v, "n"), "4");
}
