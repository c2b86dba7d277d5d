//! `vouch navfn bench`: the benchmark harness (kept out of the library).
//!
//! Everything printed is measured in this run. With `--oracle CMD` an external NavFn speaking the
//! oracle contract (docs/navfn-campaign.md) is measured side by side on the same inputs, the two
//! sides alternating pass by pass; without it only vouch's figures are printed. Workloads, for
//! each call sequence of `--modes`:
//! * planning: the planning calls only (array set-up, cost input, propagation, path extraction),
//!   best of `--repeat` in-process repetitions per test file, thread CPU time, summed over the
//!   files — each side in its own process answering the contract's `--time-planning` extension;
//! * whole process, one test file per process and the whole folder in one process (parse, plan,
//!   hash, print): CPU time of the process;
//! * scale (`--scale`): random-cost maps of the given sides, corner to corner, and cases of
//!   growing length on one map (explored cells), time and peak resident set.
//!
//! Besides, `--plan-map` times one planner request in this process (vouch only: the contract
//! has no planner mode). The hidden `--time-planning R` is vouch's side of the timing extension.

mod scale;
mod side;

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use cpu_time::ThreadTime;
use vouch_navfn::core::{Cell, NoObserver, POT_HIGH};
use vouch_navfn::maps::{SuiteFile, find_test_files, load_ros_map, read_suite_file};
use vouch_navfn::planner::{NavfnPlanner, PlannerParams};
use vouch_navfn::suite::{CaseRunner, CostInput, MapRef, RunMode};

use super::{AlgoArg, ModeArg, map_failure, parse_pair, run_mode};
use crate::contract::{CmdResult, Ctx, Exit, Failure};
use side::{Side, TimeLine};

/// A call sequence to benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BenchMode {
    /// The paper's harness (A*, no swap)
    Paper,
    /// The planner's cell-level sequence with atStart Dijkstra
    NavfnDijkstra,
    /// The planner's cell-level sequence with A*
    NavfnAstar,
}

impl From<BenchMode> for RunMode {
    fn from(m: BenchMode) -> RunMode {
        match m {
            BenchMode::Paper => RunMode::Paper,
            BenchMode::NavfnDijkstra => RunMode::NavfnDijkstra,
            BenchMode::NavfnAstar => RunMode::NavfnAstar,
        }
    }
}

/// Arguments of `vouch navfn bench`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        [
            "vouch navfn bench examples/navfn/suite --passes 3",
            "vouch navfn bench examples/navfn/suite --oracle ./my-navfn-oracle",
            "vouch navfn bench --scale 100,200,500,1000 --modes navfn-dijkstra,navfn-astar"
        ],
        "0 measured, 1 suite or map rejected, 2 usage, I/O or oracle error"
    )
)]
pub struct BenchArgs {
    /// Suite to time: a test file, or a folder searched recursively for test.txt (raw NavFn costs)
    #[arg(required_unless_present = "scale")]
    suite: Option<PathBuf>,
    /// External implementation of the oracle contract to measure side by side (a shell command;
    /// it must also answer `--time-planning R`, see docs/navfn-core.md)
    #[arg(long, value_name = "CMD")]
    oracle: Option<String>,
    /// Call sequences to time
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "paper,navfn-dijkstra,navfn-astar"
    )]
    modes: Vec<BenchMode>,
    /// Passes; the sides alternate within each pass and the median (and minimum) is reported
    #[arg(long, default_value_t = 5)]
    passes: usize,
    /// In-process repetitions of each test file's planning per pass (the best one counts)
    #[arg(long, default_value_t = 3)]
    repeat: usize,
    /// Skip the whole-process workloads
    #[arg(long)]
    no_process: bool,
    /// Scale: random-cost maps of these sides (cells), e.g. 100,200,500,1000,2000,4000
    #[arg(long, value_delimiter = ',', value_name = "N,N,…")]
    scale: Vec<usize>,
    /// Scale: where the generated maps are written (default: a folder in the temporary
    /// directory, removed afterwards)
    #[arg(long, value_name = "DIR")]
    scale_dir: Option<PathBuf>,
    /// Scale: seed of the random costs
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Also time one planner request on this map in this process (map_server YAML, PGM or PNG)
    #[arg(long, value_name = "MAP", requires_all = ["start", "goal"])]
    plan_map: Option<PathBuf>,
    /// Start of the planner request, X,Y in metres
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    start: Option<[f64; 2]>,
    /// Goal of the planner request, X,Y in metres
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    goal: Option<[f64; 2]>,
    /// Repetitions of the planner request
    #[arg(long, default_value_t = 50)]
    repeat_plan: usize,
    /// Print the figures as one JSON document (every sample included) instead of the table
    #[arg(long)]
    json: bool,
    /// Also write the JSON document to FILE (e.g. for scripts/navfn-scale-plot.py)
    #[arg(long, value_name = "FILE")]
    json_out: Option<PathBuf>,
    /// Timing extension of the oracle contract: print `TIME` lines (planning only, best of R)
    #[arg(long, hide = true, value_name = "R")]
    time_planning: Option<usize>,
    /// With --time-planning: call sequence (the contract's spelling)
    #[arg(long, hide = true, value_enum, default_value = "paper")]
    mode: ModeArg,
    /// With --time-planning: propagation in navfn mode
    #[arg(long, hide = true, value_enum, default_value = "dijkstra")]
    algo: AlgoArg,
}

