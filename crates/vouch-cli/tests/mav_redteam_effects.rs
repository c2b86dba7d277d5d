//! Red team, routes to the parachute release: each route by which an ArduCopter can be made to
//! release its parachute is played by a pymavlink ground station against a scripted vehicle that
//! does what ArduPilot does with it (`crates/vouch-mav/tests/redteam/chute_vehicle.py`), once
//! through the real `vouch mav guard` binary in enforce mode and once directly. The vehicle climbs
//! at 2 m/s, 50 m above home, armed: the standard library (`datum.vproto`) forbids a release.
//! Each attack must release the parachute without the guard (so the test can fail) and must not
//! with it. Routes that ArduPilot itself refuses are played too, to show the model says so.
//!
//! Needs `VOUCH_PYTHON` with pymavlink; without it every test prints why and returns, or fails
//! under `VOUCH_REQUIRE_PEERS=1`.

mod mav_redteam_support;

use std::path::Path;

use mav_redteam_support::*;
use serde_json::{Value, json};

/// An ArduCopter with a servo parachute on output 9 (CHUTE_TYPE 10, SERVO9_FUNCTION 27), the
/// auxiliary function "parachute release" on RC channel 7, relays of ArduPilot 4.5 (relay 1 a
/// plain relay, relay 2 the parachute's), armed, 50 m up and climbing at 2 m/s.
const CHUTE_VEHICLE: &[&str] = &[
    "--armed",
    "1",
    "--alt",
    "50",
    "--climb",
    "2",
    "--param",
    "CHUTE_ENABLED=1",
    "--param",
    "CHUTE_TYPE=10",
    "--param",
    "CHUTE_ALT_MIN=10",
    "--param",
    "SERVO9_FUNCTION=27",
    "--param",
    "RC7_OPTION=22",
    "--param",
    "RELAY1_FUNCTION=1",
    "--param",
    "RELAY2_FUNCTION=3",
];

/// An ArduCopter 4.4 whose parachute hangs on relay 0 (CHUTE_TYPE 0): no RELAYn_FUNCTION.
const RELAY_VEHICLE_4_4: &[&str] = &[
    "--version",
    "4.4",
    "--armed",
    "1",
    "--alt",
    "50",
    "--climb",
    "2",
    "--param",
    "CHUTE_ENABLED=1",
    "--param",
    "CHUTE_TYPE=0",
    "--param",
    "CHUTE_ALT_MIN=10",
];

/// One exchange against the vehicle, with or without the guard in between.
struct Run {
    gcs: Value,
    vehicle: Value,
    /// The guard's final counters (through the guard only).
    counters: Option<Value>,
}

fn run(
    py: &Path,
    tag: &str,
    vehicle: &[&str],
    guarded: bool,
    scenario: &str,
    args: &[&str],
) -> Run {
    let dir = scratch(&format!("{tag}-{}", if guarded { "guard" } else { "direct" }));
    let v = Vehicle::start_script(py, &dir, "chute_vehicle.py", vehicle);
    if guarded {
        let guard = Guard::start(&dir, v.port, &["--enforce"]);
        let gcs = gcs(py, &dir, &guard, scenario, args);
        let counters = guard.stop();
        Run { gcs, vehicle: v.finish(), counters: Some(counters) }
    } else {
        let url = format!("udpout:127.0.0.1:{}", v.port);
        let gcs = gcs_at(py, &dir, &url, scenario, args, "direct to the vehicle");
        Run { gcs, vehicle: v.finish(), counters: None }
    }
}

fn released(v: &Value) -> Vec<String> {
    v["released"].as_array().expect("released").iter().map(|r| r.to_string()).collect()
}

/// Plays `scenario` directly and through the guard: the parachute is released without the guard
/// and not with it. Returns the guarded run.
fn attack(tag: &str, vehicle: &[&str], scenario: &str, args: &[&str]) -> Option<Run> {
    let py = python()?;
    let direct = run(&py, tag, vehicle, false, scenario, args);
    assert!(
        !released(&direct.vehicle).is_empty(),
        "without the guard the attack must release the parachute: {} / {}",
        direct.vehicle["not_released"],
        direct.gcs
    );
    let guarded = run(&py, tag, vehicle, true, scenario, args);
    assert_eq!(
        released(&guarded.vehicle),
        Vec::<String>::new(),
        "the guard let the release through; GCS saw {}",
        guarded.gcs
    );
    Some(guarded)
}

