//! `vouch navfn suite gen`, `suite diff`, `campaign` and `report merge`.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand, ValueEnum};
use vouch_navfn::campaign::diff::{add_oracle, describe, diff_suite, DiffOptions};
use vouch_navfn::campaign::gen::{generate_with_ros, GenOptions};
use vouch_navfn::campaign::names::FindingKind;
use vouch_navfn::campaign::pictures::write_pictures;
use vouch_navfn::campaign::report::{Report, Shard};
use vouch_navfn::campaign::runner::{run_campaign, CampaignOptions, Progress};
use vouch_navfn::campaign::suite_io::write_suite;
use vouch_navfn::campaign::summary::summary_table;
use vouch_navfn::campaign::trace::TraceDetail;

use super::{write_file, CellModeArgs};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch navfn suite gen`.
#[derive(Args)]
#[command(
    after_help = "Example:\n  vouch navfn suite gen --seed 7 --categories circus,spiral --maps 3 -o /tmp/suite"
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
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{s}`: expected MIN..MAX, e.g. 5..30");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    Ok((a.trim().parse().map_err(|_| bad())?, b.trim().parse().map_err(|_| bad())?))
}

/// Runs `vouch navfn suite gen`.
pub fn suite_gen(a: SuiteGenArgs, ctx: &mut Ctx) -> CmdResult {
    let opts = GenOptions {
        seed: a.seed,
        categories: a.categories,
        maps_per_category: a.maps,
        min_size: a.size.0,
        max_size: a.size.1,
        cases_per_map: a.cases,
    };
    let maps = generate_with_ros(&opts, &a.ros_maps, a.ros_cases)?;
    write_suite(&a.output, &maps).map_err(vouch_navfn::campaign::CampaignError::from)?;
    let cases: usize = maps.iter().map(|m| m.cases.len()).sum();
    let (n, dir) = (maps.len(), a.output.display());
    writeln!(ctx.out, "wrote {n} maps, {cases} cases to {dir} (seed {})", a.seed)?;
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
    after_help = "Example:\n  vouch navfn suite diff examples/navfn/suite --oracle ./navfn-oracle --mode navfn --algo astar"
)]
pub struct SuiteDiffArgs {
    /// Suite folder (or one test.txt)
    suite: PathBuf,
    /// Oracle command (run through `sh -c`; the contract's arguments and the test file are appended)
    #[arg(long, value_name = "CMD")]
    oracle: String,
    #[command(flatten)]
    mode: CellModeArgs,
    /// White-box trace compared on every case
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
        ctx.out.write_all(describe(&r).as_bytes())?;
    }
    Ok(if r.different == 0 { Exit::Ok } else { Exit::Findings })
}

/// Arguments of `vouch navfn campaign`.
#[derive(Args)]
#[command(
    after_help = "Example:\n  vouch navfn campaign examples/navfn/suite --mode navfn --algo dijkstra -o report.json --pictures pics/"
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
    /// Write one JSON line per case to this file (outcome, NavFn and optimal cost, excess, turns,
    /// oscillations, failed checks)
    #[arg(long, value_name = "FILE")]
    cases_out: Option<PathBuf>,
    /// Run only shard I of N (cases with global index ≡ I mod N); join with `report merge`
    #[arg(long, value_parser = |s: &str| Shard::parse(s), value_name = "I/N")]
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

/// A progress bar on stderr.
struct Bar(indicatif::ProgressBar);

impl Progress for Bar {
    fn start(&self, cases: u64) {
        self.0.set_length(cases);
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

/// Runs `vouch navfn campaign`.
pub fn campaign(a: CampaignArgs, ctx: &mut Ctx) -> CmdResult {
    if !(a.ratio.is_finite() && a.ratio >= 1.0) {
        return Err(Failure::usage(format_args!("--ratio {} must be a number ≥ 1", a.ratio)));
    }
    let opts = CampaignOptions {
        mode: a.mode.run_mode()?,
        shard: a.shard.unwrap_or(Shard::ALL),
        metamorphic: !a.no_metamorphic,
        optimality: !a.no_optimality,
        suboptimal_ratio: a.ratio,
        per_case: a.cases_out.is_some(),
        ..CampaignOptions::default()
    };
    let bar = progress_bar(ctx);
    let progress: &dyn Progress = match &bar {
        Some(b) => b,
        None => &(),
    };
    let run = run_campaign(&a.suite, &opts, progress);
    if let Some(b) = &bar {
        b.0.finish_and_clear();
    }
    let (mut report, maps) = run?;
    if let Some(cmd) = &a.oracle {
        add_oracle(&mut report, &a.suite, cmd, opts.mode, opts.shard)?;
    }
    if let Some(dir) = &a.pictures {
        write_pictures(dir, &mut report, &maps, opts.mode)?;
    }
    if let Some(p) = &a.cases_out {
        let mut lines = String::new();
        for rec in &report.per_case {
            lines.push_str(&serde_json::to_string(rec).map_err(Failure::usage)?);
            lines.push('\n');
        }
        write_file(p, lines.as_bytes())?;
    }
    if let Some(p) = &a.output {
        write_file(p, json_text(&report)?.as_bytes())?;
    }
    if a.json {
        ctx.out.json(&report)?;
    } else {
        ctx.out.write_all(summary_table(&report).as_bytes())?;
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
    after_help = "Example:\n  vouch navfn report merge shard0.json shard1.json -o report.json"
)]
pub struct ReportMergeArgs {
    /// Merged report to write
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print the merged report on stdout as one JSON document instead of the summary table
    #[arg(long)]
    json: bool,
    /// Shard reports
    #[arg(required = true, value_name = "FILE")]
    inputs: Vec<PathBuf>,
}

fn read_report(p: &Path) -> Result<Report, Failure> {
    let text = std::fs::read_to_string(p).map_err(|e| Failure::io(p, &e))?;
    Report::from_json(p, &text).map_err(Failure::rejected)
}

/// Runs `vouch navfn report …`.
pub fn report(cmd: ReportCmd, ctx: &mut Ctx) -> CmdResult {
    let ReportCmd::Merge(a) = cmd;
    let reports = a.inputs.iter().map(|p| read_report(p)).collect::<Result<Vec<_>, _>>()?;
    let merged = Report::merge(&reports).map_err(Failure::rejected)?;
    write_file(&a.output, json_text(&merged)?.as_bytes())?;
    if !merged.complete() {
        ctx.note("warning: the merged shards do not cover every shard index");
    }
    if a.json {
        ctx.out.json(&merged)?;
    } else {
        ctx.out.write_all(summary_table(&merged).as_bytes())?;
    }
    Ok(if merged.failures() == 0 { Exit::Ok } else { Exit::Findings })
}
