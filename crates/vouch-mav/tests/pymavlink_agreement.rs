//! Byte-level agreement with pymavlink (PyPI), both directions: vouch and pymavlink encode the
//! same messages to identical bytes, and each decodes the other's frames to the same values.
//! Skips when VOUCH_PYTHON is unset or has no pymavlink (fails then under VOUCH_REQUIRE_PEERS=1).

mod common;
use common::dialect;
use serde_json::{Value as J, json};
use std::io::Write;
use std::process::{Command, Stdio};
use vouch_mav::codec::{FrameSplitter, MessageBuilder, MessageView, Value};

fn python() -> Option<String> {
    vouch_testkit::python_with(&["pymavlink"])
}

fn run_py(py: &str, mode: &str, req: &J) -> J {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/py/pymav_roundtrip.py");
    let mut child = Command::new(py)
        .args([script, mode])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start python");
    child.stdin.take().unwrap().write_all(req.to_string().as_bytes()).unwrap();
    let out = child.wait_with_output().expect("python runs");
    assert!(out.status.success(), "python failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("python answers JSON")
}

/// Messages exercising every wire feature: reordering, extensions, truncation, text, arrays,
/// signed/float types, 24-bit ids.
fn samples() -> Vec<(&'static str, J)> {
    vec![
        (
            "HEARTBEAT",
            json!({"type": 2, "autopilot": 3, "base_mode": 209, "custom_mode": 5, "system_status": 4, "mavlink_version": 3}),
        ),
        (
            "MISSION_COUNT",
            json!({"target_system": 1, "target_component": 1, "count": 100, "mission_type": 0}),
        ),
        (
            "MISSION_COUNT",
            json!({"target_system": 1, "target_component": 1, "count": 7, "mission_type": 2}),
        ),
        (
            "MISSION_REQUEST",
            json!({"target_system": 255, "target_component": 190, "seq": 42, "mission_type": 1}),
        ),
        (
            "MISSION_ITEM_INT",
            json!({"target_system": 1, "target_component": 1, "seq": 3, "frame": 6, "command": 16, "current": 0, "autocontinue": 1,
            "param1": 0.5, "param2": -2.25, "param3": 0, "param4": 90, "x": -473977420, "y": 85455940, "z": 123.5, "mission_type": 0}),
        ),
        (
            "MISSION_ACK",
            json!({"target_system": 255, "target_component": 190, "type": 13, "mission_type": 1}),
        ),
        (
            "PARAM_SET",
            json!({"target_system": 1, "target_component": 1, "param_id": "CHUTE_ALT_MIN", "param_value": 12.5, "param_type": 9}),
        ),
        (
            "PARAM_VALUE",
            json!({"param_id": "ABCDEFGHIJKLMNOP", "param_value": -1.0e-3, "param_type": 9, "param_count": 700, "param_index": 65535}),
        ),
        (
            "COMMAND_LONG",
            json!({"target_system": 1, "target_component": 1, "command": 208, "confirmation": 1, "param1": 2, "param7": -7.5}),
        ),
        (
            "COMMAND_ACK",
            json!({"command": 208, "result": 2, "progress": 0, "result_param2": -5, "target_system": 255, "target_component": 190}),
        ),
        (
            "GLOBAL_POSITION_INT",
            json!({"time_boot_ms": 123456, "lat": -350000000, "lon": 1490000000, "alt": 584000, "relative_alt": 50000, "vx": -12, "vy": 300, "vz": -50, "hdg": 35999}),
        ),
        (
            "STATUSTEXT",
            json!({"severity": 2, "text": "vouch: unsafe PARAM_SET refused", "id": 0, "chunk_seq": 0}),
        ),
        (
            "AUTOPILOT_VERSION",
            json!({"capabilities": 64495, "flight_sw_version": 67175935, "middleware_sw_version": 0, "os_sw_version": 0, "board_version": 0,
            "flight_custom_version": [1, 2, 3, 4, 5, 6, 7, 8], "middleware_custom_version": [0,0,0,0,0,0,0,0], "os_custom_version": [9,0,0,0,0,0,0,0], "vendor_id": 4660, "product_id": 22136, "uid": 1234567890123u64}),
        ),
        (
            "PARAM_EXT_ACK",
            json!({"param_id": "SR0_EXTRA1", "param_value": "12", "param_type": 9, "param_result": 0}),
        ),
    ]
}

fn vouch_encode(d: &vouch_mav::Dialect, name: &str, fields: &J, seq: u8, v: u8) -> Vec<u8> {
    let mut b = MessageBuilder::new(d, name).expect("message");
    for (f, val) in fields.as_object().unwrap() {
        match val {
            J::String(s) => b = b.set_str(f, s).expect("text"),
            J::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    b.set_value(f, i, Value::F(x.as_f64().unwrap())).expect("array");
                }
            }
            J::Number(n) => {
                let val = if let Some(u) = n.as_u64() {
                    Value::U(u)
                } else if let Some(i) = n.as_i64() {
                    Value::I(i)
                } else {
                    Value::F(n.as_f64().unwrap())
                };
                b.set_value(f, 0, val).unwrap_or_else(|e| panic!("{name}.{f}: {e}"));
            }
            _ => panic!("unsupported"),
        }
    }
    if v == 1 { b.frame_v1(seq, 255, 190).expect("v1") } else { b.frame_v2(seq, 255, 190) }
}

