//! The campaign on a real distributed engine: a local Dask cluster of two worker processes runs
//! the paper's suite in 8 shards as 8 tasks (`crates/vouch-navfn/distributed/dask_campaign.py`
//! driving this `vouch`), the driver gathers the shard reports and merges them with
//! `vouch navfn report merge`, and the merged report must say exactly what one unsharded run
//! says. Needs `../shared/navfn` and the peer venv's `dask` + `distributed`
//! (`scripts/install-peers.sh`).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

fn json(p: &Path) -> serde_json::Value {
    let bytes = std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_slice(&bytes).expect("a JSON report")
}

/// A report without the fields that name its shards and their timings.
fn results(mut v: serde_json::Value) -> serde_json::Value {
    let m = v.as_object_mut().expect("a JSON object");
    m.remove("shards");
    m.remove("runs");
    v
}

#[test]
fn dask_cluster_runs_the_paper_suite_in_eight_shards_and_merges_to_the_single_run() {
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    let Some(python) = vouch_testkit::python_with(&["dask", "distributed"]) else { return };
    let driver =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../vouch-navfn/distributed/dask_campaign.py");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("navfn_dask");
    let _ = std::fs::remove_dir_all(&out);
    let began = Instant::now();
    // The full campaign (every check, optimality, the six metamorphic transforms), one thread
    // per shard, two worker processes.
    let o = Command::new(&python)
        .arg(&driver)
        .arg(shared.join("suite"))
        .args(["--shards", "8", "--local-workers", "2", "--threads", "1", "--compare-single"])
        .arg("--vouch")
        .arg(env!("CARGO_BIN_EXE_vouch"))
        .arg("--out")
        .arg(&out)
        .output()
        .expect("the driver runs");
    let seconds = began.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "driver failed:\n{stdout}\n{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(stdout.lines().last().unwrap_or_default()).expect("summary line");
    assert_eq!(summary["equal_to_single"], true, "{summary}");

    // The reports themselves, read here rather than trusting the driver's comparison.
    let (merged, single) = (json(&out.join("merged.json")), json(&out.join("single.json")));
    assert_eq!(merged["shards"]["count"], 8);
    assert_eq!(merged["shards"]["indices"], serde_json::json!([0, 1, 2, 3, 4, 5, 6, 7]));
    assert_eq!(merged["runs"].as_array().map(Vec::len), Some(8), "one run per task");
    for i in 0..8 {
        let shard = json(&out.join(format!("shard-{i}.json")));
        assert_eq!(shard["shards"]["indices"], serde_json::json!([i]));
        assert!(shard["cases"].as_u64().expect("cases") < 121_404);
    }
    assert_eq!(results(merged.clone()), results(single), "merged ≠ single-process report");
    // and both are the paper's suite: outcome counts of shared/navfn/golden/README.md
    assert_eq!(merged["cases"], 121_404);
    assert_eq!(merged["suite"]["maps"].as_object().map(|m| m.len()), Some(101));
    let total = |field: &str| -> u64 {
        let cats = merged["categories"].as_object().expect("categories");
        cats.values().map(|c| c["outcomes"][field].as_u64().expect("count")).sum()
    };
    assert_eq!(
        ["found", "start_is_goal", "unreachable", "cycle_limit", "path_failed"].map(total),
        [71_915, 2_092, 34_034, 13_340, 23]
    );
    println!(
        "Dask local cluster (2 workers): 8 shards + 1 single-process run of the paper suite, \
         merged and compared, in {seconds:.1} s"
    );
}

/// The inflation-radius search on the same back-end: three tasks, each a shard of the goals,
/// merged by `vouch navfn inflation --merge`, equal to one unsharded run.
#[test]
fn dask_cluster_shards_the_inflation_search() {
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    let Some(python) = vouch_testkit::python_with(&["dask", "distributed"]) else { return };
    let driver =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../vouch-navfn/distributed/dask_campaign.py");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("navfn_dask_inflation");
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(&python)
        .arg(&driver)
        .arg(shared.join("nav2_maps/map_circular.yaml"))
        .args(["--inflation", "--shards", "3", "--local-workers", "2", "--compare-single"])
        .arg("--vouch")
        .arg(env!("CARGO_BIN_EXE_vouch"))
        .arg("--out")
        .arg(&out)
        .args(["--", "--robot-radius", "0.3", "--footprint-padding", "0.08"])
        .args(["--cost-scaling-factor", "3", "--goals", "4", "--start-stride", "8"])
        .output()
        .expect("the driver runs");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(stdout.lines().last().expect("a summary line")).expect("JSON");
    assert_eq!(summary["equal_to_single"], true);
    assert!(summary["smallest_safe_radius"].as_f64().is_some());
    let merged = json(&out.join("merged.json"));
    assert_eq!(merged["shards"].as_array().expect("shards").len(), 3);
}
