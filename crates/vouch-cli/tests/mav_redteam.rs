//! Red team: the real `vouch mav guard` binary in enforce mode against what an attacker would
//! try, over real sockets on 127.0.0.1, with pymavlink (and MAVProxy) peers sending the attack.
//! Each test asserts what the vehicle peer actually received; the guard's counters only beside
//! that. (The four bypasses found earlier are in `mav_redteam_bypasses.rs`.)
//!
//! Needs `VOUCH_PYTHON` with pymavlink (and MAVProxy for the last test); without it every test
//! prints why and returns, or fails under `VOUCH_REQUIRE_PEERS=1`.

mod mav_redteam_support;

use std::time::Duration;

use mav_redteam_support::*;
use serde_json::{Value, json};

const KEY: &str = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

fn no_src(v: &Value, sysids: &[u64]) -> Vec<Value> {
    v["messages"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| sysids.contains(&m["src"][0].as_u64().unwrap()))
        .cloned()
        .collect()
}

/// Every DO_PARACHUTE param1 that ArduPilot's `(uint16_t)param1` reads as RELEASE, that another
/// reader could round to it, or whose conversion C leaves undefined, is refused while the
/// vehicle climbs; DISABLE (0) and ENABLE (1) pass.
#[test]
fn parachute_values_that_may_read_as_release_never_reach_the_vehicle() {
    let Some(py) = python() else { return };
    let values = [
        "2.9999998",
        "2.0000002",
        "1.5",
        "65538",
        "-65534",
        "1e10",
        "nan",
        "inf",
        "-inf",
        "0",
        "1",
    ];
    let args: Vec<String> = values.iter().map(|v| format!("--value={v}")).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = attack(&py, "rt-values", UNSAFE_VEHICLE, &["--enforce"], "fractional", &args);
    let (g, counters, v) = (o.gcs, o.counters, o.vehicle);
    assert_eq!(v["parachute_param1"], json!([0.0, 1.0]), "only DISABLE and ENABLE arrive");
    let denied = g["command_acks"].as_array().unwrap().iter().filter(|a| **a == json!([208, 2]));
    assert_eq!(denied.count(), 9, "each refusal answered DENIED: {g}");
    assert_eq!(counters["dropped_violations"], 9, "{counters}");
}

/// COMMAND_INT instead of COMMAND_LONG, MAVLink 1 instead of 2, an untruncated MAVLink 2 payload,
/// target system 0 (broadcast), target component 0: the same unsafe release in each form is
/// refused; a harmless command behind them passes.
#[test]
fn every_form_of_the_same_command_is_checked() {
    let Some(py) = python() else { return };
    let o = attack(&py, "rt-forms", UNSAFE_VEHICLE, &["--enforce"], "forms", &[]);
    let (counters, v) = (o.counters, o.vehicle);
    assert_eq!(v["parachute_param1"], json!([]), "{:?}", types(&v));
    assert_eq!(markers_received(&v), vec![5.0]);
    assert_eq!(counters["dropped_violations"], 6, "{counters}");
}

/// System/component id games from the GCS side: heartbeats, acknowledgements and commands with
/// the ids of the vehicle's autopilot (1/1) or component 0 — 8 forgeries; from a component of
/// the vehicle's system that the vehicle side never showed (1/250, as a companion computer on a
/// ground endpoint would be): its autopilot heartbeat is a forgery and its unsafe release is
/// refused like any ground station's, its harmless command (marker 6) passes; an autopilot
/// heartbeat of an unseen system (7) is a forgery. 11 drops; the genuine GCS is unaffected.
#[test]
fn frames_claiming_a_vehicle_identity_from_the_gcs_side_are_dropped() {
    let Some(py) = python() else { return };
    let o = attack(&py, "rt-identity", UNSAFE_VEHICLE, &["--enforce"], "identity", &[]);
    let (counters, v) = (o.counters, o.vehicle);
    let from_vehicle_ids = no_src(&v, &[1, 7]);
    let srcs: Vec<_> =
        from_vehicle_ids.iter().map(|m| (m["src"].clone(), m["type"].clone())).collect();
    assert_eq!(
        srcs,
        vec![(json!([1, 250]), json!("COMMAND_LONG"))],
        "forged identities reached the vehicle"
    );
    assert_eq!(v["parachute_param1"], json!([]), "the release from 1/250 was refused");
    assert_eq!(markers_received(&v), vec![6.0, 5.0]);
    assert_eq!(counters["dropped_violations"], 11, "{counters}");
}

