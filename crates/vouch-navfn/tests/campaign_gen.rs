//! Generators: deterministic per seed, different across seeds, bordered, with start = goal and
//! unreachable pairs; the written suite reads back through the core's reader; ROS import.

use std::path::{Path, PathBuf};

use vouch_navfn::campaign::generate::{
    CATEGORIES, GenOptions, RosImport, generate, write_generated,
};
use vouch_navfn::campaign::grid::OBSTACLE;
use vouch_navfn::campaign::identity::MANIFEST;
use vouch_navfn::campaign::names::FindingKind;
use vouch_navfn::campaign::ros_import::import_ros_map;
use vouch_navfn::campaign::shard::{Shard, ShardBy};
use vouch_navfn::campaign::suite_io::{read_suite, write_suite};

/// The test process's private scratch directory (`tempfile`, under the target directory).
fn scratch() -> &'static Path {
    static DIR: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        tempfile::Builder::new()
            .prefix("campaign-gen-")
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

/// All files below `dir` as (relative path, bytes), sorted.
fn tree(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("readable").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).expect("below").display().to_string();
                out.push((rel, std::fs::read(&p).expect("readable")));
            }
        }
    }
    out.sort();
    out
}

fn opts(seed: u64) -> GenOptions {
    GenOptions {
        seed,
        maps_per_category: 3,
        cases_per_map: 60,
        min_size: 5,
        max_size: 20,
        ..GenOptions::default()
    }
}

