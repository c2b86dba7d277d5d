//! `vouch navfn check-bag`: every plan of a rosbag2 recording checked and replayed; a line per
//! plan and a summary, or one JSON document; a picture of every failing plan on request.

use std::path::PathBuf;

use clap::Args;
use vouch_navfn::bagcheck::{
    BagCheckOptions, BagReport, PlanVerdict, Replay, ReplayMode, Topics, check_bag_file,
};
use vouch_navfn::planner::PlannerParams;
use vouch_navfn::rosbag::BagError;

use super::costmap::{BodyArgs, body_shape};
use super::{AlgoArg, write_file};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// `--replay`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ReplayArg {
    /// A plan that differs from vouch's replay fails
    Check,
    /// Replays are reported (equal / different) without failing a plan
    Report,
    /// No comparison
    Off,
}

/// Arguments of `vouch navfn check-bag`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        [
            "vouch navfn check-bag examples/navfn/warehouse_bag --png-dir failing/",
            "vouch navfn check-bag recording_0.mcap --json --replay report"
        ],
        "0 every plan passes, 1 bag rejected (malformed), 2 usage or I/O error, \
         3 a plan fails"
    )
)]
pub struct CheckBagArgs {
    /// A rosbag2 bag: its folder (metadata.yaml and .mcap or .db3 files) or one storage file
    bag: PathBuf,
    /// Print one JSON document (every plan's verdict and the summary)
    #[arg(long)]
    json: bool,
    /// Write a PNG of every failing plan into this folder (plan-N.png)
    #[arg(long, value_name = "DIR")]
    png_dir: Option<PathBuf>,
    /// How replays with vouch's planner count
    #[arg(long, value_enum, default_value = "check")]
    replay: ReplayArg,
    /// Plan topic (nav_msgs/Path)
    #[arg(long, default_value = "/plan", value_name = "TOPIC")]
    plan_topic: String,
    /// map_server's map topic (nav_msgs/OccupancyGrid)
    #[arg(long, default_value = "/map", value_name = "TOPIC")]
    map_topic: String,
    /// Published global costmap (nav_msgs/OccupancyGrid)
    #[arg(long, default_value = "/global_costmap/costmap", value_name = "TOPIC")]
    costmap_topic: String,
    /// Its updates (map_msgs/OccupancyGridUpdate)
    #[arg(long, default_value = "/global_costmap/costmap_updates", value_name = "TOPIC")]
    costmap_updates_topic: String,
    /// Raw global costmap (nav2_msgs/Costmap)
    #[arg(long, default_value = "/global_costmap/costmap_raw", value_name = "TOPIC")]
    costmap_raw_topic: String,
    /// Goal topic (geometry_msgs/PoseStamped)
    #[arg(long, default_value = "/goal_pose", value_name = "TOPIC")]
    goal_topic: String,
    /// Robot pose topic (geometry_msgs/PoseWithCovarianceStamped)
    #[arg(long, default_value = "/amcl_pose", value_name = "TOPIC")]
    robot_pose_topic: String,
    /// Transform topic, used when no robot pose was recorded (tf2_msgs/TFMessage)
    #[arg(long, default_value = "/tf", value_name = "TOPIC")]
    tf_topic: String,
    /// Global frame of the costmap and the plans
    #[arg(long, default_value = "map", value_name = "FRAME")]
    global_frame: String,
    /// The robot's base frame in the transform tree
    #[arg(long, default_value = "base_link", value_name = "FRAME")]
    robot_frame: String,
    /// The planner's propagation (nav2 use_astar)
    #[arg(long, value_enum, default_value = "dijkstra")]
    algo: AlgoArg,
    /// The planner's goal tolerance in metres (nav2 default 0.5)
    #[arg(long, default_value_t = 0.5)]
    tolerance: f64,
    /// Unknown cells are obstacles (nav2 allow_unknown=false)
    #[arg(long)]
    no_unknown: bool,
    /// The planner's max_cycles_factor
    #[arg(long, default_value_t = 4, value_name = "N")]
    max_cycles_factor: usize,
    /// The planner's use_final_approach_orientation
    #[arg(long)]
    use_final_approach_orientation: bool,
    /// The robot's body: every plan's swept body is checked against the static map
    #[command(flatten)]
    body: BodyArgs,
    /// How far beyond the body lethal cells are looked for when reporting the clearance (m)
    #[arg(long, default_value_t = 2.0, value_name = "M")]
    clearance_window: f64,
}

