//! The campaign on the paper's whole suite (121,404 cases): every property must hold, the
//! outcome counts must match the golden README, the optimality statistics are printed.

use std::path::PathBuf;

use vouch_navfn::campaign::report::summary_table;
use vouch_navfn::campaign::runner::{run_campaign, CampaignOptions};

fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/navfn");
    if p.join("suite").is_dir() {
        Some(p)
    } else {
        eprintln!("skipping: {} not found", p.display());
        None
    }
}

#[test]
fn campaign_on_paper_suite_holds_every_property() {
    let Some(shared) = shared() else { return };
    let opts = CampaignOptions::default();
    let (report, _) = run_campaign(&shared.join("suite"), &opts).expect("campaign runs");
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
    for (name, pf) in t.metamorphic.iter().filter(|(k, _)| !k.starts_with("approx")) {
        assert_eq!(pf.fail, 0, "exact relation {name} failed {} times", pf.fail);
    }
    assert_eq!(report.failures(), 0);
    assert!(t.optimality.compared > 70_000);
}
