//! The standard library on the 12 real recordings of ../shared/mavlink/tlogs: zero violations,
//! the sessions the recordings' README documents are actually recognised, and what a recording
//! cannot show (answers whose requests are not in it) is counted as unverifiable. Expected
//! figures come from that README (frame counts by an independent scanner, sessions by pymavlink).

use std::path::PathBuf;
use std::sync::Arc;

use vouch_mav::dialect::load_dialect_file;
use vouch_mav::monitor::offline::{RecordingReport, check_tlog};
use vouch_mav::monitor::{Monitor, ViolationKind};

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
    let s = &r.summary;
    eprintln!(
        "  sides: gcs {} vehicle {} (one direction: {:?}); violations {}, unverifiable {}",
        s.from_gcs, s.from_vehicle, r.one_direction, s.violations, s.unverifiable
    );
    for p in s.protocols.iter().filter(|p| p.started + p.unverifiable + p.violations > 0) {
        eprintln!(
            "  {:<24} started {:>4} completed {:>4} abandoned {:>4} unfinished {:>3} violations {} unverifiable {}",
            p.name, p.started, p.completed, p.abandoned, p.unfinished, p.violations, p.unverifiable
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

fn unverifiable(r: &RecordingReport, proto: &str) -> u64 {
    r.summary.protocol(proto).map(|p| p.unverifiable).unwrap_or(0)
}

/// No violation, both directions present, nothing unverifiable except in `allowed` protocols.
fn clean_two_way(r: &RecordingReport, allowed: &[&str]) {
    assert_eq!(r.violations.len(), 0, "{:#?}", r.violations.first().map(|v| v.to_string()));
    assert_eq!(r.summary.forgeries, 0);
    assert_eq!(r.one_direction, None, "both sides are in the recording");
    for p in &r.summary.protocols {
        if !allowed.contains(&p.name.as_str()) {
            assert_eq!(p.unverifiable, 0, "{} has unverifiable messages", p.name);
        }
    }
}

/// Frames of the given message ids in a recording (the codec's reader, counting by id only).
fn frames_with_ids(file: &str, ids: &[u32]) -> u64 {
    let dir = shared().expect("shared");
    let d = load_dialect_file(&dir.join("definitions/ardupilotmega.xml")).expect("dialect");
    let data = std::fs::read(dir.join("tlogs").join(file)).expect("read tlog");
    vouch_mav::TlogReader::new(&data, &d).filter(|r| ids.contains(&r.frame.msgid)).count() as u64
}

#[test]
fn rover_2025_sitl_is_clean_and_sessions_recognised() {
    let Some(r) = run("uavlogviewer_flight_logs.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
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
    clean_two_way(&r, &["command"]);
    assert!(r.codec.frames >= 30_400);
    assert_eq!(r.codec.frames_v1, 2);
    // One PARAM_REQUEST_LIST followed by the full parameter download.
    assert_eq!(completed(&r, "param_list"), 1);
    // 18 COMMAND_ACKs whose COMMAND_LONGs are not in the recording: cannot tell.
    assert_eq!(unverifiable(&r, "command"), 18);
    assert_eq!(r.unverifiable.len(), 18);
}

#[test]
fn ardusub_2021_mavproxy_is_clean() {
    let Some(r) = run("rust-mavlink_tests_log.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
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
    clean_two_way(&r, &[]);
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
    clean_two_way(&r, &[]);
    assert_eq!(r.codec.frames, 473);
    assert_eq!(completed(&r, "mission_upload"), 1);
    assert_eq!(completed(&r, "mission_download"), 1);
    assert_eq!(completed(&r, "param_set"), 1);
    assert_eq!(completed(&r, "param_list"), 1);
    // The MAVSDK vehicle does not acknowledge the 7 COMMAND_LONG 410.
    assert_eq!(completed(&r, "command"), 0);
}

// ---- the seven uncurated recordings of real stacks -------------------------------------------

/// Only the vehicle's frames were recorded: its MISSION_COUNT and MISSION_ITEM bursts answer
/// requests that are not in the file. Each item is unverifiable (not a violation), and the report
/// says that the recording holds one direction.
#[test]
fn arduplane_vtol_2018_one_sided_recording_is_unverifiable_not_violating() {
    let Some(r) = run("uavlogviewer_vtol_arduplane_2018.tlog") else {
        return;
    };
    assert_eq!(r.codec.frames, 23_894);
    assert_eq!(r.violations.len(), 0);
    assert_eq!(r.one_direction, Some(vouch_mav::Side::Vehicle));
    assert_eq!(r.summary.from_gcs, 0);
    let items = frames_with_ids("uavlogviewer_vtol_arduplane_2018.tlog", &[39, 73]);
    assert!(items > 0);
    assert_eq!(unverifiable(&r, "mission_download"), items, "every item sent unasked");
    assert!(r.unverifiable.iter().all(|v| v.kind == ViolationKind::Unverifiable));
}

/// Mission Planner reads item 0 (home) on its own, without MISSION_REQUEST_LIST: each read is a
/// completed session, not an orphaned item. 14 commands, all ACKed; the SET_MODE messages sent
/// with DO_SET_MODE are acknowledged too.
#[test]
fn missionplanner_2024_stand_alone_item_reads_are_sessions() {
    let Some(r) = run("missionplanner_arducopter_sitl_2024.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
    assert_eq!(r.codec.frames, 10_277);
    assert_eq!(r.codec.signed, 1);
    let reads = frames_with_ids("missionplanner_arducopter_sitl_2024.tlog", &[51]);
    let lists = frames_with_ids("missionplanner_arducopter_sitl_2024.tlog", &[43]);
    assert!(reads > 0);
    assert_eq!(lists, 0, "no MISSION_REQUEST_LIST in the recording");
    assert_eq!(completed(&r, "mission_download"), reads);
    assert_eq!(completed(&r, "command"), 14);
    assert!(completed(&r, "set_mode") > 0);
}

/// ArduSub 4.1 and QGroundControl, with corrupt frames: 2 mission downloads, a parameter list, 9
/// commands.
#[test]
fn ardusub_qgc_2023_is_clean() {
    let Some(r) = run("ardusub_qgc_2023.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
    assert_eq!((r.codec.frames, r.codec.bad_crc, r.codec.garbage_bytes), (35_912, 4, 315));
    assert_eq!(completed(&r, "mission_download"), 2);
    assert_eq!(completed(&r, "param_list"), 1);
    assert_eq!(completed(&r, "command"), 9);
}

/// ArduCopter with MAVProxy over a 3DR radio (2015): 1,314 bad-CRC frames, 268 single-parameter
/// reads, and a reboot command that is never ACKed.
#[test]
fn dronekit_arducopter_2015_is_clean() {
    let Some(r) = run("dronekit_arducopter_2015.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
    assert_eq!((r.codec.frames, r.codec.bad_crc, r.codec.garbage_bytes), (75_477, 1_314, 27_613));
    assert_eq!(r.codec.truncated, 1);
    assert_eq!(completed(&r, "param_read"), 268);
    let c = r.summary.protocol("command").expect("command");
    assert_eq!(c.abandoned + c.unfinished, 1, "the reboot that was never ACKed");
}

#[test]
fn arduplane_pixhawk_2018_parameter_list_is_clean() {
    let Some(r) = run("arduplane_pixhawk_2018.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
    assert_eq!(r.codec.frames, 8_164);
    assert_eq!(completed(&r, "param_list"), 1);
}

#[test]
fn arducopter_mavproxy_2014_parameter_list_is_clean() {
    let Some(r) = run("arducopter_mavproxy_2014.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
    assert_eq!(r.codec.frames, 2_632);
    assert_eq!(completed(&r, "param_list"), 1);
}

/// PX4 2014: a parameter list that never finishes in the file.
#[test]
fn px4_mavproxy_2014_unfinished_parameter_list_is_clean() {
    let Some(r) = run("px4_mavproxy_2014.tlog") else {
        return;
    };
    clean_two_way(&r, &[]);
    assert_eq!(r.codec.frames, 129);
    let p = r.summary.protocol("param_list").expect("param_list");
    assert_eq!((p.started, p.completed, p.unfinished), (1, 0, 1));
}
