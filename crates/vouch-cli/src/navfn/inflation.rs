//! `vouch navfn inflation`: the smallest inflation radius under which NavFn's plans keep the
//! body off the obstacles (sampled goals, every start), sharded like the campaign; and the
//! merge of shard reports.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::Args;
use vouch_navfn::campaign::shard::ShardBy;
use vouch_navfn::costmap::InflationParams;
use vouch_navfn::guarantee::{SearchConfig, SearchReport, merge, replay_counterexample, search};
use vouch_navfn::maps::load_ros_map;
use vouch_navfn::picture::{PictureInput, save_png};

use super::campaign::{ShardArg, parse_shard_arg, resolve_shard};
use super::costmap::{BodyArgs, body_marks, body_shape, costmap_failure};
use super::{map_failure, write_file};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch navfn inflation`.
#[derive(Args)]
#[command(after_help = after_help!(
    [
        "vouch navfn inflation map.yaml --robot-radius 0.3 --cost-scaling-factor 3 --goals 8",
        "vouch navfn inflation map.yaml --robot-radius 0.3 --shard auto -o part-$SLURM_ARRAY_TASK_ID.json  # Slurm",
        "vouch navfn inflation --merge part-*.json",
        "vouch navfn inflation map.yaml --robot-radius 0.3 --png counterexample.png"
    ],
    "0 a safe radius was found, 1 map or parameter rejected, 2 usage or I/O error, \
     3 no radius up to --max-radius is safe"
))]
pub struct InflationArgs {
    /// Map: map_server YAML (naming a PGM/PNG), or a PGM/PNG image
    #[arg(required_unless_present = "merge")]
    map: Option<PathBuf>,
    #[command(flatten)]
    body: BodyArgs,
    /// cost_scaling_factor of the layer (nav2 default 10.0)
    #[arg(long, default_value_t = 10.0, value_name = "K")]
    cost_scaling_factor: f64,
    /// nav2 inflate_unknown
    #[arg(long)]
    inflate_unknown: bool,
    /// nav2 inflate_around_unknown
    #[arg(long)]
    inflate_around_unknown: bool,
    /// Goals sampled (each: one potential field, every start descended)
    #[arg(long, default_value_t = 8, value_name = "N")]
    goals: usize,
    /// Seed of the goal sampling
    #[arg(long, default_value_t = 1, value_name = "SEED")]
    seed: u64,
    /// Starts: every S-th column and row (1 = every cell)
    #[arg(long, default_value_t = 1, value_name = "S")]
    start_stride: usize,
    /// Largest radius tried in metres (default: four times the body's circumscribed radius)
    #[arg(long, value_name = "M")]
    max_radius: Option<f64>,
    /// Starts and goals: cells where the body clears every obstacle by more than this (metres;
    /// default one cell)
    #[arg(long, value_name = "M")]
    end_clearance: Option<f64>,
    /// Smallest radius tried in metres (with --max-radius the same value: check that one
    /// inflation radius, a body-check campaign over every start of the sampled goals)
    #[arg(long, default_value_t = 0.0, value_name = "M")]
    min_radius: f64,
    /// Run only goals g with g mod N = I, or `auto` (Slurm array, Kubernetes Indexed Job)
    #[arg(long, value_parser = parse_shard_arg, value_name = "I/N|auto")]
    shard: Option<ShardArg>,
    /// Merge shard reports (JSON files written with -o) instead of searching
    #[arg(long, num_args = 1.., value_name = "REPORT", conflicts_with = "map")]
    merge: Vec<PathBuf>,
    /// Write the JSON report to this file
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Print the JSON report
    #[arg(long)]
    json: bool,
    /// Draw the counterexample to this PNG file: the costmap of its radius, the potential, the
    /// plan (start green, goal blue), the contacts (magenta) and the closest lethal cell (cyan)
    #[arg(long, value_name = "FILE", conflicts_with = "merge")]
    png: Option<PathBuf>,
}

/// Runs `vouch navfn inflation`.
pub fn run(a: InflationArgs, ctx: &mut Ctx) -> CmdResult {
    let report = if a.merge.is_empty() { run_search(&a)? } else { merge_files(&a.merge)? };
    let text = serde_json::to_string_pretty(&report).map_err(|e| Failure::usage(e.to_string()))?;
    if let Some(path) = &a.output {
        write_file(path, text.as_bytes())?;
    }
    if let Some(png) = &a.png {
        picture(&a, &report, png, ctx)?;
    }
    if a.json {
        ctx.out.json(&report)?;
    } else {
        ctx.out.write_all(summary(&report).as_bytes())?;
    }
    Ok(if report.smallest_safe_radius.is_some() { Exit::Ok } else { Exit::Findings })
}

/// The counterexample drawn: its plan replayed on the costmap of its radius.
fn picture(a: &InflationArgs, report: &SearchReport, png: &Path, ctx: &mut Ctx) -> CmdResult {
    let Some(map_path) = &a.map else { return Err(Failure::usage("no map")) };
    let map = load_ros_map(map_path, true).map_err(map_failure)?;
    let body = body_shape(&a.body)?.ok_or_else(|| Failure::usage("no body"))?;
    let params = layer_params(a);
    match replay_counterexample(&map, report, params, &body).map_err(costmap_failure)? {
        Some((nav, body_report)) => {
            let marks = body_marks(&body_report);
            let mut pic = PictureInput::of(&nav, true);
            pic.marks = &marks;
            save_png(png, &pic).map_err(|e| Failure::io(png, &e))?;
        }
        None => ctx.note("no picture: no radius failed, so there is no counterexample"),
    }
    Ok(Exit::Ok)
}

/// The layer's parameters from the arguments (the radius is the search's to set).
fn layer_params(a: &InflationArgs) -> InflationParams {
    super::costmap::InflationArgs {
        inflation_radius: 0.0,
        cost_scaling_factor: a.cost_scaling_factor,
        inflate_unknown: a.inflate_unknown,
        inflate_around_unknown: a.inflate_around_unknown,
    }
    .params()
}

fn run_search(a: &InflationArgs) -> Result<SearchReport, Failure> {
    let Some(map_path) = &a.map else { return Err(Failure::usage("no map")) };
    let map = load_ros_map(map_path, true).map_err(map_failure)?;
    let footprint =
        a.body.footprint()?.ok_or_else(|| Failure::usage("give --robot-radius or --footprint"))?;
    let body = body_shape(&a.body)?.ok_or_else(|| Failure::usage("no body"))?;
    let max_radius = a.max_radius.unwrap_or(4.0 * body.circumscribed());
    let radii_ok = max_radius.is_finite() && a.min_radius.is_finite() && a.min_radius >= 0.0;
    if !radii_ok || a.min_radius > max_radius || a.goals == 0 {
        return Err(Failure::usage("need 0 ≤ --min-radius ≤ --max-radius and --goals ≥ 1"));
    }
    let params = layer_params(a);
    let cfg = SearchConfig {
        footprint,
        body,
        params,
        goals: a.goals,
        seed: a.seed,
        start_stride: a.start_stride,
        max_radius,
        min_radius: a.min_radius,
        shard: resolve_shard(a.shard, ShardBy::Map)?,
        end_clearance: a.end_clearance,
    };
    search(&map, &cfg).map_err(costmap_failure)
}

fn merge_files(paths: &[PathBuf]) -> Result<SearchReport, Failure> {
    let mut reports = Vec::new();
    for p in paths {
        let text = std::fs::read_to_string(p).map_err(|e| Failure::io(p, &e))?;
        let r: SearchReport = serde_json::from_str(&text).map_err(|e| {
            Failure::usage(format!("{}: not an inflation report: {e}", p.display()))
        })?;
        reports.push(r);
    }
    let first = reports.first().cloned();
    for r in &reports {
        let same = first.as_ref().is_some_and(|f| {
            (f.resolution, f.inscribed_radius, f.cost_scaling_factor, f.goals, f.seed)
                == (r.resolution, r.inscribed_radius, r.cost_scaling_factor, r.goals, r.seed)
                && (f.start_stride, f.max_radius, f.min_radius, f.end_clearance)
                    == (r.start_stride, r.max_radius, r.min_radius, r.end_clearance)
        });
        if !same {
            return Err(Failure::usage("the reports are of different searches"));
        }
    }
    merge(reports).ok_or_else(|| Failure::usage("no report to merge"))
}

fn summary(r: &SearchReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "inscribed radius {:.4} m, cost_scaling_factor {}, {} goals (seed {}), starts every {} cell(s), end clearance {:.3} m, radii {:.3} … {:.3} m by {:.3} m; {} paths checked; shards {}",
        r.inscribed_radius,
        r.cost_scaling_factor,
        r.goals,
        r.seed,
        r.start_stride,
        r.end_clearance,
        r.min_radius,
        r.max_radius,
        r.resolution,
        r.paths,
        r.shards.join(",")
    );
    match r.smallest_safe_radius {
        Some(v) if r.counterexample.is_none() && v > 0.0 => {
            let _ = writeln!(
                s,
                "every inflation_radius from {v:.4} m to {:.4} m is safe",
                r.max_radius
            );
        }
        Some(v) => {
            let _ = writeln!(s, "smallest safe inflation_radius: {v:.4} m");
        }
        None => {
            let _ = writeln!(s, "no safe inflation_radius up to {:.4} m", r.max_radius);
        }
    }
    if let Some(c) = &r.counterexample {
        let _ = writeln!(
            s,
            "counterexample at inflation_radius {:.4} m: goal #{} cell {},{} from start cell {},{}: pose {} touches lethal cell {},{}",
            c.inflation_radius,
            c.goal_index,
            c.goal[0],
            c.goal[1],
            c.start[0],
            c.start[1],
            c.contact.pose,
            c.contact.cell[0],
            c.contact.cell[1]
        );
        for p in &c.poses {
            let _ = writeln!(s, "{:.6} {:.6} {:.6}", p[0], p[1], p[2]);
        }
    }
    s
}
