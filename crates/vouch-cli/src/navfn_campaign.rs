//! `vouch navfn` subcommands of the verification campaign (navfn-campaign, issue 7):
//! `suite gen`, `suite diff`, `campaign`, `report merge`, and the `--trace`/`--pot` flags of
//! `suite run`. Argument parsing only; the logic is `vouch_navfn::campaign::commands`.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand, ValueEnum};
use vouch_navfn::campaign::commands::{self, CmdError};
use vouch_navfn::campaign::diff::DiffOptions;
use vouch_navfn::campaign::exec::RunMode;
use vouch_navfn::campaign::gen::GenOptions;
use vouch_navfn::campaign::oracle::EmitOptions;
use vouch_navfn::campaign::report::Shard;
use vouch_navfn::campaign::runner::CampaignOptions;
use vouch_navfn::campaign::trace::TraceDetail;

fn fail(e: CmdError) -> ExitCode {
    eprintln!("error: {e}");
    ExitCode::from(e.exit_code())
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CampaignMode {
    /// The paper's harness (A*, no swap, calcPath(4·nx))
    Paper,
    /// The planner's cell-level sequence with atStart Dijkstra
    NavfnDijkstra,
    /// The planner's cell-level sequence with A*
    NavfnAstar,
}

impl From<CampaignMode> for RunMode {
    fn from(m: CampaignMode) -> RunMode {
        match m {
            CampaignMode::Paper => RunMode::Paper,
            CampaignMode::NavfnDijkstra => RunMode::NavfnDijkstra,
            CampaignMode::NavfnAstar => RunMode::NavfnAstar,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DetailArg {
    /// Buffer length and FNV-1a hash per cycle
    Hash,
    /// Also the ordered cell list of every buffer
    Cells,
}

impl From<DetailArg> for TraceDetail {
    fn from(d: DetailArg) -> TraceDetail {
        match d {
            DetailArg::Hash => TraceDetail::Hash,
            DetailArg::Cells => TraceDetail::Cells,
        }
    }
}

/// Flags `suite run` takes for the oracle contract (flattened into its arguments).
#[derive(Args, Debug, Clone, Default)]
pub struct TraceArgs {
    /// Per-cycle white-box trace lines (CYCLE/PROPEND) before each CASE line (paper/navfn modes)
    #[arg(long, value_enum)]
    pub trace: Option<DetailArg>,
    /// A POT line with the whole final potential (float32 bits) before each CASE line
    #[arg(long)]
    pub pot: bool,
    /// Test only: run with a different threshold increment priInc (default 100)
    #[arg(long, hide = true)]
    pub perturb_pri_inc: Option<f32>,
}

impl TraceArgs {
    pub fn active(&self) -> bool {
        self.trace.is_some() || self.pot || self.perturb_pri_inc.is_some()
    }
}

/// `suite run` with `--trace`/`--pot`/`--perturb-pri-inc`: `navfn_mode` is `None` for paper
/// mode, else `Some(use_astar)`.
pub fn suite_run_traced(
    path: &std::path::Path,
    navfn_mode: Option<bool>,
    t: &TraceArgs,
) -> ExitCode {
    let mode = match navfn_mode {
        None => RunMode::Paper,
        Some(false) => RunMode::NavfnDijkstra,
        Some(true) => RunMode::NavfnAstar,
    };
    let opts = EmitOptions {
        mode,
        trace: t.trace.map(Into::into),
        pot: t.pot,
        perturb_pri_inc: t.perturb_pri_inc,
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    match commands::suite_run_traced(path, &opts, &mut out) {
        Ok(n) => {
            let _ = out.flush();
            eprintln!("{n} cases");
            ExitCode::SUCCESS
        }
        Err(e) => fail(e),
    }
}

#[derive(Args)]
pub struct SuiteGenArgs {
    /// Seed: the same seed always writes the same files
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output folder (`<category>/<map>/{test.txt,map.bin}`)
    #[arg(long)]
    out: PathBuf,
    /// Comma-separated subset of: circus,columns,free,obstacle,radial,random,spiral,split,walls
    #[arg(long, value_delimiter = ',')]
    categories: Vec<String>,
    /// Maps per category
    #[arg(long, default_value_t = 10)]
    maps: u32,
    /// Map width and height range MIN..MAX, border included (MIN ≥ 5)
    #[arg(long, default_value = "5..30")]
    size: String,
    /// Cases per map (all ordered pairs when the map has fewer)
    #[arg(long, default_value_t = 500)]
    cases: usize,
    /// Also import these nav2 maps (map_server YAML + PGM) into category ROS
    #[arg(long = "ros-map")]
    ros_maps: Vec<PathBuf>,
    /// Cases per imported ROS map
    #[arg(long, default_value_t = 50)]
    ros_cases: usize,
}

fn parse_size(s: &str) -> Result<(u32, u32), CmdError> {
    let bad = || CmdError::Usage(format!("--size `{s}`: expected MIN..MAX, e.g. 5..30"));
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    Ok((a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?))
}

pub fn suite_gen(a: SuiteGenArgs) -> ExitCode {
    let (min_size, max_size) = match parse_size(&a.size) {
        Ok(v) => v,
        Err(e) => return fail(e),
    };
    let opts = GenOptions {
        seed: a.seed,
        categories: a.categories,
        maps_per_category: a.maps,
        min_size,
        max_size,
        cases_per_map: a.cases,
    };
    match commands::suite_gen(&opts, &a.out, &a.ros_maps, a.ros_cases) {
        Ok(t) => {
            print!("{t}");
            ExitCode::SUCCESS
        }
        Err(e) => fail(e),
    }
}

#[derive(Args)]
pub struct SuiteDiffArgs {
    /// Suite folder (or one test.txt)
    suite: PathBuf,
    /// Oracle command (run through `sh -c`; the contract's arguments and the test file are appended)
    #[arg(long)]
    oracle: String,
    #[arg(long, value_enum, default_value = "paper")]
    mode: CampaignMode,
    /// White-box trace compared on every case (`none` = black box; mismatches are always traced)
    #[arg(long, default_value = "hash", value_parser = ["none", "hash", "cells"])]
    white_box: String,
    /// Write the diff report as JSON
    #[arg(long)]
    json: Option<PathBuf>,
    /// Test only: perturb vouch's own side (threshold increment priInc)
    #[arg(long, hide = true)]
    perturb_pri_inc: Option<f32>,
}

pub fn suite_diff(a: SuiteDiffArgs) -> ExitCode {
    let white_box = match a.white_box.as_str() {
        "none" => None,
        "cells" => Some(TraceDetail::Cells),
        _ => Some(TraceDetail::Hash),
    };
    let opts = DiffOptions {
        oracle: a.oracle,
        mode: a.mode.into(),
        white_box,
        perturb_pri_inc: a.perturb_pri_inc,
    };
    match commands::suite_diff(&a.suite, &opts, a.json.as_deref()) {
        Ok((text, same)) => {
            print!("{text}");
            if same {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(3)
            }
        }
        Err(e) => fail(e),
    }
}

#[derive(Args)]
pub struct CampaignArgs {
    /// Suite folder (`<category>/<map>/test.txt`)
    suite: PathBuf,
    #[arg(long, value_enum, default_value = "paper")]
    mode: CampaignMode,
    /// Also diff every case against this oracle command (see `suite diff`)
    #[arg(long)]
    oracle: Option<String>,
    /// Write the JSON report here
    #[arg(long)]
    report: Option<PathBuf>,
    /// Write a PNG per counterexample into this folder
    #[arg(long)]
    pictures: Option<PathBuf>,
    /// Write one JSON line per case (outcome, NavFn and optimal cost, excess, turns, oscillations)
    #[arg(long)]
    cases_out: Option<PathBuf>,
    /// Run only shard I of N (cases with global index ≡ I mod N); join with `report merge`
    #[arg(long, value_parser = |s: &str| Shard::parse(s))]
    shard: Option<Shard>,
    /// Skip the metamorphic transforms
    #[arg(long)]
    no_metamorphic: bool,
    /// Skip the optimality analysis
    #[arg(long)]
    no_optimality: bool,
    /// A path costing more than RATIO × the optimum is an optimality counterexample
    #[arg(long, default_value_t = 1.10)]
    ratio: f64,
}

pub fn campaign(a: CampaignArgs) -> ExitCode {
    let opts = CampaignOptions {
        mode: a.mode.into(),
        shard: a.shard.unwrap_or(Shard::ALL),
        metamorphic: !a.no_metamorphic,
        optimality: !a.no_optimality,
        suboptimal_ratio: a.ratio,
        progress: std::io::IsTerminal::is_terminal(&std::io::stderr()),
        ..CampaignOptions::default()
    };
    match commands::campaign(
        &a.suite,
        &opts,
        a.oracle.as_deref(),
        a.report.as_deref(),
        a.pictures.as_deref(),
        a.cases_out.as_deref(),
    ) {
        Ok((text, report)) => {
            print!("{text}");
            if report.failures() == 0 {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(3)
            }
        }
        Err(e) => fail(e),
    }
}

#[derive(Subcommand)]
pub enum ReportCmd {
    /// Join the JSON reports of `campaign --shard I/N` runs into one
    Merge(ReportMergeArgs),
}

#[derive(Args)]
pub struct ReportMergeArgs {
    /// Merged report to write
    #[arg(long)]
    out: PathBuf,
    /// Shard reports
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
}

pub fn report(cmd: ReportCmd) -> ExitCode {
    match cmd {
        ReportCmd::Merge(a) => match commands::report_merge(&a.out, &a.inputs) {
            Ok((text, r)) => {
                print!("{text}");
                if r.failures() == 0 {
                    ExitCode::SUCCESS
                } else {
                    ExitCode::from(3)
                }
            }
            Err(e) => fail(e),
        },
    }
}
