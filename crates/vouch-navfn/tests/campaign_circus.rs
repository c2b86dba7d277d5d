//! The paper's circus counterexample (§4.1, Fig. 4 right): on `circus_12L`, from the lower right
//! cell (3, 12) to the upper middle cell (2, 1), NavFn takes the expensive right lane (253) although
//! the left lane (153) is cheaper; the paper counts the detour as 700 cost units.

use vouch_navfn::campaign::exec::run_case;
use vouch_navfn::campaign::names::Outcome;
use vouch_navfn::campaign::optimal::{grid_optimum, path_cost};
use vouch_navfn::campaign::pictures::counterexample_png;
use vouch_navfn::campaign::report::CaseRecord;
use vouch_navfn::campaign::runner::{CampaignOptions, prepare, run_campaign, to_pairs};
use vouch_navfn::campaign::suite_io::read_test_file;
use vouch_navfn::suite::{CaseRunner, RunMode};

#[test]
fn circus_counterexample_is_reproduced() {
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    let dir = shared.join("suite/circus/circus_12L");
    let m = read_test_file(&dir.join("test.txt"), "circus", "circus_12L").expect("reads");
    let k = m
        .cases
        .iter()
        .position(|c| (c.x0, c.y0, c.x1, c.y1) == (3, 12, 2, 1))
        .expect("the paper's case");
    let pm = prepare(m.clone(), false);
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
    println!(
        "circus_12L (3,12)->(2,1): NavFn {navfn_cost:.1}, optimum {:.1}, excess {excess:.1} (model); cell-sum excess {cell_excess}",
        opt.cost
    );
    assert!(excess > 600.0 && excess < 900.0, "excess {excess}");
    assert!((600..=800).contains(&cell_excess), "cell-sum excess {cell_excess} vs the paper's 700");

    let dir = tempfile::tempdir().expect("temporary directory");
    let png = dir.path().join("circus.png");
    counterexample_png(&png, &pm, k, RunMode::Paper).expect("picture written");
    let bytes = std::fs::read(&png).expect("png");
    assert_eq!(&bytes[1..4], b"PNG");
}

/// The C++ path of case `k` from a golden file: the float32 bit patterns of its PATH line.
fn golden_path(golden: &str, k: usize) -> Vec<(f32, f32)> {
    let mut lines = golden.lines();
    let head = format!("CASE {k} ");
    lines.find(|l| l.starts_with(&head)).expect("the case is in the golden file");
    let path = lines.next().expect("a PATH line follows");
    let bits = |h: &str| f32::from_bits(u32::from_str_radix(h, 16).expect("hex"));
    path.split_whitespace()
        .skip(1)
        .map(|t| t.split_once(':').expect("x:y"))
        .map(|(x, y)| (bits(x), bits(y)))
        .collect()
}

/// The cost model stated in docs/navfn-campaign.md, written out here independently of the
/// campaign's code: the path's points read as cells (nearest cell, half away from zero),
/// repeats dropped, each move between neighbouring cells costing its length (1 or √2) times
/// the mean of the two cells' costs — the optimum's own metric.
fn model_cost(costs: &[u8], w: usize, path: &[(f32, f32)]) -> f64 {
    let mut cells: Vec<(i64, i64)> =
        path.iter().map(|p| (p.0.round() as i64, p.1.round() as i64)).collect();
    cells.dedup();
    let cost = |c: (i64, i64)| f64::from(costs[c.1 as usize * w + c.0 as usize]);
    cells
        .windows(2)
        .map(|m| {
            assert!((m[1].0 - m[0].0).abs() <= 1 && (m[1].1 - m[0].1).abs() <= 1, "a jump");
            let len =
                if m[0].0 != m[1].0 && m[0].1 != m[1].1 { std::f64::consts::SQRT_2 } else { 1.0 };
            len * (cost(m[0]) + cost(m[1])) / 2.0
        })
        .sum()
}

/// The least 8-connected grid cost from `a` to `b` by Bellman–Ford relaxation (every cell
/// relaxed against every neighbour until nothing changes): a different algorithm than the
/// campaign's heap-based Dijkstra, on the same stated model.
fn relaxed_optimum(costs: &[u8], w: usize, h: usize, a: (usize, usize), b: (usize, usize)) -> f64 {
    let mut d = vec![f64::INFINITY; w * h];
    d[a.1 * w + a.0] = 0.0;
    let mut changed = true;
    while changed {
        changed = false;
        for y in 1..h - 1 {
            for x in 1..w - 1 {
                let i = y * w + x;
                if costs[i] >= 254 {
                    continue;
                }
                for (nx, ny) in [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                    .into_iter()
                    .chain([(x - 1, y - 1), (x + 1, y - 1), (x - 1, y + 1), (x + 1, y + 1)])
                {
                    let j = ny * w + nx;
                    let len = if nx != x && ny != y { std::f64::consts::SQRT_2 } else { 1.0 };
                    let via = d[j] + len * (f64::from(costs[i]) + f64::from(costs[j])) / 2.0;
                    if costs[j] < 254 && via < d[i] {
                        d[i] = via;
                        changed = true;
                    }
                }
            }
        }
    }
    d[b.1 * w + b.0]
}

#[test]
fn per_case_records_carry_the_circus_excess() {
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    let dir = shared.join("suite/circus");
    let mut records: Vec<CaseRecord> = Vec::new();
    let report =
        run_campaign(&dir, &CampaignOptions::default(), &(), Some(&mut records)).expect("runs");
    assert_eq!(report.failures(), 0);
    assert_eq!(records.len(), 5, "one record per circus case");
    let rec = records
        .iter()
        .find(|r| r.map == "circus_12L" && r.coords == [3, 12, 2, 1])
        .expect("the paper's case");
    assert_eq!(rec.outcome, Outcome::Found);
    assert!(rec.failed.is_empty());
    let json = serde_json::to_value(rec).expect("json");
    assert_eq!(json["outcome"], "found");

    // The expected excess, derived without the campaign: the C++ path from the golden file,
    // the map's cell costs with NavFn's 254 border, the stated cost model, and an optimum by
    // plain relaxation.
    let map = std::fs::read(shared.join("suite/circus/circus_12L/map.bin")).expect("map");
    let (w, h) = (5, 14);
    let mut costs = map.clone();
    for y in 0..h {
        for x in 0..w {
            if x == 0 || y == 0 || x == w - 1 || y == h - 1 {
                costs[y * w + x] = 254;
            }
        }
    }
    let golden = std::fs::read_to_string(shared.join("golden/circus/circus_12L/paper_astar.txt"))
        .expect("golden");
    let path = golden_path(&golden, rec.case as usize);
    let navfn_cost = model_cost(&costs, w, &path);
    let optimum = relaxed_optimum(&costs, w, h, (2, 1), (3, 12));
    let excess = rec.excess.expect("excess");
    println!("circus_12L (3,12)->(2,1): NavFn {navfn_cost:.3}, optimum {optimum:.3}");
    assert!((rec.navfn_cost.expect("cost") - navfn_cost).abs() < 1e-9);
    assert!((rec.optimal_cost.expect("optimum") - optimum).abs() < 1e-9);
    assert!((excess - (navfn_cost - optimum)).abs() < 1e-9, "excess {excess}");
}