impl CheckBagArgs {
    fn options(&self) -> Result<BagCheckOptions, Failure> {
        if !self.clearance_window.is_finite() || self.clearance_window < 0.0 {
            return Err(Failure::usage(format!(
                "--clearance-window {}: expected ≥ 0",
                self.clearance_window
            )));
        }
        Ok(BagCheckOptions {
            topics: Topics {
                map: self.map_topic.clone(),
                costmap: self.costmap_topic.clone(),
                costmap_updates: self.costmap_updates_topic.clone(),
                costmap_raw: self.costmap_raw_topic.clone(),
                plan: self.plan_topic.clone(),
                goal: self.goal_topic.clone(),
                robot_pose: self.robot_pose_topic.clone(),
                tf: self.tf_topic.clone(),
                global_frame: self.global_frame.clone(),
                robot_frame: self.robot_frame.clone(),
            },
            params: PlannerParams {
                tolerance: self.tolerance,
                use_astar: self.algo == AlgoArg::Astar,
                allow_unknown: !self.no_unknown,
                max_cycles_factor: self.max_cycles_factor,
                use_final_approach_orientation: self.use_final_approach_orientation,
            },
            replay: match self.replay {
                ReplayArg::Check => ReplayMode::Check,
                ReplayArg::Report => ReplayMode::Report,
                ReplayArg::Off => ReplayMode::Off,
            },
            pictures: self.png_dir.is_some(),
            body: body_shape(&self.body)?,
            body_window: self.clearance_window,
        })
    }
}

/// Runs `vouch navfn check-bag`.
pub fn run(a: CheckBagArgs, ctx: &mut Ctx) -> CmdResult {
    let report = check_bag_file(&a.bag, &a.options()?).map_err(bag_failure)?;
    if let Some(dir) = &a.png_dir {
        std::fs::create_dir_all(dir).map_err(|e| Failure::io(dir, &e))?;
        for p in &report.plans {
            if let Some(png) = &p.picture {
                write_file(&dir.join(format!("plan-{}.png", p.index)), png)?;
            }
        }
    }
    if a.json {
        ctx.out.json(&report)?;
    } else {
        print_report(ctx, &report)?;
    }
    let s = &report.summary;
    ctx.note(format_args!(
        "{} plans: {} passed, {} failed; replays: {} equal, {} different, {} without a plan",
        s.plans, s.passed, s.failed, s.replay_equal, s.replay_different, s.replay_no_plan
    ));
    Ok(if report.passed() { Exit::Ok } else { Exit::Findings })
}

fn print_report(ctx: &mut Ctx, report: &BagReport) -> Result<(), Failure> {
    for p in &report.plans {
        writeln!(ctx.out, "{}", plan_line(p, report.replay_mode))?;
        if let Some(b) = &p.body {
            match &b.min {
                Some(m) => writeln!(
                    ctx.out,
                    "  body: min clearance {:.4} m at pose {} (lethal cell {},{})",
                    m.clearance, m.pose, m.cell[0], m.cell[1]
                )?,
                None => writeln!(ctx.out, "  body: min clearance ≥ {} m", b.window)?,
            }
        }
        // one line per kind of violation: the first one, and how many more
        let mut shown: Vec<&str> = Vec::new();
        for v in &p.violations {
            if shown.contains(&v.kind()) {
                continue;
            }
            shown.push(v.kind());
            let more = p.violations.iter().filter(|w| w.kind() == v.kind()).count() - 1;
            if more > 0 {
                writeln!(ctx.out, "  violation: {v} (and {more} more of this kind)")?;
            } else {
                writeln!(ctx.out, "  violation: {v}")?;
            }
        }
    }
    let s = &report.summary;
    writeln!(
        ctx.out,
        "summary: {} plans, {} passed, {} failed; replay {} equal, {} different, {} no plan; {} requests recorded",
        s.plans,
        s.passed,
        s.failed,
        s.replay_equal,
        s.replay_different,
        s.replay_no_plan,
        s.requests_recorded
    )?;
    Ok(())
}

fn plan_line(p: &PlanVerdict, mode: ReplayMode) -> String {
    let verdict = if p.passed(mode) { "ok" } else { "FAILED" };
    let replay = match &p.replay {
        Replay::Equal => "replay equal".to_string(),
        Replay::Different { first_pose, recorded_len, replayed_len, .. } => format!(
            "replay different from pose {first_pose} ({recorded_len} recorded, {replayed_len} replayed poses)"
        ),
        Replay::NoPlan { status } => format!("replay found no plan ({})", status.name()),
        Replay::Skipped => "no replay".to_string(),
    };
    format!(
        "plan {} at {}.{:09} s: {verdict}, {} poses, {replay}, {} violations",
        p.index,
        p.log_time / 1_000_000_000,
        p.log_time % 1_000_000_000,
        p.poses,
        p.violations.len()
    )
}

/// An unreadable bag is an I/O error (exit 2); a malformed one is rejected input (exit 1).
fn bag_failure(e: BagError) -> Failure {
    if e.is_io() { Failure::Usage(miette::Report::new(e)) } else { Failure::rejected(e) }
}
