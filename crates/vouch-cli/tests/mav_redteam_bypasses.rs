//! The four ways past the guard in enforce mode that an attacker found, each replayed against the
//! real `vouch mav guard` binary with pymavlink peers over UDP on 127.0.0.1: what must hold is
//! what the vehicle peer actually received.
//!
//! Needs `VOUCH_PYTHON` with pymavlink (scripts/install-peers.sh, scripts/test.sh); without it
//! every test prints why and returns, or fails under `VOUCH_REQUIRE_PEERS=1`.

mod mav_redteam_support;

use mav_redteam_support::*;
use serde_json::{Value, json};

/// MAVLink signing key used by the legitimate ground station (bytes 0..=31).
const KEY: &str = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

/// Bypass 1, fractional command selectors: DO_PARACHUTE with `param1 = 2.5` while the vehicle
/// climbs. ArduPilot switches on `(uint16_t)param1`, i.e. RELEASE. Before the fix the standard
/// library compared `param1 == PARACHUTE_RELEASE` as floats, the rule did not apply, and the
/// vehicle peer received the command (`parachute_param1 == [2.5]`, ACK ACCEPTED from the vehicle).
#[test]
fn fractional_parachute_selector_is_read_as_the_autopilot_reads_it() {
    let Some(py) = python() else { return };
    let value = ["--value", "2.5"];
    let o = attack(&py, "bypass-fractional", UNSAFE_VEHICLE, &["--enforce"], "fractional", &value);
    let (g, counters, v) = (o.gcs, o.counters, o.vehicle);
    assert_eq!(v["parachute_param1"], json!([]), "the vehicle received a parachute release");
    assert_eq!(g["command_acks"], json!([[208, 2]]), "GCS answered DENIED: {g}");
    assert_eq!(counters["dropped_violations"], 1, "{counters}");
}

/// Bypass 2, spoofed vehicle state: HEARTBEAT (armed), GLOBAL_POSITION_INT and VFR_HUD
/// (descending, 100 m up) and PARAM_VALUE (CHUTE_ALT_MIN = 0, MC_PITCH_P = MC_PITCHRATE_FF = 100)
/// sent from the GCS side with the vehicle's ids 1/1, in the same datagram as a parachute release
/// and as PARAM_SET MC_PITCHRATE_MAX = 40 (real bound 6.5 × 0.5 = 3.25). Before the fix the
/// forgeries fed the tracked state, and the vehicle peer received both the forgeries and the two
/// unsafe commands (`parachute_param1 == [2.0, 2.0, 2.0]`, three PARAM_SETs of 40).
#[test]
fn vehicle_state_forged_on_the_gcs_side_is_dropped_and_never_believed() {
    let Some(py) = python() else { return };
    let o = attack(&py, "bypass-spoof", UNSAFE_VEHICLE, &["--enforce"], "spoof", &[]);
    let (g, counters, v) = (o.gcs, o.counters, o.vehicle);
    assert_eq!(v["parachute_param1"], json!([]), "a parachute release reached the vehicle");
    assert_eq!(v["param_sets"], json!([]), "an unsafe PARAM_SET reached the vehicle");
    let spoofed: Vec<&Value> =
        v["messages"].as_array().unwrap().iter().filter(|m| m["src"] == json!([1, 1])).collect();
    assert!(spoofed.is_empty(), "frames claiming the vehicle's ids reached it: {spoofed:?}");
    assert!(g["command_acks"].as_array().unwrap().iter().all(|a| a[1] != 0), "{g}");
    assert!(counters["dropped_violations"].as_u64().unwrap() >= 6 * 4, "{counters}");
}

/// Bypass 3, unknown message ids. (a) 200 kB of random bytes: before the fix enforce mode
/// forwarded every length-cut candidate whose id the dialect does not know (the vehicle peer
/// decoded hundreds of `UNKNOWN_…` messages and bad data). (b) One datagram holding a stray
/// header of id 49152 whose length claims the 6 bytes and the good COMMAND_LONG behind it: before
/// the fix the vehicle received `UNKNOWN_49152` and never the command.
#[test]
fn unknown_ids_are_dropped_and_never_swallow_the_frame_behind_them() {
    let Some(py) = python() else { return };
    let dir = scratch("bypass-unknown");
    let vehicle = Vehicle::start(&py, &dir, &["--quiet-state"]);
    let guard = Guard::start(&dir, vehicle.port, &["--enforce"]);
    gcs(&py, &dir, &guard, "random", &[]);
    let g = gcs(&py, &dir, &guard, "stray", &[]);
    let counters = guard.stop();
    let v = vehicle.finish();
    let good = hex(g["notes"][0].as_str().unwrap().trim_start_matches("good "));
    let t = types(&v);
    assert!(
        t.iter().all(|t| t == "HEARTBEAT" || t == "COMMAND_LONG"),
        "the vehicle decoded more than heartbeats and the command: {:?}",
        t.iter().filter(|t| *t != "HEARTBEAT").collect::<Vec<_>>()
    );
    assert_eq!(v["bad_data"], 0, "bytes that are no frame reached the vehicle");
    assert_eq!(markers_received(&v), vec![7.0], "the command behind the stray header");
    assert!(datagrams(&v).contains(&good), "the command arrived byte for byte");
    assert!(counters["junk_bytes"].as_u64().unwrap() >= 190_000, "{counters}");
}

fn replay_after_restart(tag: &str, clean_stop: bool) {
    let Some(py) = python() else { return };
    let dir = scratch(tag);
    let vehicle = Vehicle::start(&py, &dir, &["--quiet-state"]);
    let args = ["--enforce", "--signing-key", KEY];
    let guard = Guard::start(&dir, vehicle.port, &args);
    let capture = dir.join("captured.hex");
    let cap = capture.to_str().unwrap();
    let markers = ["--value", "1", "--value", "2", "--value", "3"];
    let mut a = vec!["--key", KEY, "--capture", cap];
    a.extend(markers);
    gcs(&py, &dir, &guard, "signed_commands", &a);
    if clean_stop {
        guard.stop();
    } else {
        // the state is written at least every second: after 1.5 s the captured frames are in it
        std::thread::sleep(std::time::Duration::from_millis(1500));
        guard.kill();
    }
    let guard = Guard::start(&dir, vehicle.port, &args);
    gcs(&py, &dir, &guard, "replay", &["--replay", cap]);
    gcs(&py, &dir, &guard, "signed_commands", &["--key", KEY, "--value", "99"]);
    let counters = guard.stop();
    let v = vehicle.finish();
    assert_eq!(
        markers_received(&v),
        vec![1.0, 2.0, 3.0, 99.0],
        "replayed frames reached the vehicle"
    );
    assert!(counters["signing_rejected"].as_u64().unwrap() >= 3, "{counters}");
}

/// Bypass 4, replay across restarts (clean stop): signed frames captured before the guard was
/// stopped (SIGTERM) and started again pass again after it. Before the fix the replay table
/// lived only in memory and the vehicle peer received markers 1, 2, 3 twice.
#[test]
fn signed_frames_replayed_after_a_restart_are_refused() {
    replay_after_restart("bypass-replay-clean", true);
}

/// Bypass 4 after a crash: the guard is killed with SIGKILL 1.5 s after the frames were
/// accepted (the state file is written at least every second). Before the fix the replay passed.
#[test]
fn signed_frames_replayed_after_a_crash_are_refused() {
    replay_after_restart("bypass-replay-crash", false);
}
