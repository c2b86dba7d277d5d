//! DATUM case studies II (parameter dependency) and III (parachute preconditions), crafted.

mod common;
use common::*;

const PARACHUTE: f64 = 208.0; // MAV_CMD_DO_PARACHUTE
const RELEASE: f64 = 2.0; // PARACHUTE_RELEASE
const LOITER: u32 = 5;
const ACRO: u32 = 1;
const FLIP: u32 = 14;

fn param_value(c: &mut Craft, id: &str, v: f64) {
    c.param_value(id, v);
}

fn param_set(c: &mut Craft, id: &str, v: f64) {
    c.param_set(id, v);
}

/// PX4-like pitch gains: MC_PITCH_P = 6.5, MC_PITCHRATE_FF = 0.5 (product 3.25).
fn pitch_vehicle() -> Option<Craft> {
    let mut c = Craft::with_heartbeats(false, 0)?;
    param_value(&mut c, "MC_PITCH_P", 6.5);
    param_value(&mut c, "MC_PITCHRATE_FF", 0.5);
    param_value(&mut c, "MC_PITCHRATE_MAX", 3.0);
    Some(c)
}

#[test]
fn case_two_safe_param_set_passes() {
    let Some(mut c) = pitch_vehicle() else { return };
    param_set(&mut c, "MC_PITCHRATE_MAX", 3.2);
    param_value(&mut c, "MC_PITCHRATE_MAX", 3.2);
    param_set(&mut c, "MC_PITCH_P", 7.0); // 3.2 < 7.0 * 0.5
    param_value(&mut c, "MC_PITCH_P", 7.0);
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("datum_param_dependency").unwrap().completed, 2);
    assert_eq!(r.summary.protocol("param_set").unwrap().completed, 2);
}

#[test]
fn case_two_param_set_violating_the_dependency_is_reported() {
    let Some(mut c) = pitch_vehicle() else { return };
    param_set(&mut c, "MC_PITCHRATE_MAX", 200.0);
    let r = c.check();
    let v = only_violation(&r);
    assert_eq!(v.protocol, "datum_param_dependency");
    assert!(
        v.predicate
            .as_deref()
            .unwrap_or("")
            .starts_with("param_value < (PITCH_P_WEIGHT * param.MC_PITCH_P)")
    );
    assert_eq!(value(v, "param_value"), "200");
    assert_eq!(value(v, "param.MC_PITCH_P"), "6.5");
    assert_eq!(value(v, "param.MC_PITCHRATE_FF"), "0.5");
    // answered as the vehicle answers a write: PARAM_VALUE with the value in force (3.0, the
    // last one the vehicle reported), and the vehicle is asked to report it again
    let reply = v.reply.as_ref().expect("reply declared");
    assert_eq!((reply.message.as_str(), reply.to), ("PARAM_VALUE", vouch_mav::Side::Gcs));
    assert!(reply.fields.contains(&("param_value".into(), 3.0)), "{:?}", reply.fields);
    assert_eq!(reply.text_fields, vec![("param_id".to_string(), "MC_PITCHRATE_MAX".to_string())]);
    assert_eq!((reply.from_sys, reply.from_comp, reply.to_sys, reply.to_comp), (1, 1, 255, 190));
    let ask = &v.more_replies[0];
    assert_eq!((ask.message.as_str(), ask.to), ("PARAM_REQUEST_READ", vouch_mav::Side::Vehicle));
    assert_eq!((ask.from_sys, ask.from_comp, ask.to_sys, ask.to_comp), (255, 190, 1, 1));

    // Lowering a gain below what the current maximum needs is caught too (cache was updated by
    // the PARAM_VALUE stream: MC_PITCHRATE_MAX = 3.0 needs MC_PITCH_P * 0.5 > 3.0).
    let Some(mut c) = pitch_vehicle() else { return };
    param_set(&mut c, "MC_PITCH_P", 4.0);
    let v = only_violation(&c.check()).clone();
    assert_eq!(v.step.split(':').next(), Some("pitch_p"));
    assert_eq!(value(&v, "param.MC_PITCHRATE_MAX"), "3");
}

#[test]
fn case_two_weights_are_configurable_and_unknown_params_fail_closed() {
    let Some(mut c) = pitch_vehicle() else { return };
    param_set(&mut c, "MC_PITCHRATE_MAX", 200.0);
    let r = c.check_with(&[("PITCH_P_WEIGHT".into(), 100.0)]); // 650 * 0.5 = 325 > 200
    assert!(r.violations.is_empty());

    let Some(mut c) = Craft::with_heartbeats(false, 0) else {
        return;
    };
    param_set(&mut c, "MC_PITCHRATE_MAX", 1.0); // nothing known about the gains
    let v = only_violation(&c.check()).clone();
    assert_eq!(value(&v, "param.MC_PITCH_P"), "unknown");
}

