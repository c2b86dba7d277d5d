//! `vouch navfn suite gen`, `suite diff`, `campaign` and `report merge`.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use clap::{Args, Subcommand, ValueEnum};
use vouch_navfn::campaign::CampaignError;
use vouch_navfn::campaign::diff::{DiffOptions, add_oracle, describe, diff_suite};
use vouch_navfn::campaign::generate::{GenOptions, RosImport, write_generated};
use vouch_navfn::campaign::merge::Completeness;
use vouch_navfn::campaign::names::FindingKind;
use vouch_navfn::campaign::pictures::write_pictures;
use vouch_navfn::campaign::report::{CaseRecord, Report};
use vouch_navfn::campaign::runner::{CampaignOptions, CaseSink, Progress, run_campaign};
use vouch_navfn::campaign::shard::{Shard, ShardBy};
use vouch_navfn::campaign::summary::summary_table;
use vouch_navfn::campaign::trace::TraceDetail;

use super::{CellModeArgs, write_file};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch navfn suite gen`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        [
            "vouch navfn suite gen --seed 7 --categories circus,spiral --maps 3 -o suite/",
            "vouch navfn suite gen --seed 7 --maps 1000 --shard 3/8 -o suite/   # shard 3's maps"
        ],
        "0 written, 2 usage or I/O error"
    )
)]
pub struct SuiteGenArgs {
    /// Seed: the same seed always writes the same files
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output folder (`<category>/<map>/{test.txt,map.bin}`)
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    /// Comma-separated subset of: circus,columns,free,obstacle,radial,random,spiral,split,walls
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    categories: Vec<String>,
    /// Maps per category
    #[arg(long, default_value_t = 10)]
    maps: u32,
    /// Map width and height range MIN..MAX, border included (MIN ≥ 5)
    #[arg(long, default_value = "5..30", value_parser = parse_size, value_name = "MIN..MAX")]
    size: (u32, u32),
    /// Cases per map (all ordered pairs when the map has fewer)
    #[arg(long, default_value_t = 500)]
    cases: usize,
    /// Also import this nav2 map (map_server YAML + PGM) into category ROS (repeatable)
    #[arg(long = "ros-map", value_name = "FILE.yaml")]
    ros_maps: Vec<PathBuf>,
    /// Cases per imported ROS map
    #[arg(long, default_value_t = 50)]
    ros_cases: usize,
    /// Write only shard I of N of the maps, or `auto` (Slurm array, Kubernetes Indexed Job)
    ///
    /// The maps of shard I are those a `campaign --shard I/N --shard-by map` runs; `auto` reads
    /// I and N from the job's environment (see `campaign --shard`).
    #[arg(long, value_parser = parse_shard_arg, value_name = "I/N|auto")]
    shard: Option<ShardArg>,
}

/// `--shard`: a fixed `I/N`, or `auto` from the array job's environment.
#[derive(Clone, Copy, Debug)]
pub enum ShardArg {
    /// `I/N`.
    Fixed(u32, u32),
    /// From `SLURM_ARRAY_TASK_ID`/`SLURM_ARRAY_TASK_COUNT` or `JOB_COMPLETION_INDEX`/`VOUCH_SHARD_COUNT`.
    Auto,
}

pub(super) fn parse_shard_arg(s: &str) -> Result<ShardArg, String> {
    if s == "auto" {
        return Ok(ShardArg::Auto);
    }
    let sh = Shard::parse(s, ShardBy::Map).map_err(|e| e.to_string())?;
    Ok(ShardArg::Fixed(sh.index, sh.count))
}

/// The shard of `arg` split by `by` (the whole suite without `--shard`).
pub(super) fn resolve_shard(arg: Option<ShardArg>, by: ShardBy) -> Result<Shard, Failure> {
    let shard = match arg {
        None => Ok(Shard::ALL),
        Some(ShardArg::Fixed(i, n)) => Shard::new(i, n, by),
        Some(ShardArg::Auto) => Shard::from_env(|k| std::env::var(k).ok(), by),
    };
    shard.map_err(|e| Failure::from(CampaignError::from(e)))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{s}`: expected MIN..MAX, e.g. 5..30");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    Ok((a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?))
}

