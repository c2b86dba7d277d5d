//! The `vouch navfn` commands as a user runs them: exit codes (0 ok, 1 rejected, 2 usage or I/O,
//! 3 findings), what they print, help for every subcommand, and a closed pipe. Inputs are the
//! bundled examples under `examples/navfn/` and files written here.

mod common;

use common::{code, vouch_at_root as vouch};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

#[path = "navfn_cli/campaign.rs"]
mod campaign;

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("navfn_cli");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    dir.join(name)
}

const MAP: &str = "examples/navfn/warehouse.yaml";
const SUITE: &str = "examples/navfn/suite";

#[test]
fn every_subcommand_has_help_with_an_example() {
    for cmd in [
        &["plan"][..],
        &["check-bag"],
        &["suite", "run"],
        &["suite", "gen"],
        &["suite", "diff"],
        &["bench"],
        &["campaign"],
        &["report", "merge"],
    ] {
        let mut args = vec!["navfn"];
        args.extend_from_slice(cmd);
        args.push("-h");
        let o = vouch(&args);
        let out = text(&o.stdout);
        assert_eq!(code(&o), 0, "{cmd:?}");
        assert!(
            out.contains("Example:\n  vouch navfn") || out.contains("Examples:\n  vouch navfn"),
            "{cmd:?} has no example:\n{out}"
        );
        // every argument has a help text: on its line, or on the next one
        let lines: Vec<&str> = out.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            let t = line.trim();
            if !(t.starts_with('-') || t.starts_with('<')) || !line.starts_with("  ") {
                continue;
            }
            let next = lines.get(i + 1).map_or("", |l| l.trim());
            let helped = t.contains("  ") || !(next.is_empty() || next.starts_with('-'));
            assert!(helped, "{cmd:?}: `{t}` has no help");
        }
    }
}

