//! `vouch navfn …`: argument parsing and printing only; the work is in `vouch_navfn`.
//!
//! One scheme of call sequences everywhere: `--mode paper|navfn|planner` and, for the navfn and
//! planner sequences, `--algo dijkstra|astar` (paper mode is always A*). Commands that run
//! cell-level sequences only (`campaign`, `suite diff`, `suite run --trace`) refuse `planner`.

mod bench;
mod campaign;
mod check_bag;
mod costmap;
mod inflation;
mod plan;
mod suite;

use clap::{Args, Subcommand, ValueEnum};
use vouch_navfn::campaign::CampaignError;
use vouch_navfn::core::Algo;
use vouch_navfn::maps::MapError;
use vouch_navfn::suite::{RunMode, SuiteMode};

use crate::contract::{CmdResult, Ctx, Failure};

/// `vouch navfn` subcommands.
#[derive(Subcommand)]
pub enum NavfnCmd {
    /// Plan one path on a ROS map like nav2's NavfnPlanner, and check it
    ///
    /// The map is map_server YAML (naming a PGM/PNG) or an image; the plan's poses go to stdout
    /// (--poses), a file (-o) or the JSON document (--json).
    Plan(plan::PlanArgs),
    /// Check the plans recorded in a rosbag2 bag and replay them bit-exactly
    ///
    /// Every plan of an MCAP or sqlite3 bag is checked on the costmap in force when it was
    /// published, and replayed with vouch's planner.
    CheckBag(check_bag::CheckBagArgs),
    /// Inflate a ROS map as nav2's InflationLayer does, for a robot radius or footprint
    ///
    /// The static layer (map_server + nav2's static layer) inflated with nav2's cost formula,
    /// distance transform and cost table, byte for byte; a PGM or raw bytes.
    Costmap(costmap::CostmapArgs),
    /// Find the smallest inflation radius that keeps the robot's body off the obstacles
    ///
    /// Every radius (at the map's resolution) from --max-radius down; sampled goals, every
    /// start; prints the plan that fails at the largest failing radius.
    Inflation(inflation::InflationArgs),
    /// Suites in the paper's format (test.txt + map.bin): run, generate, compare
    #[command(
        subcommand,
        after_help = after_help!([
            "vouch navfn suite run examples/navfn/suite --mode navfn --check",
            "vouch navfn suite gen --seed 7 --maps 3 -o suite/",
            "vouch navfn suite diff examples/navfn/suite --oracle ./navfn-oracle"
        ])
    )]
    Suite(SuiteCmd),
    /// Time vouch's NavFn on a suite and on planner requests, beside an oracle
    Bench(bench::BenchArgs),
    /// Verification campaign: properties, optimality, metamorphic relations, report
    Campaign(campaign::CampaignArgs),
    /// Campaign reports: merge the reports of sharded runs
    #[command(
        subcommand,
        after_help = after_help!([
            "vouch navfn report merge shard0.json shard1.json -o report.json"
        ])
    )]
    Report(campaign::ReportCmd),
}

/// `vouch navfn suite` subcommands.
#[derive(Subcommand)]
pub enum SuiteCmd {
    /// Run every case of a suite and print the golden lines (MAP, CASE, PATH, WORLD)
    ///
    /// A test file, or every test file below a folder (sorted); MAP / CASE / PATH lines, and
    /// WORLD lines in planner mode.
    Run(suite::SuiteRunArgs),
    /// Generate a suite (the paper's nine categories), the same for the same seed
    Gen(campaign::SuiteGenArgs),
    /// Compare vouch with an external oracle on a suite, case by case
    ///
    /// Black box (the golden lines), and with an oracle that offers the trace extension also the
    /// per-cycle search trace (--white-box).
    Diff(campaign::SuiteDiffArgs),
}