/// Runs `vouch navfn suite gen`.
pub fn suite_gen(a: SuiteGenArgs, ctx: &mut Ctx) -> CmdResult {
    let shard = resolve_shard(a.shard, ShardBy::Map)?;
    let opts = GenOptions {
        seed: a.seed,
        categories: a.categories,
        maps_per_category: a.maps,
        min_size: a.size.0,
        max_size: a.size.1,
        cases_per_map: a.cases,
    };
    let ros = RosImport { maps: a.ros_maps, cases: a.ros_cases };
    let w = write_generated(&a.output, &opts, &ros, shard)?;
    let dir = a.output.display();
    let share = if shard == Shard::ALL {
        String::new()
    } else {
        format!(", shard {} of the suite's {} maps", shard.spec(), w.maps_total)
    };
    writeln!(
        ctx.out,
        "wrote {} maps, {} cases to {dir} (seed {}{share})",
        w.maps, w.cases, a.seed
    )?;
    Ok(Exit::Ok)
}

/// `--white-box`: what is compared besides the CASE and PATH lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum WhiteBoxArg {
    /// Black box only (a mismatch is still traced in detail)
    None,
    /// Buffer lengths and hashes of every cycle
    Hash,
    /// Also the cell lists of every buffer
    Cells,
}

/// Arguments of `vouch navfn suite diff`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        [
            "vouch navfn suite diff examples/navfn/suite --oracle ./navfn-oracle --mode navfn",
            "vouch navfn suite diff examples/navfn/suite --oracle ./black-box --white-box none"
        ],
        "0 every case equal, 1 suite rejected, 2 usage, I/O or oracle error, 3 differences"
    )
)]
pub struct SuiteDiffArgs {
    /// Suite folder (or one test.txt)
    suite: PathBuf,
    /// Oracle command (run through `sh -c`; the contract's arguments and the test file are appended)
    #[arg(long, value_name = "CMD")]
    oracle: String,
    #[command(flatten)]
    mode: CellModeArgs,
    /// Search trace compared on every case (`none` for an oracle without the trace extension)
    #[arg(long, value_enum, default_value = "hash")]
    white_box: WhiteBoxArg,
    /// Print the diff report as one JSON document instead of text
    #[arg(long)]
    json: bool,
    /// Write the diff report as JSON to this file
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Test only: perturb vouch's own side (threshold increment priInc)
    #[arg(long, hide = true)]
    perturb_pri_inc: Option<f32>,
}

/// Runs `vouch navfn suite diff`.
pub fn suite_diff(a: SuiteDiffArgs, ctx: &mut Ctx) -> CmdResult {
    let white_box = match a.white_box {
        WhiteBoxArg::None => None,
        WhiteBoxArg::Hash => Some(TraceDetail::Hash),
        WhiteBoxArg::Cells => Some(TraceDetail::Cells),
    };
    let opts = DiffOptions {
        oracle: a.oracle,
        mode: a.mode.run_mode()?,
        white_box,
        perturb_pri_inc: a.perturb_pri_inc,
    };
    let r = diff_suite(&a.suite, &opts)?;
    if let Some(p) = &a.output {
        write_file(p, json_text(&r)?.as_bytes())?;
    }
    if a.json {
        ctx.out.json(&r)?;
    } else {
        ctx.out.text(&describe(&r))?;
    }
    Ok(if r.different == 0 { Exit::Ok } else { Exit::Findings })
}

