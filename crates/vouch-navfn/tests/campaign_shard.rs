//! `--shard I/N` + `report merge`: the shards partition the cases, and the merged report has the
//! same counts as one unsharded run. Runs on a generated suite (no shared data needed).

use std::path::Path;

use vouch_navfn::campaign::gen::{generate, GenOptions};
use vouch_navfn::campaign::report::{Report, Shard};
use vouch_navfn::campaign::runner::{run_campaign, CampaignOptions};
use vouch_navfn::campaign::suite_io::write_suite;
use vouch_navfn::campaign::summary::summary_table;

fn write_report(p: &Path, r: &Report) {
    std::fs::write(p, serde_json::to_string_pretty(r).expect("json")).expect("written");
}

fn read_report(p: &Path) -> Report {
    Report::from_json(p, &std::fs::read_to_string(p).expect("read")).expect("a report")
}

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
    let (whole, _) = run_campaign(&dir.join("suite"), &base, &()).expect("runs");
    assert_eq!(whole.cases as usize, total_cases);
    assert_eq!(whole.failures(), 0);

    let mut files = Vec::new();
    for i in 0..3 {
        let opts = CampaignOptions { shard: Shard { index: i, count: 3 }, ..base.clone() };
        let (r, _) = run_campaign(&dir.join("suite"), &opts, &()).expect("shard runs");
        assert!(r.cases > 0 && (r.cases as usize) < total_cases);
        let p = dir.join(format!("shard{i}.json"));
        write_report(&p, &r);
        let back = read_report(&p);
        assert_eq!(
            (back.cases, back.mode, back.findings.len()),
            (r.cases, r.mode, r.findings.len())
        );
        assert_eq!(back.total().checks, r.total().checks);
        assert_eq!(back.total().metamorphic, r.total().metamorphic);
        files.push(p);
    }
    let shards: Vec<Report> = files.iter().map(|p| read_report(p)).collect();
    let merged = Report::merge(&shards).expect("merges");
    assert!(merged.complete());
    assert!(summary_table(&merged).contains("TOTAL"));
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
    assert!(Report::merge(&[read_report(&files[0]), read_report(&files[0])]).is_err());
    // A damaged report is refused with its position.
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{\n  \"suite\": 3\n}").expect("written");
    let e = Report::from_json(&bad, &std::fs::read_to_string(&bad).expect("read")).unwrap_err();
    assert!(e.to_string().contains("bad.json:2:"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
