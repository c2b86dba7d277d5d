//! `--shard I/N` + `report merge`: the shards partition the cases, and the merged report has the
//! same counts as one unsharded run. Runs on a generated suite (no shared data needed).

use vouch_navfn::campaign::commands::{read_report, report_merge, write_report};
use vouch_navfn::campaign::gen::{generate, GenOptions};
use vouch_navfn::campaign::report::{Report, Shard};
use vouch_navfn::campaign::runner::{run_campaign, CampaignOptions};
use vouch_navfn::campaign::suite_io::write_suite;

#[test]
fn merged_shards_equal_the_unsharded_run() {
    let dir = std::env::temp_dir().join(format!("vouch-campaign-shard-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let maps = generate(&GenOptions {
        seed: 11,
        maps_per_category: 2,
        cases_per_map: 150,
        min_size: 5,
        max_size: 16,
        ..GenOptions::default()
    })
    .expect("gen");
    write_suite(&dir.join("suite"), &maps).expect("write");
    let total_cases: usize = maps.iter().map(|m| m.cases.len()).sum();

    let base = CampaignOptions { unit_cases: 64, ..CampaignOptions::default() };
    let (whole, _) = run_campaign(&dir.join("suite"), &base).expect("runs");
    assert_eq!(whole.cases as usize, total_cases);
    assert_eq!(whole.failures(), 0);

    let mut files = Vec::new();
    for i in 0..3 {
        let opts = CampaignOptions { shard: Shard { index: i, count: 3 }, ..base.clone() };
        let (r, _) = run_campaign(&dir.join("suite"), &opts).expect("shard runs");
        assert!(r.cases > 0 && (r.cases as usize) < total_cases);
        let p = dir.join(format!("shard{i}.json"));
        write_report(&p, &r).expect("write");
        assert_eq!(read_report(&p).expect("read back").cases, r.cases);
        files.push(p);
    }
    let (text, merged) = report_merge(&dir.join("merged.json"), &files).expect("merges");
    assert!(merged.complete());
    assert!(text.contains("TOTAL"));
    let (a, b) = (whole.total(), merged.total());
    assert_eq!(merged.cases, whole.cases);
    assert_eq!(a.outcomes, b.outcomes);
    assert_eq!(a.checks, b.checks);
    assert_eq!(a.metamorphic, b.metamorphic);
    assert_eq!(a.optimality.compared, b.optimality.compared);
    assert_eq!(a.optimality.ratio_hist, b.optimality.ratio_hist);
    assert_eq!(a.optimality.obtuse_paths, b.optimality.obtuse_paths);
    assert_eq!(a.optimality.oscillating_paths, b.optimality.oscillating_paths);
    assert_eq!(a.optimality.ratio_max, b.optimality.ratio_max);
    assert!(
        (a.optimality.navfn_cost_sum - b.optimality.navfn_cost_sum).abs()
            < 1e-6 * a.optimality.navfn_cost_sum
    );
    for (k, v) in &whole.categories {
        assert_eq!(merged.categories[k].maps, v.maps, "{k}: maps counted once");
        assert_eq!(merged.categories[k].cases, v.cases, "{k}");
    }
    // A shard given twice is refused.
    assert!(Report::merge(&[
        read_report(&files[0]).expect("r"),
        read_report(&files[0]).expect("r")
    ])
    .is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