/// One measured workload: a sample per pass and side.
#[derive(serde::Serialize)]
struct Row {
    workload: String,
    /// Cases (or explored cells for the explored-cells rows).
    count: u64,
    unit: &'static str,
    vouch: Vec<f64>,
    oracle: Vec<f64>,
    vouch_peak_rss_kb: Option<u64>,
    oracle_peak_rss_kb: Option<u64>,
    /// Peak resident set before the input was read, where the side reports it.
    vouch_start_rss_kb: Option<u64>,
    oracle_start_rss_kb: Option<u64>,
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    match s.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => s[n / 2],
        n => (s[n / 2 - 1] + s[n / 2]) / 2.0,
    }
}

fn minimum(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Runs `vouch navfn bench`.
pub fn run(a: BenchArgs, ctx: &mut Ctx) -> CmdResult {
    if let Some(reps) = a.time_planning {
        return time_planning_side(&a, reps.max(1), ctx);
    }
    let vouch = Side::vouch().map_err(|e| Failure::usage(format_args!("own executable: {e}")))?;
    let oracle = a.oracle.as_deref().map(Side::oracle);
    let mut b = Bench { a: &a, vouch, oracle, rows: Vec::new() };
    if let Some(suite) = &a.suite {
        b.suite_rows(suite, ctx)?;
    }
    if !a.scale.is_empty() {
        b.scale_rows(ctx)?;
    }
    if let Some(path) = &a.plan_map {
        b.planner_rows(path)?;
    }
    let rows = b.rows;
    if let Some(path) = &a.json_out {
        let text = serde_json::to_string_pretty(&rows)
            .map_err(|e| Failure::usage(format_args!("JSON: {e}")))?;
        super::write_file(path, text.as_bytes())?;
    }
    if a.json {
        ctx.out.json(&rows)?;
        return Ok(Exit::Ok);
    }
    print_table(&a, &rows, ctx)
}

struct Bench<'a> {
    a: &'a BenchArgs,
    vouch: Side,
    oracle: Option<Side>,
    rows: Vec<Row>,
}

/// The sides of a pass in the order they run: alternating, so that neither always goes first.
fn pass_order<'s>(vouch: &'s Side, oracle: Option<&'s Side>, pass: usize) -> Vec<&'s Side> {
    match oracle {
        Some(o) if pass % 2 == 1 => vec![o, vouch],
        Some(o) => vec![vouch, o],
        None => vec![vouch],
    }
}

fn bench_failure(msg: String) -> Failure {
    Failure::usage(msg)
}

