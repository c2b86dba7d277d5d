//! Joining mid-stream: an answer to a session whose opener was never seen is *unverifiable* — a
//! class of its own, counted, not a violation — and the protocol says whether a guard passes it
//! or drops it. Also the real stacks' habits: stand-alone mission item reads, and refusals that
//! leave nobody waiting.

mod common;
use common::*;
use vouch_mav::monitor::ViolationKind;
use vouch_mav::{Side, Verdict};

fn item(l: &mut Live, seq: f64) -> Verdict {
    let f =
        [("target_system", 255.0), ("target_component", 190.0), ("seq", seq), ("command", 16.0)];
    l.send(Side::Vehicle, UAV, "MISSION_ITEM_INT", &f)
}

#[test]
fn answers_to_openers_never_seen_are_unverifiable_and_pass() {
    let Some(mut l) = Live::new() else { return };
    l.vehicle_heartbeat(false, 0);
    // the guard started in the middle of a download: items nobody asked for (as far as it saw)
    for seq in 3..6 {
        let Verdict::Unverifiable(v) = item(&mut l, f64::from(seq)) else { panic!("unverifiable") };
        assert_eq!(
            (v.kind, v.protocol.as_str()),
            (ViolationKind::Unverifiable, "mission_download")
        );
        assert!(v.reason.contains("opener was not observed"), "{}", v.reason);
    }
    // an acknowledgement of a command that was not seen; a request of an upload not seen
    let ack = [("command", 400.0), ("result", 0.0)];
    assert!(matches!(l.send(Side::Vehicle, UAV, "COMMAND_ACK", &ack), Verdict::Unverifiable(_)));
    let req = [("target_system", 255.0), ("target_component", 190.0), ("seq", 7.0)];
    assert!(matches!(
        l.send(Side::Vehicle, UAV, "MISSION_REQUEST", &req),
        Verdict::Unverifiable(_)
    ));
    let s = l.m.summary();
    assert_eq!((s.violations, s.unverifiable), (0, 5));
    assert_eq!(s.protocol("mission_download").unwrap().unverifiable, 3);
    assert_eq!(s.protocol("command").unwrap().unverifiable, 1);
    assert_eq!(s.protocol("mission_upload").unwrap().unverifiable, 1);
}

/// The same message from the role that opens the protocol is no answer: a mission item the GCS
/// sends without an announced upload is a violation (fail closed), as before.
#[test]
fn messages_of_the_opening_role_outside_a_session_stay_violations() {
    let Some(mut l) = Live::new() else { return };
    l.vehicle_heartbeat(false, 0);
    let f =
        [("target_system", 1.0), ("target_component", 1.0), ("seq", 0.0), ("mission_type", 1.0)];
    let Verdict::Violation(v) = l.send(Side::Gcs, GCS, "MISSION_ITEM_INT", &f) else {
        panic!("violation")
    };
    assert_eq!((v.kind, v.protocol.as_str()), (ViolationKind::NoSession, "mission_upload"));
}

const STRICT_ANSWERS: &str = "protocol p {\n  roles gcs, uav;\n  unverifiable POLICY;\n  strict uav -> gcs : COMMAND_ACK;\n  gcs -> uav : COMMAND_LONG;\n  uav -> gcs : COMMAND_ACK;\n}\n";

#[test]
fn the_policy_for_unverifiable_frames_is_the_protocols() {
    for (policy, passes) in [("pass", true), ("drop", false)] {
        let Some(mut l) = Live::with_source(&STRICT_ANSWERS.replace("POLICY", policy)) else {
            return;
        };
        l.vehicle_heartbeat(false, 0);
        let v = l.send(Side::Vehicle, UAV, "COMMAND_ACK", &[("command", 400.0)]);
        match (&v, passes) {
            (Verdict::Unverifiable(f), true) => assert_eq!(f.kind, ViolationKind::Unverifiable),
            // dropped like a violation, still of the unverifiable kind, not counted as violation
            (Verdict::Violation(f), false) => assert_eq!(f.kind, ViolationKind::Unverifiable),
            _ => panic!("{policy}: {v:?}"),
        }
        let s = l.m.summary();
        assert_eq!((s.violations, s.unverifiable), (0, 1), "{policy}");
    }
    // without a declaration, unverifiable frames are dropped (fail closed)
    let src = STRICT_ANSWERS.replace("  unverifiable POLICY;\n", "");
    let Some(mut l) = Live::with_source(&src) else { return };
    l.vehicle_heartbeat(false, 0);
    assert!(l.send(Side::Vehicle, UAV, "COMMAND_ACK", &[("command", 400.0)]).is_violation());
}

