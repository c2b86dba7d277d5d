//! The bad-input catalogue of `vouch mav check` and `vouch mav lint`: every input a user or an
//! attacker may hand them, each with the `mav::` code and the exit status it must get (0 ok,
//! 1 input rejected, 2 usage or I/O error, 3 findings), no panic, and no control character of
//! the input on the terminal. A checker never passes what it could not read.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use vouch_mav::codec::MessageBuilder;
use vouch_mav::dialect::Dialect;

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mav_bad_inputs");
    std::fs::create_dir_all(&d).expect("tmp dir");
    d
}

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir().join(name);
    std::fs::write(&p, bytes).expect("write input");
    p
}

/// Deterministic noise (SplitMix64), so that a failure can be reproduced.
fn noise(n: usize, mut seed: u64) -> Vec<u8> {
    (0..n)
        .map(|_| {
            seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            (z ^ (z >> 31)) as u8
        })
        .collect()
}

/// One tlog record: timestamp + a MAVLink 2 frame of `msg` with `fields`, sent as `from`.
fn record(d: &Dialect, t: u64, msg: &str, fields: &[(&str, f64)], from: (u8, u8)) -> Vec<u8> {
    let mut b = MessageBuilder::new(d, msg).expect("message in the dialect");
    for (f, v) in fields {
        b = b.set(f, *v).expect("field of the message");
    }
    let mut r = t.to_be_bytes().to_vec();
    r.extend_from_slice(&b.frame_v2(0, from.0, from.1));
    r
}

const T0: u64 = 1_700_000_000_000_000;

/// A vehicle heartbeat and a ground-station heartbeat: a clean recording.
fn clean(d: &Dialect) -> Vec<u8> {
    let mut v = record(d, T0, "HEARTBEAT", &[("type", 2.0), ("autopilot", 3.0)], (1, 1));
    v.extend(record(d, T0 + 1000, "HEARTBEAT", &[("type", 6.0), ("autopilot", 8.0)], (255, 190)));
    v
}

/// A parachute release while nothing is known of the vehicle: a violation of `datum_parachute`.
fn release(d: &Dialect) -> Vec<u8> {
    let mut v = clean(d);
    let fields =
        [("target_system", 1.0), ("target_component", 1.0), ("command", 208.0), ("param1", 2.0)];
    v.extend(record(d, T0 + 2000, "COMMAND_LONG", &fields, (255, 190)));
    v
}

struct Case {
    name: &'static str,
    args: Vec<String>,
    exit: i32,
    /// The code of the error (or warning) diagnostic, if one is expected.
    code: Option<&'static str>,
}

fn case(name: &'static str, args: &[&str], exit: i32, code: Option<&'static str>) -> Case {
    Case { name, args: args.iter().map(|s| s.to_string()).collect(), exit, code }
}

fn p(path: &Path) -> String {
    path.to_str().expect("utf-8 path").to_string()
}

fn catalogue(d: &Dialect) -> Vec<Case> {
    let clean_f = p(&write("clean.tlog", &clean(d)));
    let release_f = p(&write("release.tlog", &release(d)));
    let mut truncated = clean(d);
    truncated.truncate(8 + 6); // a timestamp and the first bytes of a frame
    let truncated_f = p(&write("truncated.tlog", &truncated));
    let mut noisy = clean(d);
    noisy.extend(noise(400, 7)); // far more than the small fraction a radio loses
    let noisy_f = p(&write("noisy.tlog", &noisy));
    let ctl_name = "ctl\u{1b}]0;pwned\u{7}.tlog";
    let ctl_f = p(&write(ctl_name, b"\x1b]0;pwned\x07\x1b[2J\x9b31m"));
    let huge_f = p(&write("huge.tlog", &vec![0xfd; 16 << 20]));
    let xml_f = p(&write("plan.tlog", b"<?xml version=\"1.0\"?>\n<flight_plan name=\"x\"/>\n"));
    let empty_f = p(&write("empty.tlog", b""));
    let random_f = p(&write("random.tlog", &noise(3000, 1)));
    let missing = p(&dir().join("missing.tlog"));
    let directory = p(&dir());
    let empty_v = p(&write("empty.vproto", b""));
    let comments_v = p(&write("comments.vproto", b"// nothing here\nconst X = 1;\n"));
    let random_v = p(&write("random.vproto", &noise(2000, 2)));
    let ctl_v = p(&write("ctl.vproto", b"protocol \x1b]0;pwned\x07 { }\n"));
    let huge_v = p(&write("huge.vproto", &vec![b'x'; 1 << 20]));
    let tlog_v = p(&write("recording.vproto", &clean(d)));
    let missing_v = p(&dir().join("missing.vproto"));
    vec![
        case("a clean recording", &["mav", "check", &clean_f], 0, None),
        case("a recording with a violation", &["mav", "check", &release_f], 3, None),
        case("missing recording", &["mav", "check", &missing], 2, Some("mav::T001")),
        case("a directory as recording", &["mav", "check", &directory], 2, Some("mav::T001")),
        case("empty recording", &["mav", "check", &empty_f], 1, Some("mav::T002")),
        case("random bytes", &["mav", "check", &random_f], 1, Some("mav::T002")),
        case("truncated frame", &["mav", "check", &truncated_f], 1, Some("mav::T002")),
        case("16 MB of frame-start bytes", &["mav", "check", &huge_f], 1, Some("mav::T002")),
        case("control characters", &["mav", "check", &ctl_f], 1, Some("mav::T002")),
        case("XML with a .tlog extension", &["mav", "check", &xml_f], 1, Some("mav::T002")),
        case("frames and much garbage", &["mav", "check", &noisy_f], 0, Some("mav::T003")),
        case(
            "one unreadable file among good ones",
            &["mav", "check", &clean_f, &empty_f],
            1,
            Some("mav::T002"),
        ),
        case("empty protocol file", &["mav", "lint", &empty_v], 1, Some("mav::P006")),
        case("constants only", &["mav", "lint", &comments_v], 1, Some("mav::P006")),
        case("random protocol bytes", &["mav", "lint", &random_v], 1, Some("mav::M002")),
        case("control characters in a protocol", &["mav", "lint", &ctl_v], 1, Some("mav::P001")),
        case("a 1 MB line", &["mav", "lint", &huge_v], 1, Some("mav::P002")),
        case("a recording as protocol", &["mav", "lint", &tlog_v], 1, Some("mav::M002")),
        case("missing protocol file", &["mav", "lint", &missing_v], 2, Some("mav::M001")),
        case("a directory as protocol", &["mav", "lint", &directory], 2, Some("mav::M001")),
        case(
            "bad protocol for check",
            &["mav", "check", "--protocol", &empty_v, &clean_f],
            1,
            Some("mav::P006"),
        ),
    ]
}