/// The mission upload was refused: MISSION_ACK DENIED (or, when the mission protocol refused the
/// item first, OPERATION_CANCELLED) reached the ground station.
fn upload_refused(r: &Run) {
    let acks = r.gcs["mission_acks"].as_array().expect("mission_acks");
    assert!(
        acks.iter().any(|a| *a == json!(14) || *a == json!(15)),
        "the refused upload was answered: {}",
        r.gcs
    );
    let counters = r.counters.as_ref().expect("guarded run");
    assert!(counters["dropped_violations"].as_u64().unwrap_or(0) >= 1, "{counters}");
}

/// A mission attack: the release is stored and reached without the guard, the upload refused
/// with it.
fn mission_attack(tag: &str, vehicle: &[&str], scenario: &str) -> Option<Run> {
    let r = attack(tag, vehicle, scenario, &[])?;
    upload_refused(&r);
    Some(r)
}

/// The two-item mission whose item 2 is DO_PARACHUTE RELEASE, then MAV_CMD_MISSION_START.
#[test]
fn mission_item_reached_by_mission_start() {
    let Some(r) = mission_attack("fx-mission-start", CHUTE_VEHICLE, "mission_start") else {
        return;
    };
    assert_eq!(r.gcs["mission_acks"], json!([14]), "DENIED, from the parachute rule: {}", r.gcs);
    let text: Vec<&str> =
        r.gcs["statustext"].as_array().unwrap().iter().filter_map(Value::as_str).collect();
    assert!(text.iter().any(|t| t.contains("parachute")), "a STATUSTEXT says why: {text:?}");
}

/// The same mission as MISSION_ITEM (float coordinates), started by SET_MODE AUTO.
#[test]
fn mission_item_float_reached_by_mode_auto() {
    mission_attack("fx-item-auto", CHUTE_VEHICLE, "mission_item_auto");
}

/// A harmless mission, then a partial write (MISSION_WRITE_PARTIAL_LIST) of the release into
/// item 2, then mission start.
#[test]
fn partial_write_of_the_release() {
    let Some(r) = mission_attack("fx-partial", CHUTE_VEHICLE, "mission_partial") else { return };
    assert_eq!(r.gcs["notes"][0], json!(0), "the harmless mission passes: {}", r.gcs);
}

/// Loiter at item 1, then MISSION_SET_CURRENT to the release at item 2.
#[test]
fn mission_set_current_into_the_release() {
    mission_attack("fx-set-current", CHUTE_VEHICLE, "mission_set_current");
}

/// Loiter at item 1, then MAV_CMD_DO_SET_MISSION_CURRENT to the release at item 2.
#[test]
fn do_set_mission_current_into_the_release() {
    mission_attack("fx-do-set-current", CHUTE_VEHICLE, "mission_do_set_current");
}

/// Item 1 is DO_JUMP to item 3, the release.
#[test]
fn do_jump_into_the_release() {
    mission_attack("fx-do-jump", CHUTE_VEHICLE, "mission_do_jump");
}

/// The vehicle already flies AUTO: a new mission is uploaded and the vehicle reaches the release
/// by its own progress.
#[test]
fn release_reached_by_the_vehicles_progress() {
    let vehicle: Vec<&str> = CHUTE_VEHICLE.iter().copied().chain(["--mode", "3"]).collect();
    mission_attack("fx-progress", &vehicle, "mission_progress");
}

/// A mission item MAV_CMD_DO_AUX_FUNCTION 22 (parachute release) in the high position.
#[test]
fn aux_function_release_as_a_mission_item() {
    mission_attack("fx-mission-aux", CHUTE_VEHICLE, "mission_aux");
}

/// MAV_CMD_DO_AUX_FUNCTION 22 high as a command: ArduPilot runs the auxiliary function whatever
/// the RC channels say.
#[test]
fn aux_function_release_as_a_command() {
    let Some(r) = attack("fx-aux", CHUTE_VEHICLE, "aux_function", &[]) else { return };
    assert_eq!(r.gcs["command_acks"], json!([[218, 2]]), "answered DENIED: {}", r.gcs);
}

/// RC_CHANNELS_OVERRIDE of channel 7 (RC7_OPTION = 22, parachute release) to 1900 µs.
#[test]
fn rc_override_of_the_parachute_channel() {
    let Some(r) = attack("fx-rc", CHUTE_VEHICLE, "rc_override", &["--value", "7"]) else { return };
    let counters = r.counters.expect("guarded");
    assert!(counters["dropped_violations"].as_u64().unwrap_or(0) >= 1, "{counters}");
}

