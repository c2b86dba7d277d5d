//! Every case of the paper's suite, bit-exact against the C++ goldens in
//! `shared/navfn/golden/<category>/<map>/{paper_astar,navfn_dijkstra}.txt`.

mod common;

use vouch_navfn::core::Algo;
use vouch_navfn::maps::{find_test_files, read_suite_file};
use vouch_navfn::planner::WorldParams;
use vouch_navfn::suite::{CostInput, SuiteMode, SuiteOptions, run_file};

fn check_mode(mode: SuiteMode, algo: Algo, golden_name: &str) {
    let Some(shared) = common::shared_navfn() else { return };
    let suite = shared.join("suite");
    let files = find_test_files(&suite, "test.txt").expect("suite readable");
    assert_eq!(files.len(), 101, "the suite has 101 maps");
    let opts = SuiteOptions { mode, algo, costs: CostInput::Raw, world: WorldParams::default() };
    let (mut total, mut equal) = (0, 0);
    let mut failures = Vec::new();
    for f in &files {
        let suite_file = read_suite_file(f).expect("suite file parses");
        let mut out = String::new();
        run_file(&suite_file, &opts, &mut out).expect("cases run");
        let rel = f.parent().unwrap().strip_prefix(&suite).unwrap();
        let golden_path = shared.join("golden").join(rel).join(golden_name);
        let golden = std::fs::read_to_string(&golden_path).expect("golden present");
        let (n, eq, diff) = common::compare(&out, &golden);
        total += n;
        equal += eq;
        if let Some(d) = diff {
            failures.push(format!("{}: {eq}/{n} equal; first difference {d}", rel.display()));
        }
    }
    println!("{golden_name}: {equal} / {total} cases bit-exact");
    assert!(failures.is_empty(), "{} maps differ:\n{}", failures.len(), failures.join("\n"));
    assert_eq!(total, 121_404);
    assert_eq!(equal, 121_404);
}

#[test]
fn paper_mode_astar_is_bit_exact() {
    check_mode(SuiteMode::Paper, Algo::Astar, "paper_astar.txt");
}

#[test]
fn navfn_mode_dijkstra_is_bit_exact() {
    check_mode(SuiteMode::Navfn, Algo::Dijkstra, "navfn_dijkstra.txt");
}
