//! The standard library on real recordings (../shared/mavlink/tlogs): zero violations, and the
//! sessions the recordings' README documents are actually recognised.

use std::path::PathBuf;
use std::sync::Arc;

use vouch_mav::dialect::load_dialect_file;
use vouch_mav::monitor::offline::{check_tlog, RecordingReport};
use vouch_mav::monitor::Monitor;

fn shared() -> Option<PathBuf> {
    vouch_testkit::shared("mavlink", "definitions/ardupilotmega.xml")
}

fn run(file: &str) -> Option<RecordingReport> {
    let dir = shared()?;
    let dialect =
        Arc::new(load_dialect_file(&dir.join("definitions/ardupilotmega.xml")).expect("dialect"));
    let data = std::fs::read(dir.join("tlogs").join(file)).expect("read tlog");
    let mut m = Monitor::with_stdlib(dialect, &[]).expect("stdlib loads");
    let r = check_tlog(&data, &mut m);
    eprintln!("{file}: {:?}", r.codec);
    for p in &r.summary.protocols {
        eprintln!(
            "  {:<24} started {:>4} completed {:>4} abandoned {:>4} unfinished {:>3} violations {}",
            p.name, p.started, p.completed, p.abandoned, p.unfinished, p.violations
        );
    }
    for v in r.violations.iter().take(10) {
        eprintln!("  VIOLATION {v}");
    }
    Some(r)
}

fn completed(r: &RecordingReport, proto: &str) -> u64 {
    r.summary.protocol(proto).map(|p| p.completed).unwrap_or(0)
}

#[test]
fn rover_2025_sitl_is_clean_and_sessions_recognised() {
    let Some(r) = run("uavlogviewer_flight_logs.tlog") else {
        return;
    };
    assert_eq!(r.violations.len(), 0, "legitimate ArduPilot traffic must not violate");
    // README: 96,644 decodable messages, about 140 bytes of broken data.
    assert!(r.codec.frames >= 96_600, "frames {}", r.codec.frames);
    // 11 uploads from the GCS: 9 clears (count 0) + 2 with items, all ACCEPTED.
    assert_eq!(completed(&r, "mission_upload"), 11);
    // 2 downloads (4 and 19 items) without closing ACK.
    assert_eq!(completed(&r, "mission_download"), 2);
    // 55 PARAM_SET, each answered by a PARAM_VALUE of the same id.
    assert_eq!(completed(&r, "param_set"), 55);
    // 12 COMMAND_LONG, each ACKed.
    assert_eq!(completed(&r, "command"), 12);
}

#[test]
fn ardusub_2024_blueos_is_clean() {
    let Some(r) = run("mavlink-server_00025-2024-04-22.tlog") else {
        return;
    };
    assert_eq!(r.violations.len(), 0);
    assert!(r.codec.frames >= 30_400);
    assert_eq!(r.codec.frames_v1, 2);
    // One PARAM_REQUEST_LIST followed by the full parameter download.
    assert_eq!(completed(&r, "param_list"), 1);
}

#[test]
fn ardusub_2021_mavproxy_is_clean() {
    let Some(r) = run("rust-mavlink_tests_log.tlog") else {
        return;
    };
    assert_eq!(r.violations.len(), 0);
    assert_eq!(r.codec.frames, 1426);
    // 230 PARAM_REQUEST_READ (repeated reads of a few names) without replies: none completed.
    let pr = r.summary.protocol("param_read").expect("param_read");
    assert!(pr.started > 0);
    assert_eq!(pr.completed, 0);
}

#[test]
fn mavproxy_to_pymavlink_vehicle_upload_is_clean() {
    let Some(r) = run("upload100_mavproxy_to_pymavlink_vehicle.tlog") else {
        return;
    };
    assert_eq!(r.violations.len(), 0);
    assert_eq!(r.codec.frames, 470);
    assert_eq!(completed(&r, "mission_upload"), 1);
    assert_eq!(completed(&r, "mission_download"), 1);
    assert_eq!(completed(&r, "param_set"), 1);
    assert_eq!(completed(&r, "param_list"), 1);
    assert_eq!(completed(&r, "command"), 7);
}

#[test]
fn mavproxy_to_mavsdk_vehicle_upload_is_clean() {
    let Some(r) = run("upload100_mavproxy_to_mavsdk_vehicle.tlog") else {
        return;
    };
    assert_eq!(r.violations.len(), 0);
    assert_eq!(r.codec.frames, 473);
    assert_eq!(completed(&r, "mission_upload"), 1);
    assert_eq!(completed(&r, "mission_download"), 1);
    assert_eq!(completed(&r, "param_set"), 1);
    assert_eq!(completed(&r, "param_list"), 1);
    // The MAVSDK vehicle does not acknowledge the 7 COMMAND_LONG 410.
    assert_eq!(completed(&r, "command"), 0);
}