/// A recording of one side only: the check says so, and exits cleanly (no violation).
#[test]
fn a_one_sided_recording_is_reported_as_such() {
    let Some(mut c) = Craft::new() else { return };
    c.send(UAV, "HEARTBEAT", &[("type", 2.0), ("autopilot", 3.0)]);
    c.uav("MISSION_COUNT", &[("count", 3.0)]);
    for s in 0..3 {
        c.uav("MISSION_ITEM_INT", &[("seq", f64::from(s)), ("command", 16.0)]);
    }
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.one_direction, Some(Side::Vehicle));
    assert_eq!(r.unverifiable.len(), 3);
}

/// Mission Planner reads item 0 (home) every 12 s without listing the mission first.
#[test]
fn stand_alone_item_reads_are_sessions() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    for _ in 0..3 {
        c.gcs("MISSION_REQUEST_INT", &[("seq", 0.0)]);
        c.wait_ms(12);
        c.uav("MISSION_ITEM_INT", &[("seq", 0.0), ("command", 16.0)]);
        c.wait_ms(12_000);
    }
    // a re-request before the answer is a retry of the same read
    c.gcs("MISSION_REQUEST_INT", &[("seq", 0.0)]);
    c.gcs("MISSION_REQUEST_INT", &[("seq", 0.0)]);
    c.uav("MISSION_ITEM_INT", &[("seq", 0.0), ("command", 16.0)]);
    let r = c.check();
    assert_clean(&r);
    assert!(r.unverifiable.is_empty());
    assert_eq!(r.summary.protocol("mission_download").unwrap().completed, 4);
    // a download after a stand-alone read is unaffected
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.gcs("MISSION_REQUEST_INT", &[("seq", 0.0)]);
    c.uav("MISSION_ITEM_INT", &[("seq", 0.0), ("command", 16.0)]);
    c.gcs("MISSION_REQUEST_LIST", &[]);
    c.uav("MISSION_COUNT", &[("count", 2.0)]);
    for s in 0..2 {
        c.gcs("MISSION_REQUEST_INT", &[("seq", f64::from(s))]);
        c.uav("MISSION_ITEM_INT", &[("seq", f64::from(s)), ("command", 16.0)]);
    }
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("mission_download").unwrap().completed, 2);
}

/// No refusal leaves a side waiting: an item the guard drops cancels the upload toward both
/// the GCS and the vehicle; an early ACK from the vehicle (which is done) cancels toward the GCS.
#[test]
fn refusals_answer_every_side_that_would_wait() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.count(3, 0);
    c.request(0, 0, false);
    c.item(2, 0); // wrong item
    let r = c.check();
    let v = only_violation(&r);
    let to: Vec<(&str, Side, u8)> = v
        .replies()
        .map(|r| {
            (r.message.as_str(), r.to, r.fields.iter().find(|f| f.0 == "type").unwrap().1 as u8)
        })
        .collect();
    assert_eq!(to, vec![("MISSION_ACK", Side::Gcs, 15), ("MISSION_ACK", Side::Vehicle, 15)]);
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    c.count(3, 0);
    c.transfer(0..1, 0, false);
    c.ack(0, 0); // early ACCEPTED from the vehicle
    let r = c.check();
    let sides: Vec<Side> = only_violation(&r).replies().map(|r| r.to).collect();
    assert_eq!(sides, vec![Side::Gcs]);
}

/// A refused PARAM_SET is answered with the last value the vehicle reported; when it never
/// reported one, no value is made up: only the vehicle is asked to report it.
#[test]
fn a_refused_parameter_write_with_no_known_value_asks_the_vehicle() {
    let Some(mut c) = Craft::with_heartbeats(false, 0) else { return };
    let f = [
        ("target_system", 1.0),
        ("target_component", 1.0),
        ("param_value", 40.0),
        ("param_type", 9.0),
    ];
    c.send_full(GCS, "PARAM_SET", &f, &[("param_id", "MC_PITCHRATE_MAX")]);
    let r = c.check();
    let v = only_violation(&r);
    let replies: Vec<&str> = v.replies().map(|r| r.message.as_str()).collect();
    assert_eq!(replies, vec!["PARAM_REQUEST_READ"]);
    let ask = v.replies().next().unwrap();
    assert_eq!(ask.text_fields, vec![("param_id".to_string(), "MC_PITCHRATE_MAX".to_string())]);
    assert!(ask.fields.contains(&("param_index".into(), -1.0)));
}
