//! The `vouch mav` commands as a user runs them: exit codes (0 ok, 1 input rejected, 2 usage or
//! I/O error, 3 violations), located diagnostics, help texts, and output into a closed pipe.

mod common;

use common::{code, vouch};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use vouch_mav::codec::MessageBuilder;
use vouch_mav::dialect::Dialect;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mav_cli");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    dir.join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// A recording of `n` parachute releases (COMMAND_LONG DO_PARACHUTE, param1 = 2) from a GCS
/// while nothing is known about the vehicle: each one violates `datum_parachute`.
fn parachute_recording(n: u32) -> Option<PathBuf> {
    let d = match Dialect::default_dialect() {
        Ok(d) => d,
        Err(e) => {
            let need = vouch_testkit::Need::Shared;
            return vouch_testkit::missing(need, &format!("no default dialect ({e})"));
        }
    };
    let mut bytes = Vec::new();
    let mut t = 1_700_000_000_000_000u64;
    for i in 0..n {
        let frame = MessageBuilder::new(&d, "COMMAND_LONG")
            .and_then(|b| b.set("target_system", 1))
            .and_then(|b| b.set("target_component", 1))
            .and_then(|b| b.set("command", 208))
            .and_then(|b| b.set("param1", 2))
            .expect("COMMAND_LONG fields")
            .frame_v2(i as u8, 255, 190);
        t += 10_000;
        bytes.extend_from_slice(&t.to_be_bytes());
        bytes.extend_from_slice(&frame);
    }
    let p = tmp(&format!("parachute{n}.tlog"));
    std::fs::write(&p, bytes).expect("write tlog");
    Some(p)
}

#[test]
fn check_into_a_closed_pipe_ends_quietly_with_exit_0() {
    let Some(tlog) = parachute_recording(3000) else { return };
    // Without a reader that goes away: every release is reported, far more than a pipe buffer.
    let full = vouch(&["mav", "check", s(&tlog), "--max-reports", "100000"]);
    assert_eq!(code(&full), 3, "{}", stderr(&full));
    assert!(full.stdout.len() > 256 * 1024, "{} bytes", full.stdout.len());
    // `vouch mav check F | head -c 100`: the reader closes the pipe after a few bytes.
    let mut child = Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["mav", "check", s(&tlog), "--max-reports", "100000"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("vouch starts");
    let mut head = [0u8; 100];
    child.stdout.take().expect("stdout").read_exact(&mut head).expect("first bytes");
    let out = child.wait_with_output().expect("vouch ends");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).is_empty(), "quiet: {}", stderr(&out));
    assert!(String::from_utf8_lossy(&head).starts_with(s(&tlog)));
}

#[test]
fn check_reports_violations_as_text_json_or_into_a_file() {
    let Some(tlog) = parachute_recording(3) else { return };
    let json = vouch(&["mav", "check", s(&tlog), "--json"]);
    assert_eq!(code(&json), 3, "{}", stderr(&json));
    let doc: serde_json::Value = serde_json::from_slice(&json.stdout).expect("one JSON document");
    assert_eq!(doc["violations"], 3);
    assert_eq!(doc["files"][0]["report"]["violations"][0]["protocol"], "datum_parachute");
    let out = tmp("report.txt");
    let _ = std::fs::remove_file(&out);
    let to_file = vouch(&["mav", "check", s(&tlog), "-o", s(&out)]);
    assert_eq!(code(&to_file), 3, "{}", stderr(&to_file));
    assert!(to_file.stdout.is_empty());
    let text = std::fs::read_to_string(&out).expect("report written");
    assert!(text.contains("violations: 3"), "{text}");
    let missing = vouch(&["mav", "check", "/nonexistent/x.tlog"]);
    assert_eq!(code(&missing), 2, "{}", stderr(&missing));
}

#[test]
fn protocol_errors_are_located_with_a_code() {
    let bad = tmp("bad.vproto");
    std::fs::write(&bad, "protocol x {\n  roles gcs, uav;\n  gcs -> uav : NOPE;\n}\n").unwrap();
    let o = vouch(&["--message-format", "short", "mav", "lint", s(&bad)]);
    assert_eq!(code(&o), 1);
    let want = format!("{}:3:16: error[mav::P003]: unknown message `NOPE`", bad.display());
    assert!(stderr(&o).starts_with(&want), "{}", stderr(&o));
    let o = vouch(&["--message-format", "json", "mav", "check", "--protocol", s(&bad), "x.tlog"]);
    assert_eq!(code(&o), 1);
    let d: serde_json::Value = serde_json::from_str(stderr(&o).trim()).expect("one JSON line");
    assert_eq!((d["code"].as_str(), d["line"].as_u64()), (Some("mav::P003"), Some(3)));
    let ok = vouch(&["mav", "lint"]);
    assert_eq!(code(&ok), 0, "{}", stderr(&ok));
    let text = String::from_utf8_lossy(&ok.stdout);
    assert!(text.contains("ok: protocol mission_upload"), "{text}");
    // the policy for unverifiable answers is stated per protocol
    assert!(
        text.contains("datum_parachute") && text.contains("unverifiable answers: drop"),
        "{text}"
    );
    assert!(text.contains("unverifiable answers: pass"), "{text}");
    let no_dialect = vouch(&["mav", "lint", "--dialect", "/nonexistent/d.xml"]);
    assert_eq!(code(&no_dialect), 2, "{}", stderr(&no_dialect));
}

#[test]
fn guard_exit_codes() {
    let base = ["mav", "guard", "--gcs", "udpin:127.0.0.1:0", "--vehicle", "udpout:127.0.0.1:9"];
    let run = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        vouch(&args)
    };
    // clean runs stopped by --duration; --json puts the counters on stdout
    let o = run(&["--duration", "0.2", "--json"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let c: serde_json::Value = serde_json::from_slice(&o.stdout).expect("counters as JSON");
    assert_eq!(c["violations"], 0);
    assert!(stderr(&o).contains("protocol(s): mission_upload"), "{}", stderr(&o));
    assert_eq!(code(&run(&["--duration", "0.2", "--relay-only"])), 0);
    // usage errors
    for extra in [
        &["--duration", "-1"][..],
        &["--sign-to-vehicle", "--duration", "0.2"],
        &["--signing-key", "/nonexistent/key", "--duration", "0.2"],
        &["--set", "NOVALUE", "--duration", "0.2"],
    ] {
        let o = run(extra);
        assert_eq!(code(&o), 2, "{extra:?}: {}", stderr(&o));
    }
    let o = vouch(&["mav", "guard", "--gcs", "udpin:nowhere", "--vehicle", "udpout:127.0.0.1:9"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    // a constant that no protocol declares, and a protocol file that does not parse: rejected
    let o = run(&["--set", "NOPE=1", "--duration", "0.2"]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("mav::P008"), "{}", stderr(&o));
    let bad = tmp("broken.vproto");
    std::fs::write(&bad, "protocol broken { nonsense").unwrap();
    assert_eq!(code(&run(&["--protocol", s(&bad), "--duration", "0.2"])), 1);
}

#[test]
fn every_mav_subcommand_has_help_with_an_example() {
    for sub in ["check", "lint", "guard", "bench"] {
        let o = vouch(&["mav", sub, "--help"]);
        assert_eq!(code(&o), 0);
        let help = String::from_utf8_lossy(&o.stdout);
        assert!(help.contains(&format!("Example:\n  vouch mav {sub}")), "{sub}: {help}");
        assert!(!help.contains("../shared"), "{sub}: no default points into ../shared");
    }
}