/// Armed copter in LOITER, 50 m above home, descending at 0.5 m/s, CHUTE_ALT_MIN = 10 m. (The
/// parameter is reported after the vehicle's first heartbeat: before it, nothing shows that
/// system 1 is a vehicle, and its reports are not believed.)
fn chute_vehicle(armed: bool, mode: u32, rel_alt_m: f64, climb_ms: f64) -> Option<Craft> {
    let mut c = Craft::new()?;
    c.heartbeats(armed, mode);
    param_value(&mut c, "CHUTE_ALT_MIN", 10.0);
    c.send(
        UAV,
        "GLOBAL_POSITION_INT",
        &[("relative_alt", rel_alt_m * 1000.0), ("vz", -climb_ms * 100.0)],
    );
    Some(c)
}

fn parachute(c: &mut Craft, action: f64) {
    c.gcs("COMMAND_LONG", &[("command", PARACHUTE), ("param1", action)]);
}

fn chute_violation(armed: bool, mode: u32, alt: f64, climb: f64) -> Option<vouch_mav::Violation> {
    let mut c = chute_vehicle(armed, mode, alt, climb)?;
    parachute(&mut c, RELEASE);
    let r = c.check();
    let v = only_violation(&r).clone();
    assert_eq!(v.protocol, "datum_parachute");
    let reply = v.reply.clone().expect("reply declared");
    assert_eq!(reply.message, "COMMAND_ACK");
    assert!(reply.fields.contains(&("result".into(), 2.0)), "DENIED: {:?}", reply.fields);
    assert!(reply.fields.contains(&("command".into(), PARACHUTE)));
    Some(v)
}

#[test]
fn case_three_release_in_a_safe_state_passes() {
    let Some(mut c) = chute_vehicle(true, LOITER, 50.0, -0.5) else {
        return;
    };
    parachute(&mut c, RELEASE);
    c.uav("COMMAND_ACK", &[("command", PARACHUTE), ("result", 0.0)]);
    let r = c.check();
    assert_clean(&r);
    assert_eq!(r.summary.protocol("datum_parachute").unwrap().completed, 1);
    assert_eq!(r.summary.protocol("command").unwrap().completed, 1);
    // ENABLE / DISABLE are not a release: allowed while disarmed on the ground.
    let Some(mut c) = chute_vehicle(false, LOITER, 0.0, 0.0) else {
        return;
    };
    parachute(&mut c, 1.0);
    assert!(c.check().violations.is_empty());
}

/// Releasing the parachute from the given vehicle state is refused by refinement `predicate`,
/// whose report shows the values `seen`.
fn assert_release_refused(
    armed: bool,
    mode: u32,
    alt: f64,
    climb: f64,
    predicate: &str,
    seen: &[(&str, &str)],
) {
    let Some(v) = chute_violation(armed, mode, alt, climb) else {
        return;
    };
    assert_eq!(v.predicate.as_deref(), Some(predicate));
    for (name, shown) in seen {
        assert_eq!(value(&v, name), *shown);
    }
}

#[test]
fn case_three_release_when_disarmed() {
    assert_release_refused(
        false,
        LOITER,
        50.0,
        -0.5,
        "vehicle.armed",
        &[("vehicle.armed", "false")],
    );
}

#[test]
fn case_three_release_when_ascending() {
    assert_release_refused(
        true,
        LOITER,
        50.0,
        2.0,
        "vehicle.climb <= CHUTE_MAX_CLIMB",
        &[("vehicle.climb", "2")],
    );
}

#[test]
fn case_three_release_in_acro() {
    assert_release_refused(
        true,
        ACRO,
        50.0,
        -0.5,
        "vehicle.mode != ACRO_MODE",
        &[("vehicle.mode", "1")],
    );
}

#[test]
fn case_three_release_in_flip() {
    assert_release_refused(
        true,
        FLIP,
        50.0,
        -0.5,
        "vehicle.mode != FLIP_MODE",
        &[("vehicle.mode", "14")],
    );
}

#[test]
fn case_three_release_below_minimum_altitude() {
    assert_release_refused(
        true,
        LOITER,
        5.0,
        -0.5,
        "vehicle.alt > param.CHUTE_ALT_MIN",
        &[("vehicle.alt", "5"), ("param.CHUTE_ALT_MIN", "10")],
    );
}

#[test]
fn case_three_climb_tolerance_is_configurable() {
    let Some(mut c) = chute_vehicle(true, LOITER, 50.0, 0.3) else {
        return;
    };
    parachute(&mut c, RELEASE);
    assert_eq!(c.check().violations.len(), 1);
    assert!(c.check_with(&[("CHUTE_MAX_CLIMB".into(), 0.5)]).violations.is_empty());
}