/// Arguments of `vouch navfn campaign`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        [
            "vouch navfn campaign examples/navfn/suite -o report.json --pictures pics/",
            "vouch navfn campaign examples/navfn/suite --shard 1/4 -o shard1.json -q",
            "vouch navfn campaign SUITE --shard auto -o shard-$SLURM_ARRAY_TASK_ID.json -q  # Slurm"
        ],
        "0 no failure (findings alone do not fail), 1 suite rejected, 2 usage or I/O error, \
         3 a property or exact relation failed"
    )
)]
pub struct CampaignArgs {
    /// Suite folder (`<category>/<map>/test.txt`)
    suite: PathBuf,
    #[command(flatten)]
    mode: CellModeArgs,
    /// Also diff every case against this oracle command (see `suite diff`)
    #[arg(long, value_name = "CMD")]
    oracle: Option<String>,
    /// Write the JSON report to this file (merge shards with `report merge`)
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Print the JSON report on stdout instead of the summary table
    #[arg(long)]
    json: bool,
    /// Write a PNG per counterexample into this folder
    #[arg(long, value_name = "DIR")]
    pictures: Option<PathBuf>,
    /// Write one JSON line per case to this file, streamed in suite order (outcome, NavFn and
    /// optimal cost, excess, turns, oscillations, failed checks)
    #[arg(long, value_name = "FILE")]
    cases_out: Option<PathBuf>,
    /// Run only shard I of N and join the shards with `report merge`; `auto` takes I and N from
    /// a Slurm array job (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT) or a Kubernetes Indexed
    /// Job (JOB_COMPLETION_INDEX, and VOUCH_SHARD_COUNT for N)
    #[arg(long, value_parser = parse_shard_arg, value_name = "I/N|auto")]
    shard: Option<ShardArg>,
    /// What a shard splits: whole maps (a shard reads only its maps) or the cases of every map
    /// (balanced for suites of a few large maps; every shard reads every test file)
    #[arg(long, value_enum, default_value = "map")]
    shard_by: ShardByArg,
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

/// `--shard-by`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ShardByArg {
    /// Whole maps, by the map's home shard
    Map,
    /// Every map's cases round-robin from its home shard
    Case,
}

impl From<ShardByArg> for ShardBy {
    fn from(a: ShardByArg) -> ShardBy {
        match a {
            ShardByArg::Map => ShardBy::Map,
            ShardByArg::Case => ShardBy::Case,
        }
    }
}

/// A progress bar on stderr.
struct Bar(indicatif::ProgressBar);

impl Progress for Bar {
    fn found(&self, cases: u64) {
        self.0.inc_length(cases);
    }
    fn advance(&self, cases: u64) {
        self.0.inc(cases);
    }
}

fn progress_bar(ctx: &Ctx) -> Option<Bar> {
    if !ctx.progress_allowed() {
        return None;
    }
    let style = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:40}] {human_pos}/{human_len} cases ({rate}, eta {eta})",
    )
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
    .with_key("rate", |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
        let _ = write!(w, "{:.0} cases/s", s.per_sec());
    });
    Some(Bar(indicatif::ProgressBar::new(0).with_style(style)))
}

/// `--cases-out`: one JSON line per record, written as the campaign streams.
struct LinesFile {
    path: PathBuf,
    out: std::io::BufWriter<std::fs::File>,
}

impl CaseSink for LinesFile {
    fn accept(&mut self, record: CaseRecord) -> Result<(), CampaignError> {
        let write_err = |source| CampaignError::Write { path: self.path.clone(), source };
        serde_json::to_writer(&mut self.out, &record).map_err(|e| write_err(e.into()))?;
        self.out.write_all(b"\n").map_err(write_err)
    }
}

fn lines_file(path: &Path) -> Result<LinesFile, Failure> {
    let f = std::fs::File::create(path).map_err(|e| Failure::io(path, &e))?;
    Ok(LinesFile { path: path.to_path_buf(), out: std::io::BufWriter::new(f) })
}

/// Runs `vouch navfn campaign`.
pub fn campaign(a: CampaignArgs, ctx: &mut Ctx) -> CmdResult {
    if !(a.ratio.is_finite() && a.ratio >= 1.0) {
        return Err(Failure::usage(format_args!("--ratio {} must be a number ≥ 1", a.ratio)));
    }
    let opts = CampaignOptions {
        mode: a.mode.run_mode()?,
        shard: resolve_shard(a.shard, a.shard_by.into())?,
        metamorphic: !a.no_metamorphic,
        optimality: !a.no_optimality,
        suboptimal_ratio: a.ratio,
        ..CampaignOptions::default()
    };
    let mut lines = a.cases_out.as_deref().map(lines_file).transpose()?;
    let bar = progress_bar(ctx);
    let progress: &dyn Progress = match &bar {
        Some(b) => b,
        None => &(),
    };
    let sink = lines.as_mut().map(|l| l as &mut dyn CaseSink);
    let run = run_campaign(&a.suite, &opts, progress, sink);
    if let Some(b) = &bar {
        b.0.finish_and_clear();
    }
    let mut report = run?;
    if let Some(l) = &mut lines {
        l.out.flush().map_err(|e| Failure::io(&l.path, &e))?;
    }
    if report.suite.maps.is_empty() {
        ctx.note(format_args!("note: shard {} holds no map of this suite", opts.shard.spec()));
    }
    if let Some(cmd) = &a.oracle {
        add_oracle(&mut report, &a.suite, cmd, opts.mode, opts.shard)?;
    }
    if let Some(dir) = &a.pictures {
        write_pictures(dir, &mut report, &a.suite, opts.mode)?;
    }
    if let Some(p) = &a.output {
        write_file(p, json_text(&report)?.as_bytes())?;
    }
    if a.json {
        ctx.out.json(&report)?;
    } else {
        ctx.out.text(&summary_table(&report))?;
        print_worst(ctx, &report)?;
    }
    Ok(if report.failures() == 0 { Exit::Ok } else { Exit::Findings })
}