impl Bench<'_> {
    fn passes(&self) -> usize {
        self.a.passes.max(1)
    }

    /// Planning, one-file-per-process and whole-folder rows for every mode.
    fn suite_rows(&mut self, suite: &Path, ctx: &Ctx) -> Result<(), Failure> {
        let files = find_test_files(suite, "test.txt").map_err(map_failure)?;
        if files.is_empty() {
            return Err(Failure::usage(format_args!("no test.txt below {}", suite.display())));
        }
        let n = files.len();
        for &mode in &self.a.modes {
            let args = contract_args(mode.into());
            let name = RunMode::from(mode).name();
            ctx.note(format_args!("bench: {name}: planning, {n} files"));
            let (row, _) = self.planning(format!("planning {name} ({n} files)"), &args, &files)?;
            self.rows.push(row);
            if self.a.no_process {
                continue;
            }
            if let Some(o) = &self.oracle {
                let same = files
                    .iter()
                    .map(|f| {
                        let v = self.vouch.answer_lines(&args, f)?;
                        Ok(v == o.answer_lines(&args, f)?)
                    })
                    .collect::<Result<Vec<bool>, String>>()
                    .map_err(bench_failure)?;
                let equal = same.iter().filter(|&&s| s).count();
                ctx.note(format_args!(
                    "bench: {name}: CASE/PATH lines identical on {equal} of {n} files"
                ));
            }
            ctx.note(format_args!("bench: {name}: whole processes"));
            let label = format!("process {name}, one file per process ({n})");
            let row = self.process(label, &args, &files)?;
            self.rows.push(row);
            let label = format!("process {name}, whole folder in one process");
            let row = self.process(label, &args, &[suite.to_path_buf()])?;
            self.rows.push(row);
        }
        Ok(())
    }

    /// Planning time per case (µs), interleaved passes; returns the row and vouch's last lines.
    fn planning(
        &self,
        label: String,
        args: &[String],
        files: &[PathBuf],
    ) -> Result<(Row, Vec<TimeLine>), Failure> {
        let (mut v, mut o) = (Vec::new(), Vec::new());
        let (mut v_rss, mut o_rss) = (0, 0);
        let (mut v_start, mut o_start) = (None, None);
        let mut cases = 0;
        let mut last = Vec::new();
        for pass in 0..self.passes() {
            for side in pass_order(&self.vouch, self.oracle.as_ref(), pass) {
                let mut total_ns = 0.0;
                let mut lines = Vec::new();
                for f in files {
                    lines.extend(
                        side.time_planning(args, self.a.repeat.max(1), f).map_err(bench_failure)?,
                    );
                }
                total_ns += lines.iter().map(|t| t.best_ns).sum::<f64>();
                let n: u64 = lines.iter().map(|t| t.cases).sum();
                let rss = lines.iter().map(|t| t.maxrss_kb).max().unwrap_or(0);
                let start = lines.iter().filter_map(|t| t.start_rss_kb).min();
                let per_case_us = total_ns / 1e3 / n.max(1) as f64;
                if side.name == "vouch" {
                    cases = n;
                    v.push(per_case_us);
                    v_rss = v_rss.max(rss);
                    v_start = start;
                    last = lines;
                } else {
                    o.push(per_case_us);
                    o_rss = o_rss.max(rss);
                    o_start = start;
                }
            }
        }
        let has_oracle = self.oracle.is_some();
        let row = Row {
            workload: label,
            count: cases,
            unit: "µs/case",
            vouch: v,
            oracle: o,
            vouch_peak_rss_kb: Some(v_rss),
            oracle_peak_rss_kb: has_oracle.then_some(o_rss),
            vouch_start_rss_kb: v_start,
            oracle_start_rss_kb: o_start,
        };
        Ok((row, last))
    }

    /// Whole-process CPU time (ms) of one process per target, summed, interleaved passes.
    fn process(&self, label: String, args: &[String], targets: &[PathBuf]) -> Result<Row, Failure> {
        let (mut v, mut o) = (Vec::new(), Vec::new());
        for pass in 0..self.passes() {
            for side in pass_order(&self.vouch, self.oracle.as_ref(), pass) {
                let mut total = 0.0;
                for t in targets {
                    total += side.process_cpu(args, t).map_err(bench_failure)?;
                }
                if side.name == "vouch" { &mut v } else { &mut o }.push(total * 1e3);
            }
        }
        Ok(Row {
            workload: label,
            count: targets.len() as u64,
            unit: "ms CPU",
            vouch: v,
            oracle: o,
            vouch_peak_rss_kb: None,
            oracle_peak_rss_kb: None,
            vouch_start_rss_kb: None,
            oracle_start_rss_kb: None,
        })
    }

    /// Random-cost maps: time and peak memory against map size and against explored cells.
    fn scale_rows(&mut self, ctx: &Ctx) -> Result<(), Failure> {
        let mut sides = self.a.scale.clone();
        sides.retain(|&s| s >= 3);
        sides.sort_unstable();
        sides.dedup();
        let explore = sides.iter().copied().filter(|&s| s <= 2000).max();
        let (root, temporary) = match &self.a.scale_dir {
            Some(d) => (d.clone(), false),
            None => {
                (std::env::temp_dir().join(format!("vouch-bench-{}", std::process::id())), true)
            }
        };
        let generated = scale::generate(&root, &sides, explore, self.a.seed).map_err(bench_failure);
        let result = generated.and_then(|(by_size, by_distance)| {
            for &mode in &self.a.modes {
                let args = contract_args(mode.into());
                let name = RunMode::from(mode).name();
                for input in by_size.iter().chain(&by_distance) {
                    ctx.note(format_args!("bench: scale {name} {}", input.label));
                    let files = [input.test.clone()];
                    let label = format!("scale {name} {}", input.label);
                    let (mut row, lines) = self.planning(label, &args, &files)?;
                    // one case per file: µs per case → ms per plan
                    for s in row.vouch.iter_mut().chain(row.oracle.iter_mut()) {
                        *s /= 1e3;
                    }
                    row.unit = "ms/plan";
                    row.count = lines.iter().filter_map(|t| t.explored).sum();
                    self.rows.push(row);
                }
            }
            Ok(())
        });
        if temporary {
            let _ = std::fs::remove_dir_all(&root);
        }
        result
    }

    /// One planner request in this process, Dijkstra and A* (vouch only).
    fn planner_rows(&mut self, path: &Path) -> Result<(), Failure> {
        let (Some(start), Some(goal)) = (self.a.start, self.a.goal) else { return Ok(()) };
        let map = load_ros_map(path, true).map_err(map_failure)?;
        for astar in [false, true] {
            let params = PlannerParams { use_astar: astar, ..PlannerParams::default() };
            let mut planner =
                NavfnPlanner::new(&map.costmap, map.width, map.height, map.world(), params)
                    .map_err(Failure::rejected)?;
            planner.plan_checked(start, goal).map_err(Failure::rejected)?;
            let mut points = 0;
            let mut samples = Vec::new();
            for _ in 0..self.a.repeat_plan.max(1) {
                let c0 = ThreadTime::try_now().ok();
                let t0 = Instant::now();
                points = planner.create_plan(start, goal).navfn_len;
                let wall = t0.elapsed().as_secs_f64();
                let cpu = c0.and_then(|c| c.try_elapsed().ok()).map_or(wall, |d| d.as_secs_f64());
                samples.push(cpu * 1e3);
            }
            let algo = if astar { "A*" } else { "Dijkstra" };
            self.rows.push(Row {
                workload: format!("planner {algo} ({}x{}, {points} points)", map.width, map.height),
                count: 1,
                unit: "ms/plan",
                vouch: samples,
                oracle: Vec::new(),
                vouch_peak_rss_kb: None,
                oracle_peak_rss_kb: None,
                vouch_start_rss_kb: None,
                oracle_start_rss_kb: None,
            });
        }
        Ok(())
    }
}