/// Runs one `vouch navfn` subcommand.
pub fn run(cmd: NavfnCmd, ctx: &mut Ctx) -> CmdResult {
    match cmd {
        NavfnCmd::Plan(a) => plan::run(a, ctx),
        NavfnCmd::CheckBag(a) => check_bag::run(a, ctx),
        NavfnCmd::Costmap(a) => costmap::run(a, ctx),
        NavfnCmd::Inflation(a) => inflation::run(a, ctx),
        NavfnCmd::Suite(SuiteCmd::Run(a)) => suite::run(a, ctx),
        NavfnCmd::Suite(SuiteCmd::Gen(a)) => campaign::suite_gen(a, ctx),
        NavfnCmd::Suite(SuiteCmd::Diff(a)) => campaign::suite_diff(a, ctx),
        NavfnCmd::Bench(a) => bench::run(a, ctx),
        NavfnCmd::Campaign(a) => campaign::campaign(a, ctx),
        NavfnCmd::Report(c) => campaign::report(c, ctx),
    }
}

/// `--mode`: which call sequence runs a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// The paper's harness: no swap, A*, path limit 4·nx
    Paper,
    /// The planner's cell-level call sequence (start and goal swapped, atStart Dijkstra or A*)
    Navfn,
    /// World-level NavfnPlanner emulation (test_world.txt, params.txt)
    Planner,
}

impl From<ModeArg> for SuiteMode {
    fn from(m: ModeArg) -> SuiteMode {
        match m {
            ModeArg::Paper => SuiteMode::Paper,
            ModeArg::Navfn => SuiteMode::Navfn,
            ModeArg::Planner => SuiteMode::Planner,
        }
    }
}

/// `--algo`: the propagation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AlgoArg {
    /// Dijkstra with the `atStart` stop (nav2's default)
    Dijkstra,
    /// A*
    Astar,
}

impl From<AlgoArg> for Algo {
    fn from(a: AlgoArg) -> Algo {
        match a {
            AlgoArg::Dijkstra => Algo::Dijkstra,
            AlgoArg::Astar => Algo::Astar,
        }
    }
}

/// `--mode` and `--algo` of the commands that run cell-level sequences only.
#[derive(Args, Clone, Copy, Debug)]
pub struct CellModeArgs {
    /// Call sequence: paper or navfn (planner mode is world-level and not supported here)
    #[arg(long, value_enum, default_value = "paper")]
    mode: ModeArg,
    /// Propagation in navfn mode (paper mode is always A*)
    #[arg(long, value_enum, default_value = "dijkstra")]
    algo: AlgoArg,
}

impl CellModeArgs {
    fn run_mode(self) -> Result<RunMode, Failure> {
        run_mode(self.mode, self.algo)
    }
}

/// The cell-level sequence of `--mode`/`--algo`, or a usage error for planner mode.
fn run_mode(mode: ModeArg, algo: AlgoArg) -> Result<RunMode, Failure> {
    RunMode::new(mode.into(), algo.into()).ok_or_else(|| {
        Failure::usage("this command runs cell-level sequences: --mode paper or navfn")
    })
}

/// `X,Y` as two finite numbers.
fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let (a, b) = s.split_once(',').ok_or_else(|| format!("expected X,Y, found `{s}`"))?;
    let num = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match (num(a), num(b)) {
        (Some(x), Some(y)) => Ok([x, y]),
        _ => Err(format!("expected two numbers X,Y, found `{s}`")),
    }
}

/// A map or suite error: unreadable files are I/O errors (exit 2), the rest rejected input.
fn map_failure(e: MapError) -> Failure {
    if e.is_io() { Failure::Usage(miette::Report::new(e)) } else { Failure::rejected(e) }
}

/// A campaign error: I/O problems exit 2, rejected input 1.
fn campaign_failure(e: CampaignError) -> Failure {
    if e.is_io() { Failure::Usage(miette::Report::new(e)) } else { Failure::rejected(e) }
}

/// Writes `bytes` to `path`.
fn write_file(path: &std::path::Path, bytes: &[u8]) -> Result<(), Failure> {
    std::fs::write(path, bytes).map_err(|e| Failure::io(path, &e))
}

impl From<CampaignError> for Failure {
    fn from(e: CampaignError) -> Failure {
        campaign_failure(e)
    }
}
