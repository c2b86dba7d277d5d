//! The differential harness against an oracle: itself (all equal), then a deliberately
//! perturbed oracle (priInc 100 → 99, behind the hidden `--perturb-pri-inc` flag): the harness
//! must pinpoint the first diverging cycle, which we know independently from vouch's own trace:
//! it is the first cycle whose threshold has been raised by priInc.

use std::path::PathBuf;

use vouch_navfn::campaign::diff::{DiffOptions, describe, diff_file, diff_suite};
use vouch_navfn::campaign::exec::run_case;
use vouch_navfn::campaign::grid::SuiteMap;
use vouch_navfn::campaign::oracle::{EmitOptions, emit_file, parse_answers};
use vouch_navfn::campaign::suite_io::read_test_file;
use vouch_navfn::campaign::trace::TraceDetail;
use vouch_navfn::maps::read_suite_file;
use vouch_navfn::suite::CaseRunner;
use vouch_navfn::suite::RunMode;

fn suite() -> Option<PathBuf> {
    vouch_testkit::shared("navfn", "SEMANTICS.md").map(|p| p.join("suite"))
}

const ORACLE: &str = env!("CARGO_BIN_EXE_navfn-oracle");

#[test]
fn vouch_agrees_with_itself_black_and_white_box() {
    let Some(suite) = suite() else { return };
    let opts = DiffOptions {
        oracle: ORACLE.into(),
        mode: RunMode::Paper,
        white_box: Some(TraceDetail::Hash),
        perturb_pri_inc: None,
    };
    let r = diff_suite(&suite.join("walls"), &opts).expect("diff runs");
    println!("{}", describe(&r));
    assert_eq!(r.files, 20);
    assert_eq!(r.cases, 27_947);
    assert_eq!(r.different, 0);
    assert!(r.mismatches.is_empty());
}

#[test]
fn perturbed_oracle_is_pinpointed_at_the_first_diverging_cycle() {
    let Some(suite) = suite() else { return };
    let file = suite.join("spiral/10x10_spiral/test.txt");
    let file = if file.is_file() {
        file
    } else {
        vouch_navfn::maps::find_test_files(&suite.join("spiral"), "test.txt").expect("spiral")[0]
            .clone()
    };
    let oracle = format!("{ORACLE} --perturb-pri-inc 99");
    let opts = DiffOptions {
        oracle,
        mode: RunMode::Paper,
        white_box: Some(TraceDetail::Hash),
        perturb_pri_inc: None,
    };
    let (equal, different, first) = diff_file(&file, &opts).expect("diff runs");
    assert!(different > 0, "a changed priInc must show on a spiral map");
    let m = first.expect("first mismatch reported");
    println!("{equal} equal, {different} different; first: {m:?}");
    let d = m.divergence.clone().expect("white-box divergence found");

    // Independent expectation: vouch's own trace of that case. The perturbed run is identical
    // up to the first cycle that starts with a raised threshold (A*: 254 + heuristic, then
    // + 100 in vouch but + 99 in the perturbed oracle).
    let sm: SuiteMap = read_test_file(&file, "spiral", "x").expect("reads");
    let mut costs = sm.clone();
    costs.stamp_border();
    let mut runner = CaseRunner::new();
    let run = run_case(
        &mut runner,
        &sm,
        &costs.costs,
        &sm.cases[m.case],
        RunMode::Paper,
        Some(TraceDetail::Hash),
    )
    .expect("runs");
    let trace = run.trace.expect("traced");
    let t0 = trace.cycles[0].threshold_bits;
    let first_raise =
        trace.cycles.iter().find(|c| c.threshold_bits != t0).expect("threshold raised");
    assert_eq!(d.cycle, first_raise.cycle, "diverging cycle");
    assert_eq!(d.what, "thr");
    let ours = f32::from_bits(first_raise.threshold_bits);
    assert!(d.detail.starts_with(&format!("threshold {ours} ")), "{}", d.detail);
    assert!(d.detail.contains(&format!("vs {} ", ours - 1.0)), "{}", d.detail);
    println!(
        "{}",
        describe(&vouch_navfn::campaign::diff::DiffReport {
            files: 1,
            cases: equal + different,
            equal,
            different,
            mismatches: vec![m]
        })
    );
}

#[test]
fn own_output_round_trips_through_the_contract_parser() {
    let Some(suite) = suite() else { return };
    let f = read_suite_file(&suite.join("circus/circus_5L/test.txt")).expect("reads");
    let mut text = String::new();
    emit_file(
        &f,
        &EmitOptions {
            mode: RunMode::Paper,
            trace: Some(TraceDetail::Cells),
            pot: true,
            perturb_pri_inc: None,
        },
        &mut text,
    )
    .expect("runs");
    let a = parse_answers(&text).expect("parses");
    assert_eq!(a.len(), 2);
    // Golden first case: circus/circus_5L/paper_astar.txt line 1 (golden/README.md example).
    assert_eq!(a[&0].fields["pot_fnv"], "76c9e5c2033ce832");
    assert_eq!(a[&0].fields["path_fnv"], "ea4cd8cb1b2a0255");
    assert_eq!(a[&0].path[0], "40000000:40a00000");
    assert_eq!(a[&0].pot.as_ref().map(Vec::len), Some(35));
    assert!(!a[&0].trace.cycles.is_empty());
    assert_eq!(a[&0].trace.end.as_ref().map(|e| e.end.as_str()), Some("start_reached"));
}
