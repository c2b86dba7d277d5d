//! `vouch navfn bench`: the benchmark harness (kept out of the library). Times vouch's NavFn on
//! the cases of a suite (µs per path, three call sequences) and on one planner request (ms per
//! plan, Dijkstra and A*). Single thread; only the planning calls are timed (array set-up, cost
//! input, propagation, path extraction, and the world conversion for the planner), with the
//! thread's CPU clock so that the figures hold on a shared machine (wall time beside it).
//! Figures of the C++ planner are not printed: they were measured elsewhere and are quoted,
//! with their source, in docs/navfn-core.md.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use cpu_time::ThreadTime;
use vouch_navfn::core::{Cell, NoObserver};
use vouch_navfn::maps::{find_test_files, load_ros_map, read_suite_file, SuiteFile};
use vouch_navfn::planner::{NavfnPlanner, PlannerParams};
use vouch_navfn::suite::{CaseRunner, CostInput, MapRef, RunMode};

use super::{map_failure, parse_pair};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch navfn bench`.
#[derive(Args)]
#[command(
    after_help = "Example:\n  vouch navfn bench examples/navfn/suite --plan-map examples/navfn/warehouse.yaml --start 1,1 --goal 8.5,6.5"
)]
pub struct BenchArgs {
    /// Suite to time: a test file, or a folder searched recursively for test.txt (raw NavFn costs)
    suite: PathBuf,
    /// Also time one planner request on this map (map_server YAML, or a PGM/PNG image)
    #[arg(long, value_name = "MAP", requires_all = ["start", "goal"])]
    plan_map: Option<PathBuf>,
    /// Start of the planner request, X,Y in metres
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    start: Option<[f64; 2]>,
    /// Goal of the planner request, X,Y in metres
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    goal: Option<[f64; 2]>,
    /// Repetitions of the whole suite (the best and the mean are reported)
    #[arg(long, default_value_t = 5)]
    repeat: usize,
    /// Repetitions of the planner request
    #[arg(long, default_value_t = 50)]
    repeat_plan: usize,
    /// Print the figures as one JSON document
    #[arg(long)]
    json: bool,
}

/// Best and mean of one workload, CPU and wall.
#[derive(serde::Serialize)]
struct Row {
    workload: String,
    /// Paths per repetition, or points of the planned path.
    count: usize,
    unit: &'static str,
    cpu_best: f64,
    cpu_mean: f64,
    wall_best: f64,
    wall_mean: f64,
}

/// CPU and wall seconds of `f` (CPU falls back to wall where the thread clock is missing).
fn timed(f: impl FnOnce()) -> (f64, f64) {
    let c0 = ThreadTime::try_now().ok();
    let t0 = Instant::now();
    f();
    let wall = t0.elapsed().as_secs_f64();
    let cpu = c0.and_then(|c| c.try_elapsed().ok()).map_or(wall, |d| d.as_secs_f64());
    (cpu, wall)
}

fn row(workload: String, count: usize, unit: &'static str, samples: &[(f64, f64)]) -> Row {
    let n = samples.len().max(1) as f64;
    let best = |f: fn(&(f64, f64)) -> f64| samples.iter().map(f).fold(f64::INFINITY, f64::min);
    let mean = |f: fn(&(f64, f64)) -> f64| samples.iter().map(f).sum::<f64>() / n;
    Row {
        workload,
        count,
        unit,
        cpu_best: best(|s| s.0),
        cpu_mean: mean(|s| s.0),
        wall_best: best(|s| s.1),
        wall_mean: mean(|s| s.1),
    }
}

/// µs per path of one call sequence over the whole suite.
fn suite_row(files: &[SuiteFile], mode: RunMode, repeat: usize) -> Row {
    let mut runner = CaseRunner::new();
    // case parsing is outside the timed region
    let cells: Vec<Vec<(Cell, Cell)>> = files
        .iter()
        .map(|f| {
            f.cases
                .iter()
                .filter_map(|c| c.cells(f.width, f.height))
                .map(|(a, b)| (Cell::new(a[0], a[1]), Cell::new(b[0], b[1])))
                .collect()
        })
        .collect();
    let n: usize = cells.iter().map(Vec::len).sum();
    let mut sink = 0usize;
    let mut samples = Vec::new();
    for _ in 0..repeat.max(1) {
        let (cpu, wall) = timed(|| {
            for (f, cases) in files.iter().zip(&cells) {
                let map =
                    MapRef { bytes: &f.map, nx: f.width, ny: f.height, costs: CostInput::Raw };
                for &(from, to) in cases {
                    let o = runner.run(mode, map, from, to, &mut NoObserver);
                    sink += o.map_or(0, |o| o.len);
                }
            }
        });
        let per = 1e6 / n.max(1) as f64;
        samples.push((cpu * per, wall * per));
    }
    std::hint::black_box(sink);
    row(format!("{} ({} maps)", mode.name(), files.len()), n, "µs/path", &samples)
}

/// Runs `vouch navfn bench`.
pub fn run(a: BenchArgs, ctx: &mut Ctx) -> CmdResult {
    let files = find_test_files(&a.suite, "test.txt").map_err(map_failure)?;
    if files.is_empty() {
        return Err(Failure::usage(format_args!("no test.txt below {}", a.suite.display())));
    }
    let suite: Vec<SuiteFile> =
        files.iter().map(|f| read_suite_file(f)).collect::<Result<_, _>>().map_err(map_failure)?;
    let mut rows = Vec::new();
    for mode in [RunMode::Paper, RunMode::NavfnDijkstra, RunMode::NavfnAstar] {
        rows.push(suite_row(&suite, mode, a.repeat));
    }
    if let (Some(path), Some(start), Some(goal)) = (&a.plan_map, a.start, a.goal) {
        let map = load_ros_map(path, true).map_err(map_failure)?;
        for astar in [false, true] {
            let params = PlannerParams { use_astar: astar, ..PlannerParams::default() };
            let mut planner =
                NavfnPlanner::new(&map.costmap, map.width, map.height, map.world(), params)
                    .map_err(Failure::rejected)?;
            planner.plan_checked(start, goal).map_err(Failure::rejected)?;
            let mut points = 0;
            let mut samples = Vec::new();
            for _ in 0..a.repeat_plan.max(1) {
                let (cpu, wall) = timed(|| points = planner.create_plan(start, goal).navfn_len);
                samples.push((cpu * 1e3, wall * 1e3));
            }
            let algo = if astar { "A*" } else { "Dijkstra" };
            let label = format!("planner {algo} ({}x{})", map.width, map.height);
            rows.push(row(label, points, "ms/plan", &samples));
        }
    }
    if a.json {
        ctx.out.json(&rows)?;
        return Ok(Exit::Ok);
    }
    writeln!(
        ctx.out,
        "vouch navfn bench: vouch's figures measured in this run; single thread; {} repetitions \
         of the suite, {} of the plan; CPU time of the thread, wall time in brackets",
        a.repeat.max(1),
        a.repeat_plan.max(1)
    )?;
    writeln!(
        ctx.out,
        "{:<34} {:>8} {:>9} {:>18} {:>18}",
        "workload", "count", "unit", "best", "mean"
    )?;
    for r in &rows {
        let best = format!("{:.3} ({:.3})", r.cpu_best, r.wall_best);
        let mean = format!("{:.3} ({:.3})", r.cpu_mean, r.wall_mean);
        writeln!(ctx.out, "{:<34} {:>8} {:>9} {best:>18} {mean:>18}", r.workload, r.count, r.unit)?;
    }
    Ok(Exit::Ok)
}