/// Parameter ids as the autopilot reads them: 16 characters without a NUL, junk after the NUL,
/// lower case (ArduPilot matches names without case). Each unsafe write is refused and answered
/// with a PARAM_VALUE carrying the value in force; a safe write passes.
#[test]
fn parameter_ids_are_read_as_the_autopilot_reads_them() {
    let Some(py) = python() else { return };
    let o = attack(&py, "rt-params", UNSAFE_VEHICLE, &["--enforce"], "params", &[]);
    let (g, counters, v) = (o.gcs, o.counters, o.vehicle);
    let sets = v["param_sets"].as_array().unwrap();
    assert_eq!(sets.len(), 1, "only the safe write arrives: {sets:?}");
    assert_eq!(sets[0][0], "MC_PITCHRATE_MAX");
    assert!((sets[0][1].as_f64().unwrap() - 3.1).abs() < 1e-6);
    let values = g["param_values"].as_array().unwrap();
    let got = |id: &str, x: f64| {
        values.iter().any(|p| p[0] == id && (p[1].as_f64().unwrap_or(f64::NAN) - x).abs() < 1e-6)
    };
    assert!(got("MC_PITCHRATE_MAX", 3.0), "refusal answered with the value in force: {values:?}");
    assert!(got("MC_PITCH_P", 6.5) && got("mc_pitch_p", 6.5), "{values:?}");
    assert_eq!(counters["dropped_violations"], 3, "{counters}");
}

/// With signing required: a captured genuine frame with its link id changed, its signature
/// stripped, re-signed with another key; a MAVLink 1 frame; an unknown incompatibility flag; a
/// SETUP_SIGNING. Nothing but the genuine frames reaches the vehicle.
#[test]
fn signature_games_pass_nothing() {
    let Some(py) = python() else { return };
    let guard = ["--enforce", "--signing-key", KEY];
    let key = ["--key", KEY, "--link-id", "4"];
    let o = attack(&py, "rt-signing", &["--quiet-state"], &guard, "signature_games", &key);
    let (counters, v) = (o.counters, o.vehicle);
    assert_eq!(markers_received(&v), vec![1.0, 2.0], "{:?}", types(&v));
    assert!(!types(&v).contains(&"SETUP_SIGNING".to_string()));
    assert!(counters["signing_rejected"].as_u64().unwrap() >= 5, "{counters}");
}

/// Over TCP: an unsafe release written one byte at a time, a genuine command in 7-byte pieces
/// with pauses, then half a frame and a closed connection; a new connection works.
#[test]
fn slow_and_partial_tcp_writes() {
    let Some(py) = python() else { return };
    let dir = scratch("rt-tcp");
    let vehicle = Vehicle::start(&py, &dir, UNSAFE_VEHICLE);
    let gcs_ep = format!("tcpin:127.0.0.1:{}", free_tcp_port());
    let guard = Guard::start_on(&dir, &gcs_ep, vehicle.port, &["--enforce"]);
    let g = gcs(&py, &dir, &guard, "slow", &[]);
    gcs(&py, &dir, &guard, "signed_commands", &["--value", "4"]);
    let counters = guard.stop();
    let v = vehicle.finish();
    assert_eq!(v["parachute_param1"], json!([]));
    assert_eq!(markers_received(&v), vec![3.0, 4.0], "half a frame never arrives");
    assert_eq!(g["command_acks"].as_array().unwrap()[0], json!([208, 2]), "{g}");
    assert_eq!(counters["dropped_violations"], 1, "{counters}");
}

/// Datagrams of 9,000 and 65,000 bytes full of genuine commands are never forwarded in part.
#[test]
fn oversized_datagrams_are_dropped_whole() {
    let Some(py) = python() else { return };
    let o = attack(&py, "rt-oversized", &["--quiet-state"], &["--enforce"], "oversized", &[]);
    assert_eq!(markers_received(&o.vehicle), vec![6.0]);
}

/// Floods of parameter reads (3,000 distinct names), forged vehicle heartbeats (2,000) and
/// 200 kB of random bytes: the guard stays small and keeps working — the unsafe release after
/// them is refused, the genuine command passes.
#[test]
fn floods_leave_the_guard_bounded_and_working() {
    let Some(py) = python() else { return };
    let dir = scratch("rt-flood");
    let vehicle = Vehicle::start(&py, &dir, UNSAFE_VEHICLE);
    let guard = Guard::start(&dir, vehicle.port, &["--enforce"]);
    gcs(&py, &dir, &guard, "flood", &["--wait", "2"]);
    let peak = guard.peak_rss_kb();
    let counters = guard.stop();
    let v = vehicle.finish();
    assert_eq!(v["parachute_param1"], json!([]));
    assert_eq!(markers_received(&v), vec![8.0]);
    assert!(no_src(&v, &[1]).is_empty(), "forged heartbeats reached the vehicle");
    assert!(types(&v).iter().all(|t| !t.starts_with("UNKNOWN")));
    assert_eq!(v["bad_data"], 0);
    if let Some(kb) = peak {
        assert!(kb < 16 * 1024, "guard peak RSS {kb} kB");
    }
    assert!(counters["dropped_violations"].as_u64().unwrap() >= 1000, "{counters}");
}