#[test]
fn vouch_and_pymavlink_encode_identical_bytes() {
    let (Some(py), Some(d)) = (python(), dialect()) else {
        return;
    };
    let mut req = vec![];
    let mut ours = vec![];
    for (i, (name, fields)) in samples().into_iter().enumerate() {
        for v in [1u8, 2] {
            if v == 1 && d.by_name(name).unwrap().id > 255 {
                continue;
            }
            req.push(
                json!({"name": name, "fields": fields, "seq": i, "sys": 255, "comp": 190, "v": v}),
            );
            ours.push((name, v, vouch_encode(&d, name, &fields, i as u8, v)));
        }
    }
    let theirs = run_py(&py, "encode", &J::Array(req));
    let theirs = theirs.as_array().unwrap();
    assert_eq!(theirs.len(), ours.len());
    for ((name, v, bytes), hex) in ours.iter().zip(theirs) {
        let hex = hex.as_str().unwrap();
        let ours_hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(ours_hex, hex, "{name} MAVLink {v}");
    }
}

#[test]
fn each_side_decodes_the_others_frames() {
    let (Some(py), Some(d)) = (python(), dialect()) else {
        return;
    };
    let mut req = vec![];
    let mut expected = vec![];
    for (i, (name, fields)) in samples().into_iter().enumerate() {
        let bytes = vouch_encode(&d, name, &fields, i as u8, 2);
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        req.push(json!({"hex": hex, "v": 2}));
        expected.push((name, fields, bytes));
    }
    let decoded = run_py(&py, "decode", &J::Array(req));
    for ((name, fields, bytes), got) in expected.iter().zip(decoded.as_array().unwrap()) {
        assert_eq!(got["name"], *name);
        // pymavlink's view of our frame has our values.
        for (f, want) in fields.as_object().unwrap() {
            let have = &got["fields"][f];
            match want {
                J::Number(n) => assert!(
                    (have.as_f64().unwrap() - n.as_f64().unwrap()).abs()
                        <= 1e-9 * n.as_f64().unwrap().abs().max(1.0),
                    "{name}.{f}: {have} vs {n}"
                ),
                _ => assert_eq!(have, want, "{name}.{f}"),
            }
        }
        // And our decoder reads the same from the same bytes.
        let mut pos = 0;
        let (_, fr) = FrameSplitter::new().next(bytes, &mut pos, &d, true).expect("frame");
        let view = MessageView::of_frame(&fr, &d).unwrap();
        for (f, want) in fields.as_object().unwrap() {
            match want {
                J::Number(n) => assert_eq!(
                    view.get_f64(f).unwrap() as f32,
                    n.as_f64().unwrap() as f32,
                    "{name}.{f}"
                ),
                J::String(s) => assert_eq!(view.get_str(f).unwrap(), *s),
                J::Array(a) => {
                    for (i, x) in a.iter().enumerate() {
                        assert_eq!(view.get_elem(f, i).unwrap().as_f64(), x.as_f64().unwrap());
                    }
                }
                _ => {}
            }
        }
    }
}

/// Uploads crafted by pymavlink: the complete one passes, ACK after 60 of 100 is reported.
#[test]
fn pymavlink_crafted_uploads() {
    let (Some(py), Some(d)) = (python(), dialect()) else {
        return;
    };
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/py/craft_upload.py");
    let dir = std::env::temp_dir().join(format!("vouch-mav-pycraft-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (ack_after, violations) in [(100, 0usize), (60, 1)] {
        let path = dir.join(format!("upload_{ack_after}.tlog"));
        let st = Command::new(&py)
            .args([script, path.to_str().unwrap(), "100", &ack_after.to_string()])
            .status()
            .unwrap();
        assert!(st.success());
        let data = std::fs::read(&path).unwrap();
        let mut m = vouch_mav::Monitor::with_stdlib(d.clone(), &[]).unwrap();
        let r = vouch_mav::monitor::offline::check_tlog(&data, &mut m);
        assert_eq!(r.codec.frames, 2 + 1 + 2 * ack_after as u64 + 1);
        assert_eq!(
            r.violations.len(),
            violations,
            "{:?}",
            r.violations.first().map(|v| v.to_string())
        );
        if violations == 1 {
            let v = &r.violations[0];
            assert_eq!(v.predicate.as_deref(), Some("curr == n"));
            assert!(v.values.contains(&("curr".into(), "60".into())));
        } else {
            assert_eq!(r.summary.protocol("mission_upload").unwrap().completed, 1);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
