//! The trust boundary of the tracked vehicle state: what refinements read about the vehicle is
//! learned only from frames on the vehicle side, from a system that side has shown to be a
//! vehicle; a live frame from the GCS side that claims the ids of a component the vehicle side
//! has shown is a violation of its own; offline, sides are derived from heartbeats.

mod common;
use common::*;
use vouch_mav::monitor::ViolationKind;
use vouch_mav::{Side, Verdict};

const PARACHUTE: f64 = 208.0;

fn forgery(v: &Verdict) -> bool {
    matches!(v, Verdict::Violation(x) if x.kind == ViolationKind::Forgery && x.protocol == "trust_boundary")
}

/// A live link with the vehicle armed in LOITER, 50 m up, climbing at 2 m/s, CHUTE_ALT_MIN = 10.
fn climbing() -> Option<Live> {
    let mut l = Live::new()?;
    l.send(Side::Gcs, GCS, "HEARTBEAT", &[("type", 6.0), ("autopilot", 8.0)]);
    l.vehicle_heartbeat(true, 5);
    l.send_full(
        Side::Vehicle,
        UAV,
        "PARAM_VALUE",
        &[("param_value", 10.0), ("param_type", 9.0)],
        &[("param_id", "CHUTE_ALT_MIN")],
    );
    l.send(
        Side::Vehicle,
        UAV,
        "GLOBAL_POSITION_INT",
        &[("relative_alt", 50_000.0), ("vz", -200.0)],
    );
    l.send(Side::Vehicle, UAV, "VFR_HUD", &[("climb", 2.0)]);
    Some(l)
}

fn release(l: &mut Live) -> Verdict {
    let f = [
        ("target_system", 1.0),
        ("target_component", 1.0),
        ("command", PARACHUTE),
        ("param1", 2.0),
    ];
    l.send(Side::Gcs, GCS, "COMMAND_LONG", &f)
}

#[test]
fn state_forged_from_the_gcs_side_is_a_violation_and_is_not_believed() {
    let Some(mut l) = climbing() else { return };
    // the ids of the vehicle's autopilot (or its component 0) from the GCS side: forgeries
    assert!(forgery(&l.send(Side::Gcs, UAV, "VFR_HUD", &[("climb", -1.0)])));
    let high_and_sinking = [("relative_alt", 100_000.0), ("vz", 100.0)];
    assert!(forgery(&l.send(Side::Gcs, UAV, "GLOBAL_POSITION_INT", &high_and_sinking)));
    // a component of the vehicle's system that the vehicle side never showed (a companion
    // computer on a ground endpoint): a ground sender like any other — not a forgery, and
    // never believed about the vehicle (the release below still sees the real climb)
    assert!(!forgery(&l.send(Side::Gcs, (1, 250), "GLOBAL_POSITION_INT", &high_and_sinking)));
    assert!(forgery(&l.send(
        Side::Gcs,
        (1, 0),
        "HEARTBEAT",
        &[("type", 2.0), ("autopilot", 3.0), ("base_mode", 129.0)]
    )));
    let pv = [("param_value", 0.0), ("param_type", 9.0)];
    assert!(forgery(&l.send_full(
        Side::Gcs,
        UAV,
        "PARAM_VALUE",
        &pv,
        &[("param_id", "CHUTE_ALT_MIN")]
    )));
    // an autopilot heartbeat of a system nobody has seen yet, from the GCS side
    assert!(forgery(&l.send(Side::Gcs, (7, 1), "HEARTBEAT", &[("type", 2.0), ("autopilot", 3.0)])));
    // the state is still the vehicle's own: the release is refused for the real climb rate
    let Verdict::Violation(v) = release(&mut l) else { panic!("release must be refused") };
    assert_eq!(v.protocol, "datum_parachute");
    assert_eq!(value(&v, "vehicle.climb"), "2");
    let s = l.m.summary();
    assert_eq!((s.forgeries, s.violations), (5, 6));
}

#[test]
fn before_the_vehicle_is_known_nothing_is_learned_from_the_gcs_side() {
    let Some(mut l) = Live::new() else { return };
    // no vehicle heartbeat yet: system 1 is nobody's, so this is no forgery, but no state either
    let v = l.send(
        Side::Gcs,
        UAV,
        "GLOBAL_POSITION_INT",
        &[("relative_alt", 100_000.0), ("vz", 100.0)],
    );
    assert!(matches!(v, Verdict::Ignore), "{v:?}");
    l.send(Side::Gcs, UAV, "VFR_HUD", &[("climb", -1.0)]);
    l.vehicle_heartbeat(true, 5);
    let Verdict::Violation(v) = release(&mut l) else { panic!("release must be refused") };
    assert_eq!(value(&v, "vehicle.climb"), "unknown");
    assert_eq!(l.m.summary().forgeries, 0);
}

#[test]
fn the_vehicle_side_teaches_only_about_systems_shown_to_be_vehicles() {
    let Some(mut l) = climbing() else { return };
    // a radio (no heartbeat) and a system with a GCS heartbeat on the vehicle link: their ids
    // are no vehicle's, so nothing they report is learned
    l.send(Side::Vehicle, (51, 68), "VFR_HUD", &[("climb", -1.0)]);
    l.send(Side::Vehicle, (200, 1), "HEARTBEAT", &[("type", 6.0), ("autopilot", 8.0)]);
    l.send(Side::Vehicle, (200, 1), "VFR_HUD", &[("climb", -1.0)]);
    assert!(l.m.vehicles().state(51).is_none() && l.m.vehicles().state(200).is_none());
    let Verdict::Violation(v) = release(&mut l) else { panic!("release must be refused") };
    assert_eq!(value(&v, "vehicle.climb"), "2");
    // the vehicle itself reports a safe descent: now the release passes
    l.send(Side::Vehicle, UAV, "VFR_HUD", &[("climb", -0.5)]);
    assert!(matches!(release(&mut l), Verdict::Accept));
}