#[test]
fn plan_prints_a_summary_and_poses_only_on_request() {
    let o = vouch(&["navfn", "plan", MAP, "--start", "1,1", "--goal", "8.5,6.5"]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert_eq!(out.lines().count(), 1, "a one-line summary: {out}");
    assert!(out.starts_with("status OK  poses ") && out.contains("checks ok"), "{out}");
    let poses: usize = out.split_whitespace().nth(3).and_then(|n| n.parse().ok()).expect("count");

    let file = tmp("poses.txt");
    let o = vouch(&[
        "navfn",
        "plan",
        MAP,
        "--start",
        "1,1",
        "--goal",
        "8.5,6.5",
        "--poses",
        "-o",
        file.to_str().expect("utf-8"),
    ]);
    assert_eq!(code(&o), 0);
    assert_eq!(text(&o.stdout).lines().count(), 1 + poses);
    let written = std::fs::read_to_string(&file).expect("poses written");
    assert_eq!(written.lines().count(), poses);
    assert_eq!(
        written.lines().last(),
        Some("8.500000 6.500000 0.000000"),
        "the path ends at the goal, facing the goal heading"
    );
    let o = vouch(&[
        "navfn",
        "plan",
        MAP,
        "--start",
        "1,1",
        "--goal",
        "8.5,6.5",
        "--goal-yaw",
        "-1.5",
        "--max-cycles-factor",
        "6",
        "--use-final-approach-orientation",
        "--json",
        "--poses",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    let turned = v["poses"].as_array().expect("poses");
    let last = &turned[turned.len() - 1];
    assert_ne!(last["yaw"].as_f64(), Some(0.0), "the final approach turns the last pose");
    assert_ne!(last["yaw"].as_f64(), Some(-1.5), "… away from the goal heading");
    assert_eq!(turned[0]["yaw"].as_f64(), Some(0.0), "nav2's identity orientation");
    assert!(turned[0]["x"].is_f64() && turned[0]["y"].is_f64(), "{}", turned[0]);
    assert_eq!(v["max_cycles_factor"].as_u64(), Some(6));

    let o = vouch(&["navfn", "plan", MAP, "--start", "1,1", "--goal", "8.5,6.5", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    assert_eq!(v["version"], 2);
    assert_eq!(v["status"], "ok");
    assert_eq!(v["pose_count"], poses);
    let listed = v["poses"].as_array().expect("the poses are always in the document");
    assert_eq!(listed.len() as u64, v["pose_count"].as_u64().unwrap());
}

#[test]
fn plan_rejects_bad_requests_with_coded_errors() {
    let cases: [(&[&str], &str); 5] = [
        (&["--start", "1,1", "--goal", "50,1"], "navfn::E024"),
        (&["--start", "1,1", "--goal", "1.5,1.5"], "navfn::E025"),
        (&["--start", "1,1", "--goal", "8,6", "--tolerance", "1e9"], "navfn::E021"),
        (&["--start", "1,1", "--goal", "8,6", "--tolerance=-1"], "navfn::E021"),
        (&["--start", "1.5,1", "--goal", "8,6", "--cells"], "navfn::E023"),
    ];
    for (args, want) in cases {
        let mut all = vec!["--message-format", "short", "navfn", "plan", MAP];
        all.extend_from_slice(args);
        let o = vouch(&all);
        let err = text(&o.stderr);
        assert_eq!(code(&o), 1, "{args:?}: {err}");
        assert!(err.contains(&format!("error[{want}]")), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "printed once: {err}");
    }
}

#[test]
fn map_errors_are_located_and_unreadable_files_are_io_errors() {
    let yaml = tmp("bad.yaml");
    std::fs::write(&yaml, "image: warehouse.pgm\nresolution: fast\n").expect("written");
    let o = vouch(&[
        "--message-format",
        "short",
        "navfn",
        "plan",
        yaml.to_str().expect("utf-8"),
        "--start",
        "1,1",
        "--goal",
        "2,2",
    ]);
    let err = text(&o.stderr);
    assert_eq!(code(&o), 1, "{err}");
    assert!(err.contains("bad.yaml:2:13: error[navfn::E011]"), "{err}");
    let o = vouch(&["navfn", "plan", "/nonexistent/map.yaml", "--start", "1,1", "--goal", "2,2"]);
    assert_eq!(code(&o), 2, "{}", text(&o.stderr));
}

#[test]
fn suite_run_checks_and_modes() {
    let o =
        vouch(&["navfn", "suite", "run", SUITE, "--mode", "navfn", "--algo", "astar", "--check"]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert_eq!(out.lines().filter(|l| l.starts_with("MAP ")).count(), 3);
    assert_eq!(out.lines().filter(|l| l.starts_with("CASE ")).count(), 220);
    assert!(text(&o.stderr).contains("plan checks: 0 violations"));
    // one scheme of mode names: cell-level commands refuse planner mode
    let o = vouch(&["navfn", "suite", "run", SUITE, "--mode", "planner", "--pot"]);
    assert_eq!(code(&o), 2);
    let o = vouch(&["navfn", "campaign", SUITE, "--mode", "planner"]);
    assert_eq!(code(&o), 2);
}

#[test]
fn suite_run_into_a_closed_pipe_ends_quietly() {
    // `vouch navfn suite run … | head -1`: far more output than the pipe holds
    let mut child = Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(["navfn", "suite", "run", SUITE, "--trace", "cells", "--pot"])
        .current_dir(repo())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    let mut first = String::new();
    let stdout = child.stdout.take().expect("piped");
    BufReader::new(stdout).read_line(&mut first).expect("one line");
    // the reader goes away here, like `head -1`
    let o = child.wait_with_output().expect("ends");
    assert!(!first.is_empty());
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn campaign_report_and_merge_follow_the_conventions() {
    let (a, b, merged) = (tmp("shard0.json"), tmp("shard1.json"), tmp("merged.json"));
    for (i, p) in [(0, &a), (1, &b)] {
        let shard = format!("{i}/2");
        let o = vouch(&[
            "navfn",
            "campaign",
            SUITE,
            "--mode",
            "navfn",
            "--algo",
            "astar",
            "--shard",
            &shard,
            "-o",
            p.to_str().expect("utf-8"),
        ]);
        assert_eq!(code(&o), 0, "{}", text(&o.stderr));
        assert!(text(&o.stdout).contains("TOTAL"));
    }
    let o = vouch(&[
        "navfn",
        "report",
        "merge",
        "--json",
        "-o",
        merged.to_str().expect("utf-8"),
        a.to_str().expect("utf-8"),
        b.to_str().expect("utf-8"),
    ]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    assert_eq!(v["cases"], 220);
    assert_eq!(v["options"]["mode"], "navfn-astar");
    assert!(v["categories"]["lanes"]["checks"]["obstacle_free_queues"]["pass"].is_u64());
    // a report that is not one is rejected with its position
    std::fs::write(&a, "{\"suite\": 1}").expect("written");
    let o = vouch(&["navfn", "report", "merge", "-o", "/dev/null", a.to_str().expect("utf-8")]);
    assert_eq!(code(&o), 1, "{}", text(&o.stderr));
}

#[test]
fn bench_prints_vouch_figures_only() {
    let o = vouch(&[
        "navfn",
        "bench",
        SUITE,
        "--passes",
        "1",
        "--repeat",
        "1",
        "--plan-map",
        MAP,
        "--start",
        "1,1",
        "--goal",
        "8.5,6.5",
        "--repeat-plan",
        "2",
    ]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(out.contains("every figure measured in this run"), "{out}");
    assert!(!out.contains("C++") && !out.contains("oracle"), "vouch's figures only: {out}");
    assert_eq!(out.lines().filter(|l| l.contains("µs/case")).count(), 3, "{out}");
    assert_eq!(out.lines().filter(|l| l.contains("ms CPU")).count(), 6, "{out}");
    assert_eq!(out.lines().filter(|l| l.contains("ms/plan")).count(), 2, "{out}");
    let o = vouch(&["navfn", "bench"]);
    assert_eq!(code(&o), 2, "the suite must be given");
}

/// An oracle under the contract and its timing extension: vouch itself behind a shell script.
fn self_oracle() -> PathBuf {
    let script = tmp("self-oracle.sh");
    let me = env!("CARGO_BIN_EXE_vouch");
    let body = format!(
        "#!/bin/sh\ncase \" $* \" in *\" --time-planning \"*) exec '{me}' -q navfn bench \"$@\";; esac\nexec '{me}' -q navfn suite run \"$@\"\n"
    );
    std::fs::write(&script, body).expect("script written");
    script
}

#[test]
fn bench_measures_an_oracle_side_by_side() {
    let oracle = format!("sh {}", self_oracle().display());
    let o = vouch(&[
        "navfn",
        "bench",
        SUITE,
        "--oracle",
        &oracle,
        "--modes",
        "navfn-dijkstra",
        "--passes",
        "2",
        "--repeat",
        "1",
        "--json",
    ]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("identical on 3 of 3 files"), "{}", text(&o.stderr));
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    let rows = rows.as_array().expect("rows");
    assert_eq!(rows.len(), 3, "planning, one file per process, whole folder");
    assert_eq!(rows[0]["count"], 220);
    for r in rows {
        for side in ["vouch", "oracle"] {
            let s = r[side].as_array().expect("samples");
            assert_eq!(s.len(), 2, "one sample per pass: {r}");
            assert!(s.iter().all(|v| v.as_f64().is_some_and(|v| v > 0.0)), "{r}");
        }
    }
    assert!(rows[0]["oracle_peak_rss_kb"].as_u64().is_some_and(|k| k > 0));
    // the table names the oracle and prints a ratio
    let o = vouch(&[
        "navfn",
        "bench",
        SUITE,
        "--oracle",
        &oracle,
        "--modes",
        "paper",
        "--passes",
        "1",
        "--repeat",
        "1",
        "--no-process",
    ]);
    let out = text(&o.stdout);
    assert!(out.contains("ratio") && out.contains("alternating"), "{out}");
    // an oracle that fails is an I/O error, and so is a command line that does not split
    let o = vouch(&["navfn", "bench", SUITE, "--oracle", "false", "--passes", "1", "--no-process"]);
    assert_eq!(code(&o), 2, "{}", text(&o.stderr));
    let o = vouch(&["navfn", "bench", SUITE, "--oracle", "'unbalanced", "--no-process"]);
    assert_eq!(code(&o), 2, "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("unbalanced quote"), "{}", text(&o.stderr));
}

#[test]
fn bench_scale_reports_explored_cells_and_memory() {
    let dir = tmp("scale");
    let o = vouch(&[
        "navfn",
        "bench",
        "--scale",
        "20,40",
        "--scale-dir",
        dir.to_str().expect("utf-8"),
        "--modes",
        "navfn-astar",
        "--passes",
        "1",
        "--repeat",
        "1",
        "--json",
    ]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    let rows = rows.as_array().expect("rows");
    let names: Vec<&str> = rows.iter().map(|r| r["workload"].as_str().expect("name")).collect();
    assert_eq!(names[..2], ["scale navfn-astar 20x20", "scale navfn-astar 40x40"], "{names:?}");
    let (distance, process): (Vec<&str>, Vec<&str>) =
        names[2..].iter().partition(|n| n.starts_with("scale navfn-astar 40x40 d="));
    assert!(!distance.is_empty(), "{names:?}");
    assert_eq!(
        process,
        [
            "process navfn-astar 20x20, one process per map",
            "process navfn-astar 40x40, one process per map"
        ],
        "{names:?}"
    );
    // corner to corner on a connected random map explores cells; a longer case explores more
    assert!(rows.iter().all(|r| r["count"].as_u64().is_some_and(|c| c > 0)), "{rows:?}");
    assert!(rows[0]["vouch_peak_rss_kb"].as_u64().is_some_and(|k| k > 0));
    assert!(dir.join("size_40/map.bin").is_file());
}

#[test]
fn suite_diff_exit_codes_follow_the_contract() {
    let me = env!("CARGO_BIN_EXE_vouch");
    let itself = format!("{me} -q navfn suite run");
    let o = vouch(&["navfn", "suite", "diff", SUITE, "--oracle", &itself, "--mode", "navfn"]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
    assert!(text(&o.stdout).starts_with("3 files, 220 cases: 220 equal, 0 different"));
    let perturbed = format!("{itself} --perturb-pri-inc 90");
    let report = tmp("diff.json");
    let o = vouch(&[
        "navfn",
        "suite",
        "diff",
        SUITE,
        "--oracle",
        &perturbed,
        "--json",
        "-o",
        report.to_str().expect("utf-8"),
    ]);
    assert_eq!(code(&o), 3, "a disagreement is a finding: {}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    assert!(v["different"].as_u64().is_some_and(|d| d > 0));
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).expect("written")).expect("json");
    assert_eq!(written, v);
    let o = vouch(&["navfn", "suite", "diff", SUITE, "--oracle", "/nonexistent/oracle"]);
    assert_eq!(code(&o), 2, "an oracle that cannot run is an I/O error");
}

/// A plan that fails a plan check is a finding by default (exit 3, the violation listed);
/// `--checked`, which used to ask for that, is still accepted with a deprecation warning. The
/// map: a 6×8 trinary map on which the robot starts in the border column, which NavFn's set-up
/// makes an obstacle, so a path point lies in an obstacle (ValidPath).
#[test]
fn a_failed_plan_check_exits_3_by_default() {
    #[rustfmt::skip]
    let pixels: [u8; 48] = [
        100, 150, 254,   0, 100, 254,
        254, 150,   0, 255,   0,   0,
        255, 150, 255, 100, 205, 205,
        255, 150, 100, 205, 100, 100,
        255, 150, 255, 255, 205, 255,
        255, 205, 254, 255, 255, 205,
        255, 255, 255, 255, 100, 255,
        150,   0, 205, 205, 255, 255,
    ];
    let dir = tmp("border_start");
    std::fs::create_dir_all(&dir).expect("dir");
    let pgm = [b"P5\n6 8\n255\n".as_slice(), &pixels].concat();
    std::fs::write(dir.join("m.pgm"), pgm).expect("pgm");
    let yaml = "image: m.pgm\nmode: trinary\nresolution: 1.0\norigin: [0.0, 0.0, 0.0]\n\
                negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    std::fs::write(dir.join("m.yaml"), yaml).expect("yaml");
    let map = dir.join("m.yaml");
    let map = map.to_str().expect("utf-8");
    let base = ["navfn", "plan", map, "--start", "0.42,4.63", "--goal", "3.71,4.34"];
    let o = vouch(&base);
    assert_eq!(code(&o), 3, "{}{}", text(&o.stdout), text(&o.stderr));
    assert!(text(&o.stdout).contains("violation: path point"), "{}", text(&o.stdout));
    assert!(text(&o.stdout).contains("(ValidPath)"), "{}", text(&o.stdout));
    let o = vouch(&[&base[..], &["--checked"]].concat());
    assert_eq!(code(&o), 3);
    assert!(text(&o.stderr).contains("--checked is deprecated"), "{}", text(&o.stderr));
    // the plan on the bundled map holds every check: 0
    let o = vouch(&["navfn", "plan", MAP, "--start", "1,1", "--goal", "8.5,6.5"]);
    assert_eq!(code(&o), 0, "{}", text(&o.stderr));
}