/// The contract's `--mode`/`--algo` arguments of a sequence.
fn contract_args(mode: RunMode) -> Vec<String> {
    mode.args().iter().map(|s| s.to_string()).collect()
}

fn print_table(a: &BenchArgs, rows: &[Row], ctx: &mut Ctx) -> CmdResult {
    let with_oracle = a.oracle.is_some();
    writeln!(
        ctx.out,
        "vouch navfn bench: every figure measured in this run; {} passes{}; median [minimum]",
        a.passes.max(1),
        match &a.oracle {
            Some(o) => format!(", vouch and the oracle `{o}` alternating on the same inputs"),
            None => String::new(),
        }
    )?;
    writeln!(
        ctx.out,
        "planning: thread CPU time, best of {} in-process repetitions per file; process: user+system CPU",
        a.repeat.max(1)
    )?;
    let head = if with_oracle { "oracle" } else { "" };
    writeln!(
        ctx.out,
        "{:<58} {:>9} {:>8} {:>22} {:>22} {:>6} {:>17}",
        "workload",
        "count",
        "unit",
        "vouch",
        head,
        if with_oracle { "ratio" } else { "" },
        "peak RSS MB"
    )?;
    for r in rows {
        let fig = |s: &[f64]| format!("{:.3} [{:.3}]", median(s), minimum(s));
        let (oracle, ratio) = if with_oracle && !r.oracle.is_empty() {
            (fig(&r.oracle), format!("{:.2}", median(&r.vouch) / median(&r.oracle)))
        } else {
            (String::new(), String::new())
        };
        // peak, and in brackets the growth over the start-up peak (the input's share)
        let mb = |peak: Option<u64>, start: Option<u64>| {
            peak.map(|p| match start {
                Some(s) => {
                    format!("{:.1} ({:.1})", p as f64 / 1024.0, p.saturating_sub(s) as f64 / 1024.0)
                }
                None => format!("{:.1}", p as f64 / 1024.0),
            })
        };
        let rss = match (
            mb(r.vouch_peak_rss_kb, r.vouch_start_rss_kb),
            mb(r.oracle_peak_rss_kb, r.oracle_start_rss_kb),
        ) {
            (Some(v), Some(o)) => format!("{v} / {o}"),
            (Some(v), None) => v,
            _ => String::new(),
        };
        writeln!(
            ctx.out,
            "{:<58} {:>9} {:>8} {:>22} {oracle:>22} {ratio:>6} {rss:>25}",
            r.workload,
            r.count,
            r.unit,
            fig(&r.vouch)
        )?;
    }
    Ok(Exit::Ok)
}