/// ArduPilot up to 4.4: DO_SET_RELAY and DO_REPEAT_RELAY on relay 0, which CHUTE_TYPE 0 says
/// fires the parachute (no function check, no release conditions).
#[test]
fn relay_of_the_parachute_on_arducopter_4_4() {
    let Some(r) = attack("fx-relay44", RELAY_VEHICLE_4_4, "relay", &["--value", "0"]) else {
        return;
    };
    assert_eq!(r.gcs["command_acks"], json!([[181, 2], [182, 2]]), "both DENIED: {}", r.gcs);
}

/// Routes ArduPilot itself closes, played directly and through the guard: DO_SET_SERVO and
/// DO_REPEAT_SERVO on the parachute servo (refused: the output has a function), the relay of a
/// 4.5 vehicle whose function is parachute (refused: not a plain relay), and the release as a
/// fence item and a rally item (refused: not a fence or rally point). Neither path releases; the
/// guard refuses them too.
#[test]
fn routes_arducopter_closes_stay_closed() {
    let Some(py) = python() else { return };
    for (tag, scenario, args) in [
        ("fx-servo", "servo", &["--value", "9"][..]),
        ("fx-relay45", "relay", &["--value", "1"][..]),
        ("fx-plans", "plan_types", &[][..]),
    ] {
        let direct = run(&py, tag, CHUTE_VEHICLE, false, scenario, args);
        assert_eq!(released(&direct.vehicle), Vec::<String>::new(), "{scenario}: {}", direct.gcs);
        let guarded = run(&py, tag, CHUTE_VEHICLE, true, scenario, args);
        assert_eq!(released(&guarded.vehicle), Vec::<String>::new(), "{scenario}");
        let counters = guarded.counters.expect("guarded");
        assert!(
            counters["dropped_violations"].as_u64().unwrap_or(0) >= 2,
            "{scenario}: {counters}"
        );
    }
}

/// A release sent to system 0 (broadcast) and one to component 0 of system 1 are refused with a
/// COMMAND_ACK whose source is the vehicle's autopilot (1/1), never system or component 0 — what
/// ground stations attribute to the vehicle. Without the guard the vehicle answers from 1/1 too.
#[test]
fn refusals_of_broadcast_commands_come_from_the_vehicle() {
    let Some(py) = python() else { return };
    let direct = run(&py, "fx-broadcast", CHUTE_VEHICLE, false, "broadcast_release", &[]);
    assert!(!released(&direct.vehicle).is_empty());
    let r = run(&py, "fx-broadcast", CHUTE_VEHICLE, true, "broadcast_release", &[]);
    assert_eq!(released(&r.vehicle), Vec::<String>::new());
    assert_eq!(r.gcs["acks_from"], json!([[208, 2, 1, 1], [208, 2, 1, 1]]), "{}", r.gcs);
}

/// MAVProxy as the ground station (target 1/1) relays a client's release sent to system 0: the
/// guard's refusal reaches MAVProxy from the vehicle's ids, so MAVProxy shows it as the
/// vehicle's answer (an answer from system 0 is no message of its vehicle: MAVProxy ignores it).
#[test]
fn mavproxy_shows_the_refusal_of_a_broadcast_as_the_vehicles() {
    let Some(py) =
        vouch_testkit::python_with(&["pymavlink", "MAVProxy"]).map(std::path::PathBuf::from)
    else {
        return;
    };
    let dir = scratch("fx-mavproxy");
    let v = Vehicle::start_script(&py, &dir, "chute_vehicle.py", CHUTE_VEHICLE);
    let guard = Guard::start(&dir, v.port, &["--enforce"]);
    let port = free_udp_port();
    let Some(mut mp) = MavProxyRelay::start(&py, &dir, &guard, &format!("udpout:127.0.0.1:{port}"))
    else {
        panic!("MAVProxy did not detect the vehicle through the guard: {}", guard.log());
    };
    let client = format!("udpin:127.0.0.1:{port}");
    let g = gcs_at(&py, &dir, &client, "broadcast_release", &[], &guard.log());
    let shown =
        mp.wait_for("Got COMMAND_ACK: DO_PARACHUTE: DENIED", std::time::Duration::from_secs(5));
    guard.stop();
    let vehicle = v.finish();
    assert_eq!(released(&vehicle), Vec::<String>::new());
    assert!(shown, "MAVProxy did not show the refusal as its vehicle's:\n{}", mp.text());
    assert!(g["acks_from"].as_array().unwrap().iter().all(|a| a[2] == 1 && a[3] == 1), "{g}");
}
