//! `vouch navfn campaign --shard`, `suite gen --shard` and `report merge` as a user runs them:
//! every inconsistent merge exits 1 with its reason on stderr, a partial merge needs
//! `--allow-partial`, the same suite by another path merges, merging is independent of order
//! and grouping, `--shard auto` reads Slurm and Kubernetes array jobs, generation shards add up
//! to the whole suite, and `--cases-out` streams one line per case.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use super::{code, repo, text, vouch};

/// `vouch ARGS` in an environment without array-job variables but `env`.
fn vouch_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_vouch"));
    cmd.args(args).current_dir(repo());
    for k in ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN"] {
        cmd.env_remove(k);
    }
    for k in ["SLURM_ARRAY_TASK_STEP", "JOB_COMPLETION_INDEX", "VOUCH_SHARD_COUNT"] {
        cmd.env_remove(k);
    }
    cmd.envs(env.iter().copied());
    cmd.output().expect("the vouch binary runs")
}

/// A fresh folder for one test.
fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("navfn_cli_campaign").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("tmp dir");
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// `suite gen` into `dir` (small maps: the campaigns below take well under a second).
fn generate_suite(dir: &Path, seed: &str, extra: &[&str]) {
    let mut args = vec![
        "navfn", "suite", "gen", "--seed", seed, "--maps", "3", "--cases", "6", "--size", "5..12",
    ];
    args.extend_from_slice(&["-o", s(dir)]);
    args.extend_from_slice(extra);
    let o = vouch(&args);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
}

/// `campaign SUITE --shard SHARD -o OUT EXTRA…`, which must succeed.
fn shard(suite: &str, spec: &str, out: &Path, extra: &[&str]) {
    let mut args = vec!["-q", "navfn", "campaign", suite, "--shard", spec, "-o", s(out)];
    args.extend_from_slice(extra);
    let o = vouch(&args);
    assert_eq!(code(&o), 0, "{spec}: {}", text(&o.stderr));
}

fn merge(out: &Path, inputs: &[&Path], extra: &[&str]) -> Output {
    let mut args = vec!["-q", "navfn", "report", "merge", "-o", s(out)];
    args.extend_from_slice(extra);
    args.extend(inputs.iter().map(|p| s(p)));
    vouch(&args)
}

/// A merge that must be refused: exit 1, the reason (with its code) on stderr, nothing written.
fn refused(dir: &Path, inputs: &[&Path], code_and_words: &[&str]) {
    let out = dir.join("refused.json");
    let _ = std::fs::remove_file(&out);
    let o = merge(&out, inputs, &[]);
    let err = text(&o.stderr);
    assert_eq!(code(&o), 1, "{code_and_words:?} must be refused: {err}");
    for w in code_and_words {
        assert!(err.contains(w), "stderr lacks `{w}`: {err}");
    }
    assert!(o.stdout.is_empty(), "nothing on stdout");
    assert!(!out.exists(), "no merged report written");
}

/// `path` relative to `base` (both absolute).
fn relative(path: &Path, base: &Path) -> PathBuf {
    let (p, b): (Vec<_>, Vec<_>) = (path.components().collect(), base.components().collect());
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c);
    }
    out
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(p).expect("report")).expect("json")
}

