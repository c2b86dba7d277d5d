//! `vouch navfn bench --inflation`: the inflation layer's update timed on generated static
//! layers, alone and against an external layer under the inflation contract (here stand-ins
//! written as shell scripts: one that returns the static layer unchanged, one that prints no
//! timing). The bytes of nav2's own layer are the goldens of `vouch-navfn`'s
//! `costmap_inflation` test; what is checked here is the harness: rows, samples, the byte
//! comparison and the errors.

mod common;

use common::{code, vouch};
use std::path::PathBuf;

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A stand-in external layer: `body` runs with the contract's arguments (`$1` = IN.bin,
/// `${11}` = OUT.bin).
fn script(dir: &tempfile::TempDir, name: &str, body: &str) -> String {
    let path: PathBuf = dir.path().join(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).expect("script written");
    format!("sh {}", path.display())
}

#[test]
fn inflation_rows_alone() {
    let o = vouch(&[
        "navfn",
        "bench",
        "--inflation",
        "64,120",
        "--passes",
        "2",
        "--repeat",
        "1",
        "--json",
    ]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    let rows = rows.as_array().expect("rows");
    assert_eq!(rows.len(), 2, "{rows:?}");
    assert_eq!(rows[0]["count"], 64 * 64);
    assert_eq!(rows[1]["count"], 120 * 120);
    for r in rows {
        assert_eq!(r["unit"], "ms/update");
        assert!(r["workload"].as_str().is_some_and(|w| w.starts_with("inflation ")), "{r}");
        let samples = r["vouch"].as_array().expect("samples");
        assert_eq!(samples.len(), 2, "one per pass: {r}");
        assert!(r["oracle"].as_array().is_some_and(|s| s.is_empty()), "{r}");
    }
}

#[test]
fn inflation_against_an_external_layer() {
    let dir = tempfile::tempdir().expect("temporary folder");
    // a layer that inflates nothing: every pass is timed, and the bytes differ from vouch's
    let unchanged = script(
        &dir,
        "unchanged.sh",
        "cp \"$1\" \"${11}\" && echo 'TIME reps=1 best_ns=2500000 sum_ns=2500000 maxrss_kb=1'",
    );
    let o = vouch(&[
        "navfn",
        "bench",
        "--inflation",
        "80",
        "--inflation-oracle",
        &unchanged,
        "--passes",
        "3",
        "--repeat",
        "1",
    ]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let (out, err) = (text(&o.stdout), text(&o.stderr));
    assert!(err.contains("inflation 80x80: costmap bytes DIFFERENT"), "{err}");
    let row = out.lines().find(|l| l.starts_with("inflation 80x80")).expect("the row");
    assert!(row.contains("2.500 [2.500]"), "the external side's TIME line: {row}");
    assert!(out.contains("ratio"), "{out}");
    // no TIME line, or a layer that fails: the harness stops with an I/O error (2)
    for body in ["cp \"$1\" \"${11}\"", "exit 4"] {
        let bad = script(&dir, "bad.sh", body);
        let o = vouch(&["navfn", "bench", "--inflation", "40", "--inflation-oracle", &bad]);
        assert_eq!(code(&o), 2, "{body}: {}", text(&o.stderr));
        assert!(text(&o.stderr).contains("navfn::E092"), "{}", text(&o.stderr));
    }
    // generated maps need a border ring and an interior; nothing measured is no answer
    for (flag, side) in [("--inflation", "2"), ("--scale", "1"), ("--inflation", "40,x")] {
        let o = vouch(&["navfn", "bench", flag, side]);
        assert_eq!(code(&o), 2, "{flag} {side}: {}", text(&o.stdout));
        assert!(text(&o.stderr).contains("a side from 3"), "{}", text(&o.stderr));
    }
    // the external layer needs the workload
    let o = vouch(&["navfn", "bench", "examples/navfn/suite", "--inflation-oracle", &unchanged]);
    assert_eq!(code(&o), 2, "{}", text(&o.stderr));
}
