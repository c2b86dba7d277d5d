//! The run-time checks hold on every plan of the paper's suite (both modes): 2 × 121,404
//! plans of the real NavFn semantics, so a check that is too strict would show up here.

mod common;

use vouch_navfn::checks::{check_plan, PlanView};
use vouch_navfn::core::{Algo, NoObserver};
use vouch_navfn::maps::{find_test_files, read_suite_file};
use vouch_navfn::suite_run::{CaseRunner, CostInput, SuiteMode};

#[test]
fn checks_hold_on_every_suite_plan() {
    let Some(shared) = common::shared_navfn() else { return };
    let files = find_test_files(&shared.join("suite"), "test.txt").expect("suite readable");
    let mut runner = CaseRunner::new();
    let (mut plans, mut paths) = (0usize, 0usize);
    let mut bad = Vec::new();
    for f in &files {
        let file = read_suite_file(f).expect("parses");
        for case in &file.cases {
            for (mode, algo) in [(SuiteMode::Paper, Algo::Astar), (SuiteMode::Navfn, Algo::Dijkstra)] {
                let o = runner.run_case(&file, case, mode, algo, CostInput::Raw, &mut NoObserver).unwrap();
                let report = check_plan(&PlanView::of(runner.nav()));
                plans += 1;
                paths += (o.len > 0) as usize;
                if !report.is_ok() && bad.len() < 10 {
                    bad.push(format!("{} case {} {mode:?}: {:?}", f.display(), case.number, report.violations));
                }
            }
        }
    }
    println!("checked {plans} plans ({paths} with a path)");
    assert_eq!(plans, 2 * 121_404);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
