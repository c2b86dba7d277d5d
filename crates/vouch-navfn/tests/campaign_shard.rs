//! Shards and strict merges: the shards of a campaign merge into exactly the report of one
//! unsharded run (split by map and by case, in any order or grouping, maps counted as a union),
//! and every inconsistent set of reports is refused. Runs on generated suites (no shared data).

use std::path::{Path, PathBuf};

use vouch_navfn::campaign::generate::{GenOptions, RosImport, generate, write_generated};
use vouch_navfn::campaign::merge::{Completeness, MergeError};
use vouch_navfn::campaign::report::Report;
use vouch_navfn::campaign::runner::{CampaignOptions, run_campaign};
use vouch_navfn::campaign::shard::{Shard, ShardBy};
use vouch_navfn::campaign::suite_io::write_suite;
use vouch_navfn::campaign::summary::summary_table;

/// The test process's private scratch directory (`tempfile`, under the target directory).
fn scratch() -> &'static Path {
    static DIR: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        tempfile::Builder::new()
            .prefix("shard-")
            .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
            .expect("temporary directory")
    })
    .path()
}

/// A fresh (removed if a former run left it) path in the scratch directory.
fn tmp(name: &str) -> PathBuf {
    let d = scratch().join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn gen_opts(seed: u64, cases: usize) -> GenOptions {
    GenOptions {
        seed,
        maps_per_category: 3,
        cases_per_map: cases,
        min_size: 5,
        max_size: 14,
        ..GenOptions::default()
    }
}

fn suite(name: &str, seed: u64, cases: usize) -> PathBuf {
    let dir = tmp(name);
    write_suite(&dir, &generate(&gen_opts(seed, cases)).expect("gen")).expect("write");
    dir
}

fn base() -> CampaignOptions {
    CampaignOptions { unit_cases: 16, ..CampaignOptions::default() }
}

fn run(dir: &Path, opts: &CampaignOptions) -> Report {
    run_campaign(dir, opts, &(), None).expect("campaign runs")
}

fn shards(dir: &Path, n: u32, by: ShardBy, opts: &CampaignOptions) -> Vec<Report> {
    (0..n)
        .map(|i| {
            run(
                dir,
                &CampaignOptions { shard: Shard::new(i, n, by).expect("shard"), ..opts.clone() },
            )
        })
        .collect()
}

fn strict(rs: &[Report]) -> Result<Report, MergeError> {
    Report::merge(rs, Completeness::Required)
}

fn partial(rs: &[Report]) -> Report {
    Report::merge(rs, Completeness::AllowPartial).expect("partial merge")
}

/// The report through its JSON file format and back.
fn round_trip(r: &Report) -> Report {
    let text = serde_json::to_string_pretty(r).expect("json");
    Report::from_json(Path::new("r.json"), &text).expect("reads back")
}

#[test]
fn merged_shards_equal_the_unsharded_run_in_both_splits() {
    // 4 cases per map and 6 shards: split by case, most shards skip some maps entirely
    let dir = suite("equal", 11, 4);
    let whole = run(&dir, &base());
    assert_eq!(whole.suite.maps.len(), 27);
    assert_eq!(whole.cases, whole.suite.cases());
    assert!(whole.suite.content.is_some());
    assert_eq!(whole.failures(), 0);
    for by in [ShardBy::Map, ShardBy::Case] {
        let parts: Vec<Report> = shards(&dir, 6, by, &base()).iter().map(round_trip).collect();
        assert!(parts.iter().all(|r| r.cases < whole.cases));
        let merged = strict(&parts).expect("complete set merges");
        assert!(
            merged.same_results(&whole),
            "{by:?}:\n{}\nvs\n{}",
            summary_table(&merged),
            summary_table(&whole)
        );
        assert_eq!(merged.categories, whole.categories, "{by:?}: every count");
        assert_eq!(merged.suite.content, whole.suite.content);
        let maps: u64 = merged.categories.values().map(|c| c.maps).sum();
        assert_eq!(maps, 27, "{by:?}: maps counted as a union");
        if by == ShardBy::Case {
            let per_shard: u64 = parts.iter().map(|r| r.suite.maps.len() as u64).sum();
            assert!(per_shard > 27, "maps shared by case shards are counted once");
        }
        // any order, any grouping
        let mut rev = parts.clone();
        rev.reverse();
        assert_eq!(strict(&rev).expect("reversed"), merged);
        let left = partial(&[parts[4].clone(), parts[0].clone()]);
        let right = partial(&[parts[5].clone(), parts[2].clone(), parts[1].clone()]);
        let grouped = strict(&[right, round_trip(&left), parts[3].clone()]).expect("grouped");
        assert_eq!(grouped, merged);
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn inconsistent_sets_are_refused() {
    let dir = suite("refuse", 12, 6);
    let parts = shards(&dir, 4, ShardBy::Map, &base());
    // mixed N: 0/4 + 1/3 + 2/4 + 3/4
    let mut mixed = parts.clone();
    mixed[1] = run(
        &dir,
        &CampaignOptions { shard: Shard::new(1, 3, ShardBy::Map).expect("1/3"), ..base() },
    );
    assert!(matches!(strict(&mixed), Err(MergeError::Split(..))), "{:?}", strict(&mixed).err());
    // mixed splits of the same N
    let mut by = parts.clone();
    by[2] = run(
        &dir,
        &CampaignOptions { shard: Shard::new(2, 4, ShardBy::Case).expect("2/4"), ..base() },
    );
    assert!(matches!(strict(&by), Err(MergeError::Split(..))));
    // different options
    let mut ratio = parts.clone();
    ratio[3] = run(
        &dir,
        &CampaignOptions {
            suboptimal_ratio: 1.2,
            shard: Shard::new(3, 4, ShardBy::Map).expect("3/4"),
            ..base()
        },
    );
    assert!(matches!(strict(&ratio), Err(MergeError::Options(..))));
    let mut meta = parts.clone();
    meta[0] = run(
        &dir,
        &CampaignOptions {
            metamorphic: false,
            shard: Shard::new(0, 4, ShardBy::Map).expect("0/4"),
            ..base()
        },
    );
    assert!(matches!(strict(&meta), Err(MergeError::Options(..))));
    // duplicates, directly and inside a merged report
    let dup =
        [parts[0].clone(), parts[1].clone(), parts[1].clone(), parts[2].clone(), parts[3].clone()];
    assert!(matches!(strict(&dup), Err(MergeError::Duplicate { index: 1, count: 4 })));
    let pair = partial(&parts[0..2]);
    assert!(matches!(
        strict(&[pair, parts[1].clone(), parts[2].clone(), parts[3].clone()]),
        Err(MergeError::Duplicate { .. })
    ));
    // missing shards: refused unless partial merges are allowed
    let e = strict(&parts[0..3]).expect_err("incomplete");
    assert!(matches!(&e, MergeError::Incomplete(m) if m.contains("3/4")), "{e}");
    let p = partial(&parts[0..3]);
    assert_eq!((p.shards.missing(8), p.suite.content.clone()), (vec![3], None));
    // another vouch version
    let mut other = parts.clone();
    other[2].vouch_version = "0.0.1".into();
    assert!(matches!(strict(&other), Err(MergeError::Version(..))));
    // the complete set merges
    assert!(strict(&parts).is_ok());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_suite_is_identified_by_content_not_by_path() {
    // the CLI test `navfn_cli` runs shards by relative and absolute paths
    let dir = suite("identity", 13, 6);
    let abs = dir.canonicalize().expect("absolute");
    let name = dir.file_name().expect("named");
    let other = dir.join("..").join(name);
    let a = run(
        &abs,
        &CampaignOptions { shard: Shard::new(0, 2, ShardBy::Case).expect("0/2"), ..base() },
    );
    let b = run(
        &other,
        &CampaignOptions { shard: Shard::new(1, 2, ShardBy::Case).expect("1/2"), ..base() },
    );
    assert_ne!(a.runs[0].suite_path, b.runs[0].suite_path);
    let merged = strict(&[a.clone(), b]).expect("same suite by absolute and relative path");
    assert_eq!(merged.suite.content, run(&dir, &base()).suite.content);

    // different contents at the same path, same names and sizes: one map byte changed
    let victim =
        merged.suite.maps.keys().find(|k| k.starts_with("free/")).expect("a free map").clone();
    let bin = dir.join(&victim).join("map.bin");
    let mut bytes = std::fs::read(&bin).expect("map");
    let i = bytes.iter().position(|&c| c < 200).expect("a free cell");
    bytes[i] += 1;
    std::fs::write(&bin, bytes).expect("rewritten");
    let b2 = run(
        &abs,
        &CampaignOptions { shard: Shard::new(1, 2, ShardBy::Case).expect("1/2"), ..base() },
    );
    let e = strict(&[a.clone(), b2]).expect_err("contents differ");
    assert!(matches!(&e, MergeError::MapContent { key, .. } if *key == victim), "{e}");

    // another suite at the same path (regenerated with another seed)
    std::fs::remove_dir_all(&dir).expect("removed");
    write_suite(&dir, &generate(&gen_opts(14, 6)).expect("gen")).expect("write");
    let b3 = run(
        &abs,
        &CampaignOptions { shard: Shard::new(1, 2, ShardBy::Case).expect("1/2"), ..base() },
    );
    assert!(matches!(strict(&[a, b3]), Err(MergeError::Suite(..))));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn shares_of_a_generated_suite_run_where_they_were_generated() {
    let o = GenOptions {
        maps_per_category: 4,
        cases_per_map: 5,
        min_size: 5,
        max_size: 12,
        seed: 21,
        ..GenOptions::default()
    };
    let whole_dir = tmp("share-whole");
    write_generated(&whole_dir, &o, &RosImport::default(), Shard::ALL).expect("gen");
    let whole = run(&whole_dir, &base());
    let mut parts = Vec::new();
    for i in 0..3 {
        let shard = Shard::new(i, 3, ShardBy::Map).expect("shard");
        let d = tmp(&format!("share-{i}"));
        write_generated(&d, &o, &RosImport::default(), shard).expect("gen share");
        parts.push(run(&d, &CampaignOptions { shard, ..base() }));
        // a share does not hold the other shards' maps: splitting it by case is refused
        let by_case =
            CampaignOptions { shard: Shard::new(i, 3, ShardBy::Case).expect("shard"), ..base() };
        assert!(run_campaign(&d, &by_case, &(), None).is_err());
        let _ = std::fs::remove_dir_all(d);
    }
    let merged = strict(&parts).expect("shares merge");
    assert!(merged.same_results(&whole));
    // a share whose map went missing leaves the merged suite incomplete
    let lost = {
        let mut r = parts[1].clone();
        let key = r.suite.maps.keys().next().expect("a map").clone();
        r.suite.maps.remove(&key);
        r
    };
    let e = strict(&[parts[0].clone(), lost, parts[2].clone()]).expect_err("a map is missing");
    assert!(matches!(&e, MergeError::Incomplete(m) if m.contains("maps read")), "{e}");
    let _ = std::fs::remove_dir_all(whole_dir);
}

/// An edit that damages a report's JSON.
type Damage = dyn Fn(&mut serde_json::Value);

/// The malformed-report catalogue: each damage is refused on reading with its reason.
#[test]
fn malformed_reports_are_refused_with_their_reason() {
    let dir = suite("malformed", 15, 4);
    let good = run(
        &dir,
        &CampaignOptions { shard: Shard::new(1, 4, ShardBy::Map).expect("1/4"), ..base() },
    );
    let good: serde_json::Value = serde_json::to_value(&good).expect("json");
    let damaged = |edit: &Damage| {
        let mut v = good.clone();
        edit(&mut v);
        Report::from_json(Path::new("bad.json"), &v.to_string())
    };
    let catalogue: [(&str, &Damage); 9] = [
        ("ascending", &|v| v["shards"]["indices"] = serde_json::json!([2, 1])),
        ("ascending", &|v| v["shards"]["indices"] = serde_json::json!([1, 1])),
        ("ascending", &|v| v["shards"]["indices"] = serde_json::json!([])),
        ("not below the shard count", &|v| v["shards"]["indices"] = serde_json::json!([4])),
        ("ascending", &|v| v["shards"]["count"] = serde_json::json!(0)),
        ("run of a shard", &|v| v["runs"][0]["shard"] = serde_json::json!(3)),
        ("categories add up", &|v| v["cases"] = serde_json::json!(1)),
        ("more maps read", &|v| v["suite"]["maps_total"] = serde_json::json!(0)),
        ("ratio", &|v| v["options"]["ratio"] = serde_json::json!(0.5)),
    ];
    for (why, edit) in catalogue {
        let e = damaged(edit).expect_err(why);
        assert!(e.to_string().contains(why), "{why}: {e}");
    }
    let e = damaged(&|v| {
        let cats = v["categories"].as_object_mut().expect("categories");
        let first = cats.values_mut().next().expect("a category");
        first["optimality"]["ratio_hist"] = serde_json::json!([1, 2]);
    })
    .expect_err("histogram");
    assert!(e.to_string().contains("histogram"), "{e}");
    // counts near the top of u64 saturate in a merge instead of overflowing
    let mut a: Report = Report::from_json(Path::new("a.json"), &good.to_string()).expect("reads");
    let huge = u64::MAX - 1;
    for c in a.categories.values_mut() {
        c.cases = huge;
        c.outcomes.found = huge;
    }
    a.cases = huge.saturating_mul(a.categories.len() as u64);
    let mut b = a.clone();
    b.shards.indices = vec![2];
    b.runs[0].shard = 2;
    let m = partial(&[a, b]);
    assert_eq!(m.cases, u64::MAX);
    let _ = std::fs::remove_dir_all(dir);
}