fn print_worst(ctx: &mut Ctx, report: &Report) -> Result<(), Failure> {
    let worst = report.findings.iter().filter(|f| f.kind == FindingKind::Suboptimal).take(3);
    let mut first = true;
    for f in worst {
        if std::mem::take(&mut first) {
            writeln!(ctx.out, "worst optimality counterexamples:")?;
        }
        let (c, m, k, xy, d) = (&f.category, &f.map, f.case, f.coords, &f.detail);
        writeln!(ctx.out, "  {c}/{m} case {k} {xy:?}: {d}")?;
    }
    Ok(())
}

fn json_text<T: serde::Serialize>(v: &T) -> Result<String, Failure> {
    serde_json::to_string_pretty(v).map_err(Failure::usage)
}

/// `vouch navfn report` subcommands.
#[derive(Subcommand)]
pub enum ReportCmd {
    /// Join the JSON reports of `campaign --shard I/N` runs into one
    Merge(ReportMergeArgs),
}

/// Arguments of `vouch navfn report merge`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        ["vouch navfn report merge shard0.json shard1.json shard2.json shard3.json -o report.json"],
        "0 merged without failures, 1 reports that do not belong together, \
         2 usage or I/O error, 3 the merged report has failures"
    )
)]
pub struct ReportMergeArgs {
    /// Merged report to write
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print the merged report on stdout as one JSON document instead of the summary table
    #[arg(long)]
    json: bool,
    /// Merge even when shards, maps or cases of the suite are missing (the report says which
    /// shards it holds); without it an incomplete set is refused
    #[arg(long)]
    allow_partial: bool,
    /// Shard reports (any order; merged reports may be merged again)
    #[arg(required = true, value_name = "FILE")]
    inputs: Vec<PathBuf>,
}

fn read_report(p: &Path) -> Result<Report, Failure> {
    Report::read(p).map_err(|e| {
        if e.is_io() { Failure::Usage(miette::Report::new(e)) } else { Failure::rejected(e) }
    })
}

/// Runs `vouch navfn report …`.
pub fn report(cmd: ReportCmd, ctx: &mut Ctx) -> CmdResult {
    let ReportCmd::Merge(a) = cmd;
    let reports = a.inputs.iter().map(|p| read_report(p)).collect::<Result<Vec<_>, _>>()?;
    let completeness =
        if a.allow_partial { Completeness::AllowPartial } else { Completeness::Required };
    let merged = Report::merge(&reports, completeness).map_err(Failure::rejected)?;
    write_file(&a.output, json_text(&merged)?.as_bytes())?;
    if !merged.shards.complete() || merged.suite.content.is_none() {
        let (n, total, count) =
            (merged.suite.maps.len(), merged.suite.maps_total, merged.shards.count);
        let first: Vec<String> =
            merged.shards.missing(8).iter().map(|i| format!("{i}/{count}")).collect();
        ctx.note(format_args!(
            "partial merge: {} shard(s) missing [{}], {n} of the suite's {total} maps",
            merged.shards.missing_count(),
            first.join(", ")
        ));
    }
    if a.json {
        ctx.out.json(&merged)?;
    } else {
        ctx.out.text(&summary_table(&merged))?;
    }
    Ok(if merged.failures() == 0 { Exit::Ok } else { Exit::Findings })
}
