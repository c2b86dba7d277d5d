//! `vouch fpl validate --target …` and its budgets as a user runs them: the demo on the
//! emulated Cortex-M4 (exit 0, the report names the build), `--cflags` replacing the flags,
//! a walk a budget cuts short (exit 3, the cut state named; also the emulated board's memory
//! for join points), and a missing emulator (exit 2,
//! `fpl::E054`).

mod common;

use std::path::{Path, PathBuf};

use common::{code, vouch};

fn plan(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

fn arm_peers() -> bool {
    vouch_testkit::program("arm-none-eabi-gcc", "--version").is_some()
        && vouch_testkit::program("qemu-system-arm", "--version").is_some()
}

#[test]
fn the_demo_validates_on_cortex_m4_and_the_report_names_the_build() {
    if !arm_peers() {
        return;
    }
    let demo = plan("examples/fpl/demo.xml");
    let d = demo.to_str().expect("utf-8 path");
    let o = vouch(&["fpl", "validate", "--target", "cortex-m4", "--json", "--random-runs", "1", d]);
    assert_eq!(code(&o), 0, "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    assert_eq!(j["target"], "cortex-m4");
    assert_eq!(j["fixpoint"], true);
    let built = j["built"].as_str().expect("built");
    assert!(built.contains("-mcpu=cortex-m4") && built.contains("mps2-an386"), "{built}");
    let flags = "-mcpu=cortex-m4 -mthumb -O0";
    let o = vouch(&[
        "fpl",
        "validate",
        "--target",
        "cortex-m4",
        "--cflags",
        flags,
        "--random-runs",
        "0",
        d,
    ]);
    assert_eq!(code(&o), 0);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -O0,"), "{text}");
}

#[test]
fn a_walk_cut_by_the_path_budget_exits_3_and_names_the_cut_state() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let wide = plan("crates/vouch-fpl/tests/evidence_plans/wide.xml");
    let w = wide.to_str().expect("utf-8 path");
    // the first call makes 511 runs (its 33,151 paths joined where each loop is left)
    let o = vouch(&["fpl", "validate", "--max-paths", "300", "--random-runs", "0", w]);
    assert_eq!(code(&o), 3);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(
            "NOT ESTABLISHED for the whole plan: 1 state(s) cut — block 0 'Grid' stage 0"
        ),
        "{text}"
    );
    let o = vouch(&["fpl", "validate", "--random-runs", "0", w]);
    assert_eq!(code(&o), 0, "{}", String::from_utf8_lossy(&o.stdout));
}

/// On the emulated core the join points of one call may take 1 MiB: a call that needs more
/// is cut — exit 3, the reason and the state named — not reported as a crash.
#[test]
fn a_call_beyond_the_boards_memory_for_join_points_is_cut() {
    if !arm_peers() {
        return;
    }
    let ranges = plan("crates/vouch-fpl/tests/evidence_plans/explode_ranges.xml");
    let r = ranges.to_str().expect("utf-8 path");
    let args = ["fpl", "validate", "--target", "cortex-m4", "--depth", "1", "--random-runs", "0"];
    let o = vouch(&[&args[..], &[r]].concat());
    assert_eq!(code(&o), 3, "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("C and semantics agree"), "{text}");
    assert!(text.contains("the C side had no memory left for the join points"), "{text}");
    assert!(text.contains("1 state(s) cut — block 0 'Chain' stage 0"), "{text}");
}

#[test]
fn a_missing_emulator_is_a_usage_error() {
    let demo = plan("examples/fpl/demo.xml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["fpl", "validate", "--target", "cortex-m7", demo.to_str().expect("utf-8")])
        .env("VOUCH_QEMU_ARM", "/nonexistent/qemu-system-arm")
        .output()
        .expect("runs");
    assert_eq!(code(&o), 2);
    assert!(String::from_utf8_lossy(&o.stderr).contains("fpl::E054"));
}