#[test]
fn same_seed_same_files_different_seed_different_files() {
    let (a, b, c) = (tmp("a"), tmp("b"), tmp("c"));
    write_suite(&a, &generate(&opts(42)).expect("gen")).expect("write");
    write_suite(&b, &generate(&opts(42)).expect("gen")).expect("write");
    write_suite(&c, &generate(&opts(43)).expect("gen")).expect("write");
    let (ta, tb, tc) = (tree(&a), tree(&b), tree(&c));
    assert_eq!(ta.len(), 9 * 3 * 2, "nine categories × 3 maps × (test.txt + map.bin)");
    assert_eq!(ta, tb, "same seed must give byte-identical files");
    assert_ne!(ta, tc, "different seeds must differ");
    // Not just the names: the map bytes differ too.
    let bins = |t: &[(String, Vec<u8>)]| {
        t.iter().filter(|(n, _)| n.ends_with(".bin")).map(|(_, b)| b.clone()).collect::<Vec<_>>()
    };
    assert_ne!(bins(&ta), bins(&tc));
    for d in [a, b, c] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn category_subset_does_not_change_other_maps() {
    let all = generate(&opts(7)).expect("gen");
    let only = generate(&GenOptions { categories: vec!["walls".into()], ..opts(7) }).expect("gen");
    let walls: Vec<_> = all.iter().filter(|m| m.category == "walls").cloned().collect();
    assert_eq!(only, walls);
    assert!(generate(&GenOptions { categories: vec!["nope".into()], ..opts(7) }).is_err());
}

#[test]
fn maps_have_border_start_goal_and_unreachable_pairs() {
    let maps = generate(&GenOptions { maps_per_category: 6, ..opts(2024) }).expect("gen");
    let mut cross_component = 0;
    for cat in CATEGORIES {
        assert!(maps.iter().any(|m| m.category == cat), "category {cat} generated");
    }
    for m in &maps {
        let (w, h) = (m.width, m.height);
        for x in 0..w {
            assert_eq!(m.get(x, 0), OBSTACLE);
            assert_eq!(m.get(x, h - 1), OBSTACLE);
        }
        for y in 0..h {
            assert_eq!(m.get(0, y), OBSTACLE);
            assert_eq!(m.get(w - 1, y), OBSTACLE);
        }
        assert!(m.costs.iter().all(|&c| (50..=254).contains(&c)), "{}: NavFn costs only", m.name);
        assert!(
            m.cases.iter().any(|c| (c.x0, c.y0) == (c.x1, c.y1)),
            "{}: a start = goal case",
            m.name
        );
        let (label, n) = m.components();
        for c in &m.cases {
            assert!(
                m.is_free(c.x0, c.y0) && m.is_free(c.x1, c.y1),
                "{}: cases on traversable cells",
                m.name
            );
        }
        if n > 1 {
            let has = m.cases.iter().any(|c| label[m.idx(c.x0, c.y0)] != label[m.idx(c.x1, c.y1)]);
            assert!(has, "{}: {n} regions but no unreachable pair", m.name);
            cross_component += 1;
        }
    }
    assert!(cross_component >= 6, "split/obstacle/walls/spiral maps produce disconnected regions");
    // Spiral maps: one corridor, i.e. a single region, and long paths.
    for m in maps.iter().filter(|m| m.category == "spiral") {
        assert_eq!(m.components().1, 1, "{}: spiral is one corridor", m.name);
    }
}

#[test]
fn written_suite_reads_back_with_the_core_reader() {
    let d = tmp("rt");
    let maps = generate(&opts(5)).expect("gen");
    write_suite(&d, &maps).expect("write");
    let back = read_suite(&d).expect("read");
    assert_eq!(back.len(), maps.len());
    for m in &maps {
        let b =
            back.iter().find(|b| b.category == m.category && b.name == m.name).expect("present");
        assert_eq!(
            (b.width, b.height, &b.costs, &b.cases),
            (m.width, m.height, &m.costs, &m.cases)
        );
    }
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn ros_import_reproduces_the_paper_ros_maps() {
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    for name in ["keepout_mask", "map_circular", "speed_mask"] {
        let yaml = shared.join("nav2_maps").join(format!("{name}.yaml"));
        let m = import_ros_map(&yaml, name, None).expect("imports");
        let want =
            std::fs::read(shared.join("suite/ROS").join(name).join("map.bin")).expect("suite map");
        let differing = m.costs.iter().zip(&want).filter(|(a, b)| a != b).count();
        assert_eq!(m.costs.len(), want.len(), "{name}: size");
        assert_eq!(differing, 0, "{name}: {differing} cells differ from the paper's conversion");
    }
}

#[test]
fn generated_circus_maps_reproduce_the_lane_counterexample() {
    use vouch_navfn::campaign::runner::{CampaignOptions, run_campaign};
    let d = tmp("circus");
    let maps = generate(&GenOptions {
        categories: vec!["circus".into()],
        maps_per_category: 8,
        cases_per_map: 20,
        ..opts(3)
    })
    .expect("gen");
    write_suite(&d, &maps).expect("write");
    let opts = CampaignOptions { metamorphic: false, ..CampaignOptions::default() };
    let report = run_campaign(&d, &opts, &(), None).expect("runs");
    let c = &report.categories["circus"];
    assert_eq!(report.failures(), 0);
    // NavFn climbs the expensive lane on some generated tracks: paths > 10 % above the optimum.
    assert!(
        c.optimality.suboptimal_paths > 0,
        "no circus counterexample in {} paths",
        c.optimality.compared
    );
    assert!(
        report.findings.iter().any(|f| f.kind == FindingKind::Suboptimal && f.category == "circus")
    );
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn generation_shards_are_disjoint_and_their_union_is_the_unsharded_suite_byte_for_byte() {
    let o = GenOptions { maps_per_category: 4, ..opts(99) };
    let whole = tmp("share-whole");
    let w = write_generated(&whole, &o, &RosImport::default(), Shard::ALL).expect("gen");
    assert_eq!((w.maps, w.maps_total), (36, 36));
    let expected = tree(&whole);
    assert!(expected.iter().any(|(n, _)| n == MANIFEST), "the manifest is written");
    let mut union: Vec<(String, Vec<u8>)> = Vec::new();
    let mut maps = 0;
    for i in 0..4 {
        let shard = Shard::new(i, 4, ShardBy::Map).expect("shard");
        let d = tmp(&format!("share-{i}"));
        let s = write_generated(&d, &o, &RosImport::default(), shard).expect("gen share");
        assert_eq!(s.maps_total, 36);
        assert!(s.maps > 0 && s.maps < 36, "shard {i} wrote {} maps", s.maps);
        maps += s.maps;
        let again = tmp(&format!("share-{i}-again"));
        write_generated(&again, &o, &RosImport::default(), shard).expect("gen share");
        assert_eq!(tree(&again), tree(&d), "a share is deterministic for its seed");
        for (name, bytes) in tree(&d) {
            if name == MANIFEST {
                let want = expected.iter().find(|(n, _)| n == MANIFEST).expect("manifest");
                assert_eq!(bytes, want.1, "every share carries the suite's manifest");
            } else {
                assert!(!union.iter().any(|(n, _)| *n == name), "{name} in two shares");
                union.push((name, bytes));
            }
        }
        for dir in [d, again] {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
    assert_eq!(maps, 36);
    union.push(expected.iter().find(|(n, _)| n == MANIFEST).expect("manifest").clone());
    union.sort();
    assert_eq!(union, expected, "union of the shares = the unsharded generation");
    let _ = std::fs::remove_dir_all(whole);
}

#[test]
fn names_sort_in_index_order_beyond_a_thousand_maps() {
    let o = GenOptions {
        categories: vec!["free".into()],
        maps_per_category: 1001,
        cases_per_map: 1,
        min_size: 5,
        max_size: 5,
        ..opts(1)
    };
    let maps = generate(&o).expect("gen");
    assert!(maps[0].name.starts_with("0000_"), "{}", maps[0].name);
    let names: Vec<&str> = maps.iter().map(|m| m.name.as_str()).collect();
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(names, sorted);
}