#[test]
fn every_bad_merge_is_refused_and_good_ones_do_not_depend_on_order_or_path() {
    let d = tmp("merge");
    let suite = d.join("suite");
    generate_suite(&suite, "5", &[]);
    // shards by a relative path (from the working directory vouch runs in)
    let rel =
        relative(&suite.canonicalize().expect("absolute"), &repo().canonicalize().expect("repo"));
    let r: Vec<PathBuf> = (0..4).map(|i| d.join(format!("r{i}.json"))).collect();
    for (i, p) in r.iter().enumerate() {
        shard(s(&rel), &format!("{i}/4"), p, &[]);
    }
    let [r0, r1, r2, r3] = [&r[0], &r[1], &r[2], &r[3]].map(PathBuf::as_path);

    // mixed N: 0/4 + 1/3 + 2/4 + 3/4
    let third = d.join("third.json");
    shard(s(&suite), "1/3", &third, &[]);
    refused(&d, &[r0, &third, r2, r3], &["navfn::E047", "N = 4", "N = 3"]);
    // mixed splits
    let by_case = d.join("by_case.json");
    shard(s(&suite), "1/4", &by_case, &["--shard-by", "case"]);
    refused(&d, &[r0, &by_case, r2, r3], &["navfn::E047", "split by case"]);
    // different options
    let ratio = d.join("ratio.json");
    shard(s(&suite), "1/4", &ratio, &["--ratio", "1.5"]);
    refused(&d, &[r0, &ratio, r2, r3], &["navfn::E044", "ratio 1.5"]);
    let mode = d.join("mode.json");
    shard(s(&suite), "1/4", &mode, &["--mode", "navfn"]);
    refused(&d, &[r0, &mode, r2, r3], &["navfn::E044", "navfn-dijkstra"]);
    // duplicates
    refused(&d, &[r0, r1, r1, r2, r3], &["navfn::E048", "1/4 appears twice"]);
    // missing shards: refused, then accepted with --allow-partial
    refused(&d, &[r0, r1, r3], &["navfn::E049", "2/4 missing", "--allow-partial"]);
    let part = d.join("part.json");
    let o = merge(&part, &[r0, r1, r3], &["--allow-partial"]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    assert_eq!(json(&part)["shards"]["indices"], serde_json::json!([0, 1, 3]));
    assert!(json(&part)["suite"]["content"].is_null());

    // the complete set, in two orders and two groupings: the same file
    let (all, rev, grouped) = (d.join("all.json"), d.join("rev.json"), d.join("grouped.json"));
    assert_eq!(code(&merge(&all, &[r0, r1, r2, r3], &[])), 0);
    assert_eq!(code(&merge(&rev, &[r3, r1, r2, r0], &[])), 0);
    let pair = d.join("pair.json");
    assert_eq!(code(&merge(&pair, &[r2, r0], &["--allow-partial"])), 0);
    assert_eq!(code(&merge(&grouped, &[r3, &pair, r1], &[])), 0);
    let bytes = std::fs::read(&all).expect("merged");
    assert_eq!(std::fs::read(&rev).expect("merged"), bytes, "order");
    assert_eq!(std::fs::read(&grouped).expect("merged"), bytes, "grouping");
    // … and equal to one unsharded run, but for the shard list and the timings
    let single = d.join("single.json");
    let o = vouch(&["-q", "navfn", "campaign", s(&suite), "-o", s(&single)]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let results = |mut v: serde_json::Value| {
        let m = v.as_object_mut().expect("object");
        m.remove("runs");
        m.remove("shards");
        v
    };
    assert_eq!(results(json(&all)), results(json(&single)));
    assert_eq!(json(&all)["suite"]["maps"].as_object().expect("maps").len(), 27);

    // the same suite by an absolute path merges with shards run by a relative one
    assert!(rel.is_relative());
    let abs = suite.canonicalize().expect("absolute");
    let r1_abs = d.join("r1_abs.json");
    shard(s(&abs), "1/4", &r1_abs, &[]);
    assert_ne!(json(&r1_abs)["runs"][0]["suite_path"], json(r1)["runs"][0]["suite_path"]);
    let o = merge(&d.join("abs.json"), &[r0, &r1_abs, r2, r3], &[]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));

    // different contents at the same path: another suite (another seed)
    let other = d.join("other");
    generate_suite(&other, "6", &[]);
    std::fs::remove_dir_all(&suite).expect("removed");
    std::fs::rename(&other, &suite).expect("moved");
    let r1_other = d.join("r1_other.json");
    shard(s(&suite), "1/4", &r1_other, &[]);
    refused(&d, &[r0, &r1_other, r2, r3], &["navfn::E045", "different suites"]);
}

#[test]
fn a_map_edited_in_place_is_caught_by_the_shards_that_share_it() {
    let d = tmp("edited");
    let suite = d.join("suite");
    generate_suite(&suite, "8", &[]);
    let (a, b) = (d.join("a.json"), d.join("b.json"));
    shard(s(&suite), "0/2", &a, &["--shard-by", "case"]);
    let free = suite.join("free");
    let map = std::fs::read_dir(&free).expect("free maps").flatten().next().expect("a map").path();
    let mut bytes = std::fs::read(map.join("map.bin")).expect("map");
    let i = bytes.iter().position(|&c| c < 200).expect("a free cell");
    bytes[i] += 1;
    std::fs::write(map.join("map.bin"), bytes).expect("edited");
    shard(s(&suite), "1/2", &b, &["--shard-by", "case"]);
    refused(&d, &[&a, &b], &["navfn::E046", "differs between the shards"]);
}

#[test]
fn shard_auto_reads_slurm_and_kubernetes_array_jobs() {
    let d = tmp("auto");
    let suite = d.join("suite");
    generate_suite(&suite, "9", &[]);
    let run = |env: &[(&str, &str)], out: &Path| {
        vouch_env(&["-q", "navfn", "campaign", s(&suite), "--shard", "auto", "-o", s(out)], env)
    };
    let slurm = d.join("slurm.json");
    let o = run(&[("SLURM_ARRAY_TASK_ID", "3"), ("SLURM_ARRAY_TASK_COUNT", "4")], &slurm);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    assert_eq!(
        json(&slurm)["shards"],
        serde_json::json!({"count": 4, "by": "map", "indices": [3]})
    );
    let k8s = d.join("k8s.json");
    let o = run(&[("JOB_COMPLETION_INDEX", "2"), ("VOUCH_SHARD_COUNT", "4")], &k8s);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    assert_eq!(json(&k8s)["shards"]["indices"], serde_json::json!([2]));
    // the same shard as `--shard 3/4`
    let fixed = d.join("fixed.json");
    shard(s(&suite), "3/4", &fixed, &[]);
    assert_eq!(json(&fixed)["suite"], json(&slurm)["suite"]);
    // no count for Kubernetes, no array job at all, an index beyond the count: usage errors
    for env in [
        &[("JOB_COMPLETION_INDEX", "2")][..],
        &[][..],
        &[("SLURM_ARRAY_TASK_ID", "4"), ("SLURM_ARRAY_TASK_COUNT", "4")][..],
    ] {
        let o = run(env, &d.join("bad.json"));
        assert_eq!(code(&o), 2, "{env:?}");
        assert!(text(&o.stderr).contains("navfn::E054"), "{}", text(&o.stderr));
    }
}

#[test]
fn generation_shards_add_up_to_the_suite_and_run_where_they_were_written() {
    let d = tmp("gen");
    let whole = d.join("whole");
    generate_suite(&whole, "4", &[]);
    let manifest = std::fs::read(whole.join("vouch-suite.json")).expect("the suite's manifest");
    let mut reports = Vec::new();
    for i in 0..3 {
        let share = d.join(format!("share{i}"));
        let env = [("JOB_COMPLETION_INDEX", i.to_string()), ("VOUCH_SHARD_COUNT", "3".into())];
        let env: Vec<(&str, &str)> = env.iter().map(|(k, v)| (*k, v.as_str())).collect();
        let o = vouch_env(
            &[
                "navfn",
                "suite",
                "gen",
                "--seed",
                "4",
                "--maps",
                "3",
                "--cases",
                "6",
                "--size",
                "5..12",
                "--shard",
                "auto",
                "-o",
                s(&share),
            ],
            &env,
        );
        assert_eq!(code(&o), 0, "{}", text(&o.stderr));
        assert!(text(&o.stdout).contains(&format!("shard {i}/3 of the suite's 27 maps")));
        let share_manifest = std::fs::read(share.join("vouch-suite.json")).expect("manifest");
        assert_eq!(share_manifest, manifest, "every share carries the suite's manifest");
        let r = d.join(format!("r{i}.json"));
        shard(s(&share), &format!("{i}/3"), &r, &[]);
        reports.push(r);
    }
    let merged = d.join("merged.json");
    let refs: Vec<&Path> = reports.iter().map(PathBuf::as_path).collect();
    let o = merge(&merged, &refs, &[]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let single = d.join("single.json");
    assert_eq!(code(&vouch(&["-q", "navfn", "campaign", s(&whole), "-o", s(&single)])), 0);
    // the digests of every map's bytes, and the content hash over them, are the unsharded
    // generation's: the union of the shares is the whole suite, byte for byte (the library
    // test `campaign_gen` compares the files themselves)
    assert_eq!(json(&merged)["suite"], json(&single)["suite"]);
    assert!(json(&single)["suite"]["content"].is_string());
    assert_eq!(json(&merged)["categories"], json(&single)["categories"]);
    // a share split by case cannot cover its cases: refused
    let o = vouch(&[
        "-q",
        "navfn",
        "campaign",
        s(&d.join("share0")),
        "--shard",
        "0/3",
        "--shard-by",
        "case",
    ]);
    assert_eq!(code(&o), 1, "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("--shard-by map"));
}

#[test]
fn cases_out_streams_one_line_per_case_in_suite_order() {
    let d = tmp("lines");
    let suite = d.join("suite");
    generate_suite(&suite, "10", &[]);
    let lines = d.join("cases.jsonl");
    let o = vouch(&["-q", "navfn", "campaign", s(&suite), "--json", "--cases-out", s(&lines)]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("report");
    let text = std::fs::read_to_string(&lines).expect("lines");
    let records: Vec<serde_json::Value> =
        text.lines().map(|l| serde_json::from_str(l).expect("one JSON object per line")).collect();
    assert_eq!(records.len() as u64, report["cases"].as_u64().expect("cases"));
    let keys: Vec<(String, String, u64)> = records
        .iter()
        .map(|r| {
            let st = |k: &str| r[k].as_str().expect("string").to_string();
            (st("category"), st("map"), r["case"].as_u64().expect("case"))
        })
        .collect();
    let mut sorted = keys.clone();
    sorted.sort();
    assert_eq!(keys, sorted, "suite order: category, map, case");
    // an unwritable file is an I/O error before anything runs
    let o =
        vouch(&["-q", "navfn", "campaign", s(&suite), "--cases-out", "/nonexistent/dir/c.jsonl"]);
    assert_eq!(code(&o), 2);
}

/// `PATH` with the directory of the `vouch` under test first.
fn path_with_vouch() -> String {
    let bin = Path::new(env!("CARGO_BIN_EXE_vouch")).parent().expect("bin dir").to_path_buf();
    format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default())
}

/// Merges `reports/shard-*.json` of `dir` and checks the result covers the whole suite.
fn merged_covers_the_suite(dir: &Path, shards: usize) {
    let files: Vec<PathBuf> = (0..shards).map(|i| dir.join(format!("shard-{i}.json"))).collect();
    let refs: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    let merged = dir.join("report.json");
    let o = merge(&merged, &refs, &[]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let v = json(&merged);
    assert_eq!(v["shards"]["indices"].as_array().map(Vec::len), Some(shards));
    assert!(v["suite"]["content"].is_string(), "every map of the suite is in the merge");
}

#[test]
fn the_slurm_array_example_runs_as_written() {
    let d = tmp("slurm");
    let script = repo().join("examples/navfn/cluster/slurm-campaign.sh");
    let text_of = std::fs::read_to_string(&script).expect("the example");
    assert!(text_of.contains("#SBATCH --array=0-15"));
    std::fs::create_dir_all(d.join("reports")).expect("reports");
    // every array task as Slurm would start it (16 tasks, 1 map per category, 3 cases per map)
    for i in 0..16 {
        let o = Command::new("bash")
            .arg(&script)
            .current_dir(&d)
            .env("PATH", path_with_vouch())
            .envs([
                ("SLURM_ARRAY_JOB_ID", "42".to_string()),
                ("SLURM_ARRAY_TASK_ID", i.to_string()),
                ("SLURM_ARRAY_TASK_MIN", "0".into()),
                ("SLURM_ARRAY_TASK_COUNT", "16".into()),
                ("SLURM_SUBMIT_DIR", s(&d).into()),
                ("TMPDIR", s(&d).into()),
                ("MAPS", "2".into()),
                ("CASES", "3".into()),
            ])
            .output()
            .expect("bash runs the example");
        assert!(o.status.success(), "task {i}: {}", text(&o.stderr));
    }
    merged_covers_the_suite(&d.join("reports"), 16);
    let left: Vec<_> = std::fs::read_dir(&d).expect("dir").flatten().collect();
    assert_eq!(left.len(), 1, "each task removes its share of the suite: {left:?}");
}

#[test]
fn the_kubernetes_indexed_job_example_runs_as_written() {
    let d = tmp("k8s");
    let manifest =
        std::fs::read_to_string(repo().join("examples/navfn/cluster/campaign-indexed-job.yaml"))
            .expect("the example");
    let field = |key: &str| -> String {
        let line = manifest.lines().find(|l| l.trim_start().starts_with(key)).expect(key);
        line.split_once(':')
            .expect("key: value")
            .1
            .split('#')
            .next()
            .unwrap_or("")
            .trim()
            .trim_matches('"')
            .to_string()
    };
    assert_eq!(field("completionMode"), "Indexed");
    let count = field("completions");
    assert_eq!(field("value"), count, "VOUCH_SHARD_COUNT = completions");
    // the container's shell script: the block under `- |`, with the volumes as local folders
    let lines: Vec<&str> = manifest.lines().collect();
    let start = lines.iter().position(|l| l.trim() == "- |").expect("script block") + 1;
    let indent = lines[start].len() - lines[start].trim_start().len();
    let script: String = lines[start..]
        .iter()
        .take_while(|l| l.len() - l.trim_start().len() >= indent || l.trim().is_empty())
        .map(|l| format!("{}\n", l.get(indent..).unwrap_or("")))
        .collect();
    let script = script
        .replace("--maps 1000 --cases 500", "--maps 2 --cases 3")
        .replace("/work/", &format!("{}/work-$JOB_COMPLETION_INDEX/", s(&d)))
        .replace("/reports/", &format!("{}/reports/", s(&d)));
    std::fs::create_dir_all(d.join("reports")).expect("reports");
    let n: usize = count.parse().expect("a number");
    for i in 0..n {
        let o = Command::new("sh")
            .args(["-c", &script])
            .env("PATH", path_with_vouch())
            .env("JOB_COMPLETION_INDEX", i.to_string())
            .env("VOUCH_SHARD_COUNT", &count)
            .output()
            .expect("sh runs the container's script");
        assert!(o.status.success(), "index {i}: {}", text(&o.stderr));
    }
    merged_covers_the_suite(&d.join("reports"), n);
}

#[test]
fn oracle_comparisons_are_split_by_home_shard_and_recorded_among_the_options() {
    let d = tmp("oracle");
    let suite = d.join("suite");
    generate_suite(&suite, "12", &[]);
    let oracle = format!("{} -q navfn suite run", env!("CARGO_BIN_EXE_vouch"));
    let fast = ["--no-metamorphic", "--no-optimality"];
    let with_oracle = [&fast[..], &["--oracle", &oracle]].concat();
    let (a, b, single) = (d.join("a.json"), d.join("b.json"), d.join("single.json"));
    shard(s(&suite), "0/2", &a, &with_oracle);
    shard(s(&suite), "1/2", &b, &with_oracle);
    let mut args = vec!["-q", "navfn", "campaign", s(&suite), "-o", s(&single)];
    args.extend_from_slice(&with_oracle);
    assert_eq!(code(&vouch(&args)), 0);
    let merged = d.join("merged.json");
    assert_eq!(code(&merge(&merged, &[&a, &b], &[])), 0);
    let (m, one) = (json(&merged), json(&single));
    assert_eq!(m["categories"], one["categories"], "oracle counts add up to the single run's");
    assert_eq!(m["options"]["oracle"], serde_json::json!(oracle));
    let equal: u64 = m["categories"]
        .as_object()
        .expect("categories")
        .values()
        .map(|c| c["oracle"]["pass"].as_u64().expect("count"))
        .sum();
    assert_eq!(
        equal,
        m["cases"].as_u64().expect("cases"),
        "vouch agrees with itself on every case"
    );
    // a shard run without the oracle does not merge with one run with it
    let plain = d.join("plain.json");
    shard(s(&suite), "1/2", &plain, &fast);
    refused(&d, &[&a, &plain], &["navfn::E044", "oracle none"]);
}
