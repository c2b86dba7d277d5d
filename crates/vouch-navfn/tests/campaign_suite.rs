//! The campaign on the paper's whole suite (121,404 cases): every property must hold, the
//! outcome counts must match the golden README, the optimality statistics are printed.

use std::path::PathBuf;

use vouch_navfn::campaign::runner::{CampaignOptions, run_campaign};
use vouch_navfn::campaign::summary::summary_table;

fn shared() -> Option<PathBuf> {
    vouch_testkit::shared("navfn", "SEMANTICS.md")
}

#[test]
fn campaign_on_paper_suite_holds_every_property() {
    let Some(shared) = shared() else { return };
    let opts = CampaignOptions::default();
    let report = run_campaign(&shared.join("suite"), &opts, &(), None).expect("campaign runs");
    println!("{}", summary_table(&report));
    let t = report.total();
    assert_eq!(report.cases, 121_404);
    // Outcome statistics of paper mode from shared/navfn/golden/README.md.
    assert_eq!(t.outcomes.found, 71_915);
    assert_eq!(t.outcomes.start_is_goal, 2_092);
    assert_eq!(t.outcomes.unreachable, 34_034);
    assert_eq!(t.outcomes.cycle_limit, 13_340);
    assert_eq!(t.outcomes.path_failed, 23);
    for (name, pf) in &t.checks {
        assert_eq!(pf.fail, 0, "check {name} failed {} times", pf.fail);
        assert!(pf.pass > 0, "check {name} never ran");
    }
    for (name, pf) in t.metamorphic.iter().filter(|(k, _)| k.exact()) {
        assert_eq!(pf.fail, 0, "exact relation {name} failed {} times", pf.fail);
    }
    assert_eq!(report.failures(), 0);
    // Every found path (start ≠ goal) is compared with the optimum (all are 8-connected).
    assert_eq!(t.optimality.compared, 71_915);
    // The derived bound: NavFn's cell path is an 8-connected path of traversable cells (every
    // ValidPath check passed above) costed in the optimum's metric, so it cannot be cheaper
    // than the optimum; only f64 summation order may differ (costs < 10^6, error < 10^-6).
    assert!(
        t.optimality.excess_min >= -1e-6,
        "a path below the optimum: {}",
        t.optimality.excess_min
    );
    println!(
        "optimality: excess {:.2} %, ratio max {:.3}, {} paths above ×{}",
        t.optimality.excess_percent(),
        t.optimality.ratio_max,
        t.optimality.suboptimal_paths,
        opts.suboptimal_ratio
    );
    // golden/README.md: 152 oscillation detections in paper mode; the paper: 0.13 % of the paths.
    assert_eq!(t.optimality.oscillating_paths, 152);
    // The paper: obtuse turns in 1.91 % of the paths (oscillations excluded).
    let obtuse_pct = 100.0 * t.optimality.obtuse_paths as f64 / report.cases as f64;
    assert!((1.7..2.1).contains(&obtuse_pct), "obtuse turns in {obtuse_pct:.2} % of the cases");
    println!(
        "wall time {:.2} s on {} threads ({} cases, all checks, 6 metamorphic transforms per case)",
        report.runs[0].wall_seconds, report.runs[0].threads, report.cases
    );
}

#[test]
fn campaign_in_planner_dijkstra_mode_matches_golden_outcomes() {
    let Some(shared) = shared() else { return };
    let opts = CampaignOptions {
        mode: vouch_navfn::suite::RunMode::NavfnDijkstra,
        metamorphic: false,
        ..CampaignOptions::default()
    };
    let report = run_campaign(&shared.join("suite"), &opts, &(), None).expect("campaign runs");
    let t = report.total();
    // golden/README.md, navfn mode Dijkstra: 73,800 + 2,092 found, 20 calcPath exhausted.
    assert_eq!(t.outcomes.found, 73_800);
    assert_eq!(t.outcomes.start_is_goal, 2_092);
    assert_eq!(t.outcomes.path_failed, 20);
    // Connectivity does not depend on the mode.
    assert_eq!(t.outcomes.unreachable, 34_034);
    assert_eq!(report.failures(), 0);
    println!(
        "navfn-dijkstra: obtuse {} oscillating {} of {} cases; wall {:.2} s",
        t.optimality.obtuse_paths,
        t.optimality.oscillating_paths,
        report.cases,
        report.runs[0].wall_seconds
    );
}
