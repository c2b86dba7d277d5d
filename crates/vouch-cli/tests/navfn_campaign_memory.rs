//! Benchmark (ignored by default): peak memory of the campaign at scale, whole run against its
//! shards, measured now, side by side, with GNU time's maximum resident set size:
//!
//! ```sh
//! cargo test --release -p vouch-cli --test navfn_campaign_memory -- --ignored --nocapture
//! ```
//!
//! On a generated suite of 5,040 maps (`suite gen --seed 17 --maps 560 --cases 20`): the whole
//! run, `--shard 0/8` split by map and by case, the other seven map shards, `report merge` of
//! the eight, and `--cases-out` on this suite and on one twice as large (with and without it:
//! what grows with the suite is the report's digest of every map, not the records). It checks the issue's
//! bounds (a shard at most 1/8 of the whole run plus 20 MB; the merged report equal to the
//! whole run) and prints every figure. With `VOUCH_BASELINE=/path/to/another/vouch` it also
//! measures that binary (e.g. a build of an earlier commit) on the same suite in the same run:
//! whole, `--shard 0/8`, `--cases-out`.

use std::path::{Path, PathBuf};
use std::process::Command;

const TIME: &str = "/usr/bin/time";

/// `vouch ARGS` under GNU time: (peak RSS in MB, wall seconds).
fn measured(args: &[&str]) -> (f64, f64) {
    measured_with(env!("CARGO_BIN_EXE_vouch"), args)
}

/// `BINARY ARGS` under GNU time: (peak RSS in MB, wall seconds).
fn measured_with(binary: &str, args: &[&str]) -> (f64, f64) {
    let o = Command::new(TIME)
        .args(["-f", "%M %e", binary])
        .args(args)
        .output()
        .expect("GNU time runs vouch");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "vouch {args:?}: {err}");
    let last = err.lines().last().unwrap_or_default();
    let mut it = last.split_whitespace().map(|v| v.parse::<f64>().expect("a number"));
    let (kb, secs) = (it.next().expect("max RSS"), it.next().expect("wall"));
    (kb / 1024.0, secs)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn generate_suite(dir: &Path, maps: &str) {
    let _ = std::fs::remove_dir_all(dir);
    let args = ["-q", "navfn", "suite", "gen", "--seed", "17", "--maps", maps, "--cases", "20"];
    let o = Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(args)
        .args(["-o", s(dir)])
        .output()
        .expect("vouch runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn results(p: &Path) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(p).expect("report")).expect("json");
    let m = v.as_object_mut().expect("object");
    m.remove("runs");
    m.remove("shards");
    v
}

#[test]
#[ignore = "benchmark: run with --ignored --nocapture"]
fn campaign_memory_whole_run_against_shards() {
    if vouch_testkit::program(TIME, "--version").is_none() {
        return;
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("navfn_campaign_memory");
    let suite = dir.join("suite");
    generate_suite(&suite, "560");
    let out = |name: &str| -> PathBuf { dir.join(name) };
    let run = |extra: &[&str], report: &Path| {
        let mut args = vec!["-q", "navfn", "campaign", s(&suite), "-o", s(report)];
        args.extend_from_slice(extra);
        measured(&args)
    };
    let whole = out("whole.json");
    let (full_mb, full_s) = run(&[], &whole);
    let shard_files: Vec<PathBuf> = (0..8).map(|i| out(&format!("shard{i}.json"))).collect();
    let mut shard_mb = Vec::new();
    for (i, f) in shard_files.iter().enumerate() {
        shard_mb.push(run(&["--shard", &format!("{i}/8")], f));
    }
    let case0 = run(&["--shard", "0/8", "--shard-by", "case"], &out("case0.json"));
    let merged = out("merged.json");
    let mut args = vec!["-q", "navfn", "report", "merge", "-o", s(&merged)];
    args.extend(shard_files.iter().map(|p| s(p)));
    let merge = measured(&args);
    let equal = results(&merged) == results(&whole);
    let lines = out("cases.jsonl");
    let with_lines = run(&["--cases-out", s(&lines)], &out("lines.json"));
    let records = std::fs::read_to_string(&lines).expect("lines").lines().count();

    let big = dir.join("suite2x");
    generate_suite(&big, "1120");
    let big_run = measured(&["-q", "navfn", "campaign", s(&big), "-o", s(&out("big0.json"))]);
    let big_lines = measured(&[
        "-q",
        "navfn",
        "campaign",
        s(&big),
        "-o",
        s(&out("big.json")),
        "--cases-out",
        s(&out("big.jsonl")),
    ]);
    let big_records = std::fs::read_to_string(out("big.jsonl")).expect("lines").lines().count();

    let whole_v = results(&whole);
    let maps = whole_v["suite"]["maps"].as_object().map_or(0, |m| m.len());
    println!("suite gen --seed 17 --maps 560 --cases 20: {maps} maps, {} cases", whole_v["cases"]);
    println!("{:<44} {:>12} {:>8}", "run", "peak RSS", "wall");
    let row =
        |name: &str, (mb, secs): (f64, f64)| println!("{name:<44} {mb:>9.1} MB {secs:>6.2} s");
    row("campaign (whole suite)", (full_mb, full_s));
    row("campaign --shard 0/8 (split by map)", shard_mb[0]);
    let others = shard_mb[1..].iter().fold((0.0f64, 0.0f64), |a, b| (a.0.max(b.0), a.1.max(b.1)));
    row("campaign --shard 1/8 … 7/8 (largest)", others);
    row("campaign --shard 0/8 --shard-by case", case0);
    row("report merge (8 shards)", merge);
    row(&format!("campaign --cases-out ({records} lines)"), with_lines);
    row("campaign, 2× suite (--maps 1120)", big_run);
    row(&format!("campaign --cases-out, 2× suite ({big_records} lines)"), big_lines);
    if let Ok(baseline) = std::env::var("VOUCH_BASELINE") {
        let base = |extra: &[&str]| {
            let mut args = vec!["-q", "navfn", "campaign", s(&suite), "-o", "/dev/null"];
            args.extend_from_slice(extra);
            measured_with(&baseline, &args)
        };
        let base_lines = out("baseline.jsonl");
        row("baseline: campaign (whole suite)", base(&[]));
        row("baseline: campaign --shard 0/8", base(&["--shard", "0/8"]));
        row("baseline: campaign --cases-out", base(&["--cases-out", s(&base_lines)]));
    }
    let bound = full_mb / 8.0 + 20.0;
    println!(
        "bound for a shard: whole/8 + 20 MB = {bound:.1} MB; merged report = whole run: {equal}"
    );
    assert!(equal, "the merged report differs from the whole run");
    assert!(shard_mb[0].0 <= bound, "shard 0/8 peaks at {:.1} MB > {bound:.1} MB", shard_mb[0].0);
    assert_eq!(records as u64, whole_v["cases"].as_u64().expect("cases"));
}