/// Control characters other than the line ends of the output itself.
fn raw_controls(bytes: &[u8]) -> bool {
    String::from_utf8_lossy(bytes).chars().any(|c| c.is_control() && c != '\n' && c != '\r')
}

fn run(args: &[String], format: &str) -> Output {
    let mut all = vec!["--message-format", format];
    all.extend(args.iter().map(String::as_str));
    common::vouch(&all)
}

#[test]
fn every_bad_input_gets_its_code_and_exit_status_and_nothing_raw() {
    let d = match Dialect::default_dialect() {
        Ok(d) => d,
        Err(e) => {
            let _: Option<()> = vouch_testkit::missing(
                vouch_testkit::Need::Shared,
                &format!("no default dialect ({e})"),
            );
            return;
        }
    };
    let mut failures = Vec::new();
    for c in catalogue(&d) {
        let json = run(&c.args, "json");
        let short = run(&c.args, "short");
        let err = String::from_utf8_lossy(&json.stderr).into_owned();
        let mut problems = Vec::new();
        if json.status.code() != Some(c.exit) || short.status.code() != Some(c.exit) {
            problems.push(format!("exit {:?}, expected {}", json.status.code(), c.exit));
        }
        let codes: Vec<String> = err
            .lines()
            .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
            .filter_map(|v| v["code"].as_str().map(str::to_string))
            .collect();
        match c.code {
            Some(want) if !codes.iter().any(|g| g == want) => {
                problems.push(format!("codes {codes:?}, expected {want}"))
            }
            None if !codes.is_empty() => problems.push(format!("unexpected codes {codes:?}")),
            _ => {}
        }
        if (c.exit == 1 || c.exit == 2)
            && !String::from_utf8_lossy(&short.stderr).contains(c.code.unwrap_or("mav::"))
        {
            problems.push("the short diagnostic has no code".into());
        }
        for o in [&json, &short] {
            if String::from_utf8_lossy(&o.stderr).contains("panicked") {
                problems.push("panicked".into());
            }
            if raw_controls(&o.stdout) || raw_controls(&o.stderr) {
                problems.push("a raw control character reached the output".into());
            }
        }
        if !problems.is_empty() {
            failures.push(format!("{}: {} (stderr: {err})", c.name, problems.join("; ")));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn json_reports_unread_bytes_and_files_that_could_not_be_checked() {
    let Ok(d) = Dialect::default_dialect() else { return };
    let mut noisy = clean(&d);
    let good = noisy.len() as u64;
    noisy.extend(noise(400, 3));
    let noisy_f = write("noisy_json.tlog", &noisy);
    let empty_f = write("empty_json.tlog", b"");
    let o = common::vouch(&["mav", "check", "--json", &p(&noisy_f), &p(&empty_f)]);
    assert_eq!(common::code(&o), 1, "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    assert_eq!(doc["version"], 2);
    assert_eq!(doc["unreadable_files"], 1);
    let r = &doc["files"][0]["report"];
    assert_eq!(r["bytes"], good + 400);
    // Every byte after the two records is noise; noise may hold no frame record.
    assert_eq!(r["unread_bytes"], 400);
    assert_eq!(doc["files"][0]["warnings"][0]["code"], "mav::T003");
    assert_eq!(doc["files"][1]["error"]["code"], "mav::T002");
}
