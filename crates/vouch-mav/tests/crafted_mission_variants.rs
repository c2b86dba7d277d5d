//! Mission microservice variants that real stacks use (recorded in ../shared/mavlink/tlogs_wild2)
//! and their limits: a clear acknowledged after the count that followed it, guided-mode items,
//! reads beyond the count. Each legitimate form passes; the same shapes used wrongly are still
//! reported.

mod common;
use common::*;
use vouch_mav::monitor::ViolationKind;

const MISSION: u8 = 0;

/// A guided-mode item (`current` = 2 or 3), as ArduPilot takes it outside any upload.
fn guided_item(c: &mut Craft, current: f64) {
    c.gcs(
        "MISSION_ITEM_INT",
        &[("seq", 0.0), ("command", 16.0), ("frame", 3.0), ("current", current), ("z", 20.0)],
    );
}

#[test]
fn clear_acknowledged_after_the_count_that_followed_it_passes() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.gcs("MISSION_CLEAR_ALL", &[]);
    c.count(3, MISSION);
    c.ack(0, MISSION); // the clear's answer
    c.transfer(0..3, MISSION, true);
    c.ack(0, MISSION);
    let r = c.check();
    assert_clean(&r);
    // one session: the clear, and the upload behind it
    assert_eq!(
        r.summary.protocol("mission_upload").map(|p| (p.started, p.completed)),
        Some((1, 1))
    );
}

#[test]
fn an_accepted_right_after_the_count_without_a_clear_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.count(3, MISSION);
    c.ack(0, MISSION);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.protocol, "mission_upload");
    assert_eq!(v.predicate.as_deref(), Some("curr == n"));
}

#[test]
fn only_one_ack_is_due_after_a_clear() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.gcs("MISSION_CLEAR_ALL", &[]);
    c.count(3, MISSION);
    c.ack(0, MISSION);
    c.ack(0, MISSION);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!((v.predicate.as_deref(), value(v, "curr")), (Some("curr == n"), "0"));
}

#[test]
fn an_accepted_after_some_items_is_still_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.count(3, MISSION);
    c.transfer(0..1, MISSION, false);
    c.ack(0, MISSION);
    let r = c.check();
    assert_eq!(only_violation(&r).predicate.as_deref(), Some("curr == n"));
}

#[test]
fn guided_items_answered_by_one_ack_pass() {
    let Some(mut c) = Craft::with_heartbeats(true, 4) else { return };
    for current in [2.0, 3.0, 2.0] {
        guided_item(&mut c, current);
        c.ack(0, MISSION);
    }
    guided_item(&mut c, 2.0);
    guided_item(&mut c, 2.0); // sent again, the answer was late
    c.ack(1, MISSION); // MAV_MISSION_ERROR: not in a guided mode
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_upload").map(|p| p.completed), Some(4));
}

#[test]
fn an_item_with_current_0_or_1_outside_an_upload_is_still_refused() {
    for current in [0.0, 1.0] {
        let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
        guided_item(&mut c, current);
        let r = c.check();
        let v = only_violation(&r);
        assert_eq!((v.protocol.as_str(), v.kind), ("mission_upload", ViolationKind::NoSession));
    }
}

#[test]
fn reading_home_beyond_an_empty_count_passes() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.gcs("MISSION_REQUEST_LIST", &[]);
    c.uav("MISSION_COUNT", &[("count", 0.0)]);
    c.gcs("MISSION_REQUEST", &[("seq", 0.0)]);
    c.uav("MISSION_ITEM", &[("seq", 0.0), ("command", 16.0)]);
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_download").map(|p| p.started), Some(1));
}

#[test]
fn an_item_beyond_the_count_that_nobody_asked_for_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.gcs("MISSION_REQUEST_LIST", &[]);
    c.uav("MISSION_COUNT", &[("count", 1.0)]);
    c.gcs("MISSION_REQUEST", &[("seq", 0.0)]);
    c.uav("MISSION_ITEM", &[("seq", 0.0), ("command", 16.0)]);
    c.uav("MISSION_ITEM", &[("seq", 5.0), ("command", 16.0)]);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.protocol, "mission_download");
    assert_eq!(v.predicate.as_deref(), Some("beyond > 0"));
}

fn partial(c: &mut Craft, first: f64, last: f64) {
    c.gcs("MISSION_WRITE_PARTIAL_LIST", &[("start_index", first), ("end_index", last)]);
}

#[test]
fn partial_write_with_a_rerequest_passes() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.upload(5, MISSION, false);
    partial(&mut c, 2.0, 3.0);
    c.request(2, MISSION, false);
    c.item(2, MISSION);
    c.request(3, MISSION, false);
    c.request(3, MISSION, false); // re-request after a timeout
    c.item(3, MISSION);
    c.ack(0, MISSION);
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_upload").map(|p| p.completed), Some(2));
}

#[test]
fn partial_write_accepted_before_its_last_item_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    partial(&mut c, 1.0, 4.0);
    c.request(1, MISSION, false);
    c.item(1, MISSION);
    c.ack(0, MISSION);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.predicate.as_deref(), Some("curr == last + 1"));
    assert_eq!((value(v, "curr"), value(v, "last")), ("2", "4"));
}

#[test]
fn partial_write_item_outside_its_range_is_reported() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    partial(&mut c, 1.0, 2.0);
    c.request(1, MISSION, false);
    c.item(1, MISSION);
    c.item(4, MISSION); // never requested
    let r = c.check();
    assert_eq!(only_violation(&r).protocol, "mission_upload");
}

#[test]
fn command_in_progress_then_cancelled_passes() {
    let Some(mut c) = Craft::with_heartbeats(true, 4) else { return };
    // A long-running command: MAV_CMD_PREFLIGHT_CALIBRATION.
    c.gcs("COMMAND_LONG", &[("command", 241.0), ("param1", 1.0)]);
    c.uav("COMMAND_ACK", &[("command", 241.0), ("result", 5.0), ("progress", 10.0)]); // IN_PROGRESS
    c.gcs("COMMAND_LONG", &[("command", 241.0), ("param1", 1.0), ("confirmation", 1.0)]);
    c.gcs("COMMAND_CANCEL", &[("command", 241.0)]);
    c.uav("COMMAND_ACK", &[("command", 241.0), ("result", 6.0)]); // CANCELLED
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("command").map(|p| p.completed), Some(1));
}

#[test]
fn guided_item_acked_while_a_download_waits_for_its_timeout_passes() {
    let Some(mut c) = Craft::with_heartbeats(true, 4) else { return };
    c.gcs("MISSION_REQUEST_LIST", &[]);
    c.uav("MISSION_COUNT", &[("count", 0.0)]);
    guided_item(&mut c, 2.0);
    c.ack(0, MISSION);
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_download").map(|p| p.completed), Some(1));
}