/// vouch's side of the contract's timing extension: one `TIME` line per test file.
fn time_planning_side(a: &BenchArgs, reps: usize, ctx: &mut Ctx) -> CmdResult {
    let mode = run_mode(a.mode, a.algo)?;
    let Some(suite) = &a.suite else { return Err(Failure::usage("missing test file")) };
    let start_rss_kb = side::peak_rss_kb();
    for f in find_test_files(suite, "test.txt").map_err(map_failure)? {
        let file = read_suite_file(&f).map_err(map_failure)?;
        let (mut t, sum_ns) = time_file(&file, mode, reps);
        t.maxrss_kb = side::peak_rss_kb();
        t.start_rss_kb = Some(start_rss_kb);
        writeln!(ctx.out, "{}", side::format_time_line(&t, reps, sum_ns))?;
    }
    Ok(Exit::Ok)
}

/// The cases of a file as cells (parsing stays outside the timed region).
fn case_cells(file: &SuiteFile) -> Vec<(Cell, Cell)> {
    file.cases
        .iter()
        .filter_map(|c| c.cells(file.width, file.height))
        .map(|(a, b)| (Cell::new(a[0], a[1]), Cell::new(b[0], b[1])))
        .collect()
}

/// Best and summed thread CPU time of `reps` repetitions of every case's planning calls, then
/// (untimed, same arrays) the cells each case gives a finite potential.
fn time_file(file: &SuiteFile, mode: RunMode, reps: usize) -> (TimeLine, f64) {
    let cells = case_cells(file);
    let map = MapRef { bytes: &file.map, nx: file.width, ny: file.height, costs: CostInput::Raw };
    let mut runner = CaseRunner::new();
    let (mut best, mut sum, mut found) = (f64::INFINITY, 0.0, 0);
    for _ in 0..reps {
        let c0 = ThreadTime::try_now().ok();
        let t0 = Instant::now();
        let mut n = 0;
        for &(from, to) in &cells {
            let o = runner.run(mode, map, from, to, &mut NoObserver);
            n += o.is_ok_and(|o| o.len > 0) as u64;
        }
        let wall = t0.elapsed().as_secs_f64();
        let cpu = c0.and_then(|c| c.try_elapsed().ok()).map_or(wall, |d| d.as_secs_f64());
        best = f64::min(best, cpu * 1e9);
        sum += cpu * 1e9;
        found = n;
    }
    let explored = cells
        .iter()
        .map(|&(from, to)| {
            let _ = runner.run(mode, map, from, to, &mut NoObserver);
            runner.nav().potential().iter().filter(|&&p| p < POT_HIGH).count() as u64
        })
        .sum();
    let t = TimeLine {
        cases: cells.len() as u64,
        best_ns: best,
        found,
        explored: Some(explored),
        ..TimeLine::default()
    };
    (t, sum)
}
