//! `vouch fpl validate`, `check` and `sim --jumps` as a user runs them: the walk reaches its
//! fixpoint by default and says so (text and JSON), a depth bound is labelled "bounded", the
//! model checker reports "fixpoint reached", and a jumps file that is not pairs of numbers is
//! rejected at the word.

mod common;

use common::{code, vouch};
use std::path::{Path, PathBuf};
use std::process::Output;

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn demo() -> PathBuf {
    vouch_testkit::repo_root().join("examples/fpl/demo.xml")
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

#[test]
fn validate_reaches_the_fixpoint_by_default() {
    if vouch_testkit::c_compiler().is_none() {
        return;
    }
    let d = demo();
    let o = vouch(&["fpl", "validate", "--json", "--random-runs", "1", s(&d)]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("one JSON document");
    assert_eq!(v["fixpoint"], serde_json::json!(true));
    assert!(v["depth"].is_null());
    assert!(v["states"].as_u64().is_some_and(|n| n > 1), "{v}");
    assert!(v["transitions"].as_u64() >= v["states"].as_u64());
    assert!(v["counterexample"].is_null());
    let text = vouch(&["fpl", "validate", "--random-runs", "0", s(&d)]);
    assert_eq!(code(&text), 0, "{}", stderr(&text));
    assert!(
        stdout(&text).contains("C and semantics agree — fixpoint reached"),
        "{}",
        stdout(&text)
    );
}

#[test]
fn a_depth_bound_is_labelled_bounded() {
    if vouch_testkit::c_compiler().is_none() {
        return;
    }
    let d = demo();
    let o = vouch(&["fpl", "validate", "--depth", "1", "--random-runs", "0", s(&d)]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("bounded (depth 1), not a fixpoint"), "{}", stdout(&o));
    let j = vouch(&["fpl", "validate", "--json", "--depth", "1", "--random-runs", "0", s(&d)]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&j)).expect("one JSON document");
    assert_eq!(
        (v["fixpoint"].clone(), v["depth"].clone()),
        (serde_json::json!(false), serde_json::json!(1))
    );
}

#[test]
fn check_decides_on_the_whole_graph() {
    let d = demo();
    let o = vouch(&["fpl", "check", s(&d)]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(
        stdout(&o).lines().next().is_some_and(|l| l.ends_with("fixpoint reached")),
        "{}",
        stdout(&o)
    );
    let j = vouch(&["fpl", "check", "--json", "--operator", s(&d)]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&j)).expect("one JSON document");
    assert_eq!(v["fixpoint"], serde_json::json!(true));
}

#[test]
fn sim_replays_operator_jumps_and_rejects_a_bad_jumps_file() {
    let d = demo();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fpl_evidence_cli");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let good = dir.join("jumps.txt");
    std::fs::write(&good, "2 1\n2 0\n").expect("write");
    let o = vouch(&["fpl", "sim", s(&d), "--jumps", s(&good), "--steps", "2", "--trace"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let trace = stdout(&o);
    let at = trace.find("step 2").expect("two calls");
    assert!(trace[..at].contains("goto 1\n") && trace[..at].contains("goto 0\n"), "{trace}");
    let bad = dir.join("bad_jumps.txt");
    std::fs::write(&bad, "2 1\n3 x\n").expect("write");
    let o = vouch(&["--message-format", "short", "fpl", "sim", s(&d), "--jumps", s(&bad)]);
    assert_eq!(code(&o), 1);
    assert!(
        stderr(&o).contains("2:3: error[fpl::E044]: not a whole number: 'x'"),
        "{}",
        stderr(&o)
    );
    std::fs::write(&bad, "1 99").expect("write");
    let o = vouch(&["fpl", "sim", s(&d), "--jumps", s(&bad)]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("block 99 does not exist"), "{}", stderr(&o));
}

/// A walk cut by a budget establishes no "holds": `fpl check` on a plan whose calls have more
/// paths than the walk follows reports the properties as holding on the explored part only and
/// exits 3, as `validate` does on a cut walk; the same properties on a small plan exit 0.
#[test]
fn check_on_a_cut_state_space_is_not_a_pass() {
    let plan =
        concat!(env!("CARGO_MANIFEST_DIR"), "/../vouch-fpl/tests/evidence_plans/explode_loops.xml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["fpl", "check", plan, "--no-blocked", "--deadlock-free"])
        .output()
        .expect("runs");
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(3), "{out}");
    assert!(out.contains("not established"), "{out}");
    let demo = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/fpl/demo.xml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["fpl", "check", demo, "--no-blocked", "--deadlock-free"])
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stdout));
}
