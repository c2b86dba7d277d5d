//! The paper's circus counterexample (§4.1, Fig. 4 right): on `circus_12L`, from the lower right
//! cell (3, 12) to the upper middle cell (2, 1), NavFn takes the expensive right lane (253) although
//! the left lane (153) is cheaper; the paper counts the detour as 700 cost units.

use std::path::PathBuf;

use vouch_navfn::campaign::exec::{run_case, RunMode};
use vouch_navfn::campaign::optimal::{grid_optimum, path_cost};
use vouch_navfn::campaign::pictures::counterexample_png;
use vouch_navfn::campaign::runner::{prepare, to_pairs};
use vouch_navfn::campaign::suite_io::read_test_file;
use vouch_navfn::suite_run::CaseRunner;

#[test]
fn circus_counterexample_is_reproduced() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/navfn/suite/circus/circus_12L");
    if !dir.is_dir() {
        eprintln!("skipping: {} not found", dir.display());
        return;
    }
    let m = read_test_file(&dir.join("test.txt"), "circus", "circus_12L").expect("reads");
    let k = m
        .cases
        .iter()
        .position(|c| (c.x0, c.y0, c.x1, c.y1) == (3, 12, 2, 1))
        .expect("the paper's case");
    let pm = prepare(m.clone(), 0, false);
    let mut runner = CaseRunner::new();
    let run = run_case(&mut runner, &m, &pm.setup_costs, &m.cases[k], RunMode::Paper, None)
        .expect("runs");
    assert!(run.outcome.len > 0, "NavFn finds a path");
    let path = to_pairs(runner.nav().path());

    // NavFn's path stays in the right lane (column 3) from row 12 up to row 2.
    for p in &path[..path.len() - 1] {
        assert_eq!(p.0.round(), 3.0, "point {p:?} leaves the right lane");
    }
    // The optimum under the campaign's cost model takes the left lane (column 1).
    let opt = grid_optimum(&pm.setup_costs, m.width, m.height, (3, 12), (2, 1)).expect("reachable");
    assert!(
        opt.cells.iter().filter(|c| c.0 == 1).count() >= 10,
        "optimum via the left lane: {:?}",
        opt.cells
    );
    let navfn_cost = path_cost(&pm.setup_costs, m.width, m.height, &path);
    let excess = navfn_cost - opt.cost;
    // Paper: "a path whose cost is 700 units higher" (sum of cell costs along the lanes:
    // ten cells of 253 against ten of 153 plus the detour cells). Our model charges each move
    // its length × mean cost, so the excess differs a little but has the same order.
    let cells = |cs: &[(u32, u32)]| cs.iter().map(|&(x, y)| u32::from(m.get(x, y))).sum::<u32>();
    let navfn_cells: Vec<(u32, u32)> =
        path.iter().map(|p| (p.0.round() as u32, p.1.round() as u32)).collect();
    let cell_excess = cells(&navfn_cells) as i64 - cells(&opt.cells) as i64;
    println!("circus_12L (3,12)->(2,1): NavFn {navfn_cost:.1}, optimum {:.1}, excess {excess:.1} (model); cell-sum excess {cell_excess}", opt.cost);
    assert!(excess > 600.0 && excess < 900.0, "excess {excess}");
    assert!((600..=800).contains(&cell_excess), "cell-sum excess {cell_excess} vs the paper's 700");

    let png = std::env::temp_dir().join(format!("vouch-circus-{}.png", std::process::id()));
    counterexample_png(&png, &pm, k, RunMode::Paper).expect("picture written");
    let bytes = std::fs::read(&png).expect("png");
    assert_eq!(&bytes[1..4], b"PNG");
    println!("picture: {}", png.display());
}

#[test]
fn per_case_records_carry_the_circus_excess() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/navfn/suite/circus");
    if !dir.is_dir() {
        eprintln!("skipping: {} not found", dir.display());
        return;
    }
    let out = std::env::temp_dir().join(format!("vouch-circus-cases-{}.jsonl", std::process::id()));
    let opts = vouch_navfn::campaign::runner::CampaignOptions::default();
    let (text, report) =
        vouch_navfn::campaign::commands::campaign(&dir, &opts, None, None, None, Some(&out))
            .expect("runs");
    assert!(text.contains("circus"));
    assert_eq!(report.failures(), 0);
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(&out)
        .expect("written")
        .lines()
        .map(|l| serde_json::from_str(l).expect("json line"))
        .collect();
    assert_eq!(lines.len(), 5, "one line per circus case");
    let rec = lines
        .iter()
        .find(|v| v["map"] == "circus_12L" && v["coords"] == serde_json::json!([3, 12, 2, 1]))
        .expect("the paper's case");
    assert_eq!(rec["outcome"], "found");
    let excess = rec["excess"].as_f64().expect("excess");
    assert!((excess - 820.7).abs() < 0.1, "excess {excess}");
    assert!(rec["failed"].as_array().is_some_and(|a| a.is_empty()));
    let _ = std::fs::remove_file(out);
}