/// An accepted PARAM_SET does not change the parameter cache: only the vehicle's PARAM_VALUE
/// does (the vehicle may refuse or clamp the write).
#[test]
fn parameter_values_come_only_from_the_vehicle() {
    let Some(mut l) = Live::new() else { return };
    l.vehicle_heartbeat(false, 0);
    let report = |l: &mut Live, id: &str, v: f64| {
        let f = [("param_value", v), ("param_type", 9.0)];
        l.send_full(Side::Vehicle, UAV, "PARAM_VALUE", &f, &[("param_id", id)]);
    };
    report(&mut l, "MC_PITCH_P", 6.5);
    report(&mut l, "MC_PITCHRATE_FF", 0.5);
    report(&mut l, "MC_PITCHRATE_MAX", 3.0);
    let set = |l: &mut Live, id: &str, v: f64| {
        let f = [
            ("target_system", 1.0),
            ("target_component", 1.0),
            ("param_value", v),
            ("param_type", 9.0),
        ];
        l.send_full(Side::Gcs, GCS, "PARAM_SET", &f, &[("param_id", id)])
    };
    // safe: 3.0 < 10 * 0.5 — but until the vehicle confirms, the cache keeps 6.5
    assert!(!set(&mut l, "MC_PITCH_P", 10.0).is_violation());
    let Verdict::Violation(v) = set(&mut l, "MC_PITCHRATE_MAX", 4.0) else { panic!("refused") };
    assert_eq!(value(&v, "param.MC_PITCH_P"), "6.5");
    report(&mut l, "MC_PITCH_P", 10.0);
    assert!(!set(&mut l, "MC_PITCHRATE_MAX", 4.0).is_violation());
    // a name in another case is the same parameter (ArduPilot matches names without case)
    let Verdict::Violation(v) = set(&mut l, "mc_pitchrate_max", 40.0) else { panic!("refused") };
    assert_eq!(v.protocol, "datum_param_dependency");
    // the refusal is answered with the value in force, under the name the GCS used
    let r = v.reply.as_ref().expect("PARAM_VALUE reply");
    assert_eq!(r.message, "PARAM_VALUE");
    assert!(r.fields.contains(&("param_value".into(), 3.0)), "{:?}", r.fields);
    assert_eq!(r.text_fields, vec![("param_id".to_string(), "mc_pitchrate_max".to_string())]);
}

/// Offline, a recording has no sides: a system that sends an autopilot heartbeat is the vehicle
/// (whatever its id), one that sends a GCS heartbeat is a ground station (whatever its id).
#[test]
fn offline_sides_are_derived_from_heartbeats() {
    let Some(mut c) = Craft::new() else { return };
    let gcs = (42, 7);
    let uav = (250, 1);
    c.send(gcs, "HEARTBEAT", &[("type", 6.0), ("autopilot", 8.0)]);
    c.send(uav, "HEARTBEAT", &[("type", 2.0), ("autopilot", 3.0), ("base_mode", 1.0)]);
    // a parachute release from system 42 to the disarmed vehicle 250: refused (disarmed), which
    // needs 42 to be the GCS and 250 the vehicle whose state is read
    let f = [
        ("target_system", 250.0),
        ("target_component", 1.0),
        ("command", PARACHUTE),
        ("param1", 2.0),
    ];
    c.send(gcs, "COMMAND_LONG", &f);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.predicate.as_deref(), Some("vehicle.armed"));
    assert_eq!(value(v, "vehicle.armed"), "false");
    assert_eq!((r.summary.from_gcs, r.summary.from_vehicle), (2, 1));
    assert_eq!(r.one_direction, None);
}

/// A broadcast command (target system 0) reaches every vehicle: it is checked against the only
/// vehicle known, and fails closed when that is not one.
#[test]
fn broadcast_commands_are_checked_against_the_vehicle_they_reach() {
    let Some(mut l) = climbing() else { return };
    let f = [
        ("target_system", 0.0),
        ("target_component", 0.0),
        ("command", PARACHUTE),
        ("param1", 2.0),
    ];
    let Verdict::Violation(v) = l.send(Side::Gcs, GCS, "COMMAND_LONG", &f) else {
        panic!("refused")
    };
    assert_eq!(value(&v, "vehicle.climb"), "2");
    // a second vehicle: a broadcast can no longer be shown safe for all
    l.send(
        Side::Vehicle,
        (2, 1),
        "HEARTBEAT",
        &[("type", 2.0), ("autopilot", 3.0), ("base_mode", 129.0)],
    );
    l.send(Side::Vehicle, UAV, "VFR_HUD", &[("climb", -0.5)]);
    let Verdict::Violation(v) = l.send(Side::Gcs, GCS, "COMMAND_LONG", &f) else {
        panic!("refused")
    };
    assert_eq!(value(&v, "vehicle.armed"), "unknown");
}