/// The guard joins mid-stream: answers to requests it never saw (a COMMAND_ACK, a mission item)
/// pass as unverifiable; a mission item the GCS sends without an announced upload is refused and
/// cancelled; a stand-alone read of item 0 (Mission Planner's habit) is answered.
#[test]
fn joining_mid_stream_and_stand_alone_reads() {
    let Some(py) = python() else { return };
    let vehicle = ["--quiet-state", "--stale-answers"];
    let o = attack(&py, "rt-midstream", &vehicle, &["--enforce"], "midstream", &[]);
    let (g, counters, v) = (o.gcs, o.counters, o.vehicle);
    assert!(g["command_acks"].as_array().unwrap().contains(&json!([400, 0])), "{g}");
    assert_eq!(g["mission_items"], json!([3, 0]), "the stale item and the read of item 0");
    assert_eq!(g["mission_acks"], json!([15]), "the unannounced item is cancelled");
    assert!(received(&v, "MISSION_ITEM_INT").is_empty());
    assert_eq!(received(&v, "MISSION_REQUEST_INT").len(), 1);
    assert_eq!(counters["unverifiable_forwarded"], 2, "{counters}");
    assert_eq!(counters["violations"], 1, "{counters}");
}

/// 300 datagrams mixing genuine commands with garbage (random bytes, start markers, headers of
/// unknown ids claiming the bytes behind them, corrupted and cut frames): the vehicle receives
/// every genuine frame, byte for byte and in order, and nothing else.
#[test]
fn any_mix_of_frames_and_garbage_delivers_exactly_the_frames() {
    let Some(py) = python() else { return };
    let o = attack(&py, "rt-mix", &["--quiet-state"], &["--enforce"], "mix", &[]);
    let (g, v) = (o.gcs, o.vehicle);
    let good: Vec<String> =
        g["notes"][0].as_array().unwrap().iter().map(|h| h.as_str().unwrap().to_string()).collect();
    assert!(good.len() > 200);
    let want: Vec<f64> = (0..good.len()).map(|i| 1000.0 + i as f64).collect();
    assert_eq!(markers_received(&v), want);
    assert!(types(&v).iter().all(|t| t == "HEARTBEAT" || t == "COMMAND_LONG"), "{:?}", types(&v));
    assert_eq!(v["bad_data"], 0);
    let all: String =
        v["datagrams"].as_array().unwrap().iter().map(|d| d.as_str().unwrap()).collect();
    let mut at = 0;
    for f in &good {
        let i = all[at..].find(f.as_str()).expect("a genuine frame arrived intact") + at;
        at = i + f.len();
    }
}

/// MAVProxy (a real ground station) sends `long MAV_CMD_DO_PARACHUTE 2.5` and
/// `param set MC_PITCHRATE_MAX 40` through the guard: neither reaches the vehicle, and MAVProxy
/// is answered at once — DENIED, and a PARAM_VALUE with the value in force, so that it reports
/// the failed write instead of waiting.
#[test]
fn mavproxy_gets_answers_for_what_the_guard_refuses() {
    let Some(py) =
        vouch_testkit::python_with(&["pymavlink", "MAVProxy"]).map(std::path::PathBuf::from)
    else {
        return;
    };
    let dir = scratch("rt-mavproxy");
    let vehicle = Vehicle::start(&py, &dir, UNSAFE_VEHICLE);
    let guard = Guard::start(&dir, vehicle.port, &["--enforce", "--alert-gcs"]);
    let text = mavproxy(
        &py,
        &dir,
        &guard,
        &["long MAV_CMD_DO_PARACHUTE 2.5", "param set MC_PITCHRATE_MAX 40"],
        &["DENIED", "Failed to set MC_PITCHRATE_MAX"],
        Duration::from_secs(40),
    );
    let counters = guard.stop();
    let v = vehicle.finish();
    assert_eq!(v["parachute_param1"], json!([]), "MAVProxy output:\n{text}");
    assert_eq!(v["param_sets"], json!([]), "MAVProxy output:\n{text}");
    assert!(text.contains("DENIED"), "MAVProxy output:\n{text}");
    assert!(
        text.contains("Failed to set MC_PITCHRATE_MAX to 40")
            && text.contains("invalid returned value 3"),
        "answered with the value in force, not left to time out:\n{text}"
    );
    assert!(counters["dropped_violations"].as_u64().unwrap() >= 2, "{counters}");
}
