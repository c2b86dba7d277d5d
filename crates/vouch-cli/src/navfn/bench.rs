//! `vouch navfn bench`: the arguments, a call into `vouch_navfn::bench` (the harness: every
//! figure measured in the run, side by side with `--oracle`), and the table.
//!
//! The hidden `--time-planning R` is vouch's side of the oracle contract's timing extension.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use vouch_navfn::bench::{self, BenchConfig, BenchError, Row, median, minimum};
use vouch_navfn::suite::RunMode;

use super::{AlgoArg, ModeArg, map_failure, parse_pair, run_mode};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

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
            "vouch navfn bench --scale 100,200,500,1000 --modes navfn-dijkstra,navfn-astar",
            "vouch navfn bench --inflation 1000,4000 --inflation-oracle ./my-inflation-layer"
        ],
        "0 measured, 1 suite or map rejected, 2 usage, I/O or oracle error"
    )
)]
pub struct BenchArgs {
    /// Suite to time: a test file, or a folder searched recursively for test.txt (raw NavFn costs)
    #[arg(required_unless_present_any = ["scale", "inflation"])]
    suite: Option<PathBuf>,
    /// External implementation of the oracle contract to measure side by side (a command line,
    /// split into words like a shell would and run without one; it must also answer
    /// `--time-planning R`, see docs/navfn-core.md)
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
    /// Skip the whole-process workloads (suite: one file per process and the whole folder;
    /// scale: one process per map)
    #[arg(long)]
    no_process: bool,
    /// Scale: random-cost maps of these sides (cells, at least 3), e.g. 100,200,500,1000,2000,4000
    #[arg(long, value_delimiter = ',', value_parser = parse_side, value_name = "N,N,…")]
    scale: Vec<usize>,
    /// Scale: where the generated maps are written (default: a folder in the temporary
    /// directory, removed afterwards)
    #[arg(long, value_name = "DIR")]
    scale_dir: Option<PathBuf>,
    /// Scale and inflation: seed of the generated maps
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Inflation: time nav2's inflation layer update on generated static layers of these
    /// sides (cells), e.g. 1000,4000
    #[arg(long, value_delimiter = ',', value_parser = parse_side, value_name = "N,N,…")]
    inflation: Vec<usize>,
    /// Inflation: an external inflation layer to measure side by side (a command line taking
    /// `IN.bin W H RESOLUTION radius R INFLATION_RADIUS K 0|1 0|1 OUT.bin --time R`, see
    /// docs/navfn-body.md)
    #[arg(long, value_name = "CMD", requires = "inflation")]
    inflation_oracle: Option<String>,
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

/// A generated map's side: at least 3 cells (a border ring and an interior), at most 2^15 (a
/// map of 2^30 cells, 1 GiB per byte array).
fn parse_side(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (3..=1 << 15).contains(&n) => Ok(n),
        _ => Err(format!("`{text}`: a side from 3 to 32768 cells")),
    }
}

/// A harness error: a map or suite error as elsewhere, a refused planner request 1, and a
/// side that cannot be started or fails, a bad `--oracle` or an unwritable input 2.
fn bench_failure(e: BenchError) -> Failure {
    match e {
        BenchError::Input(m) => map_failure(m),
        BenchError::Plan(p) => Failure::rejected(p),
        e => Failure::Usage(miette::Report::new(e)),
    }
}

/// Runs `vouch navfn bench`.
pub fn run(a: BenchArgs, ctx: &mut Ctx) -> CmdResult {
    if let Some(reps) = a.time_planning {
        return time_planning_side(&a, reps.max(1), ctx);
    }
    let vouch_exe = std::env::current_exe()
        .map_err(|e| Failure::usage(format_args!("cannot locate the vouch executable: {e}")))?;
    let cfg = BenchConfig {
        suite: a.suite.clone(),
        oracle: a.oracle.clone(),
        vouch_exe,
        modes: a.modes.iter().map(|&m| m.into()).collect(),
        passes: a.passes,
        repeat: a.repeat,
        process: !a.no_process,
        scale: a.scale.clone(),
        scale_dir: a.scale_dir.clone(),
        seed: a.seed,
        inflation: a.inflation.clone(),
        inflation_oracle: a.inflation_oracle.clone(),
    };
    let mut rows = bench::run(&cfg, &mut |line| ctx.note(line)).map_err(bench_failure)?;
    if let (Some(map), Some(start), Some(goal)) = (&a.plan_map, a.start, a.goal) {
        rows.extend(bench::planner_rows(map, start, goal, a.repeat_plan).map_err(bench_failure)?);
    }
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

fn print_table(a: &BenchArgs, rows: &[Row], ctx: &mut Ctx) -> CmdResult {
    let with_oracle = a.oracle.is_some() || a.inflation_oracle.is_some();
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
            r.unit.as_str(),
            fig(&r.vouch)
        )?;
    }
    Ok(Exit::Ok)
}

/// vouch's side of the contract's timing extension: one `TIME` line per test file.
fn time_planning_side(a: &BenchArgs, reps: usize, ctx: &mut Ctx) -> CmdResult {
    let mode = run_mode(a.mode, a.algo)?;
    let Some(suite) = &a.suite else { return Err(Failure::usage("missing test file")) };
    for t in bench::time_planning(suite, mode, reps).map_err(bench_failure)? {
        writeln!(ctx.out, "{}", t.render())?;
    }
    Ok(Exit::Ok)
}
