//! `vouch navfn plan`: one nav2 plan on a ROS map, checked; a summary by default, the poses on
//! request.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use vouch_navfn::checks::{CheckReport, PlanView, check_plan};
use vouch_navfn::maps::load_ros_map;
use vouch_navfn::picture::{PictureInput, save_png};
use vouch_navfn::planner::{
    End, NavfnPlanner, PlanError, PlanStatus, PlannerParams, PlannerPlan, Pose, PosePlan,
};

use super::costmap::{BodyArgs, InflationArgs, body_check, body_marks, inflate, print_body};
use super::{AlgoArg, map_failure, parse_pair, write_file};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch navfn plan`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        [
            "vouch navfn plan examples/navfn/warehouse.yaml --start 1,1 --goal 8.5,6.5 --png plan.png",
            "vouch navfn plan examples/navfn/warehouse.yaml --start 1,1 --goal 8.5,6.5 --json"
        ],
        "0 planned and every plan check holds, 1 map or request rejected or no path, \
         2 usage or I/O error, 3 a plan check failed"
    )
)]
pub struct PlanArgs {
    /// Map: map_server YAML (naming a PGM/PNG), or a PGM/PNG image (resolution 1, origin 0)
    map: PathBuf,
    /// Robot start: X,Y in metres, or column,row with --cells
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    start: [f64; 2],
    /// Robot goal: X,Y in metres, or column,row with --cells
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    goal: [f64; 2],
    /// Start and goal are cell indices (column,row; row 0 = bottom of the image)
    #[arg(long)]
    cells: bool,
    /// Propagation
    #[arg(long, value_enum, default_value = "dijkstra")]
    algo: AlgoArg,
    /// Goal tolerance in metres (nav2 default 0.5)
    #[arg(long, default_value_t = 0.5)]
    tolerance: f64,
    /// Treat unknown cells as obstacles (nav2 allow_unknown=false)
    #[arg(long)]
    no_unknown: bool,
    /// Robot start heading in radians (the orientation of the start pose)
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_name = "RAD")]
    start_yaw: f64,
    /// Goal heading in radians (the orientation of the last pose)
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_name = "RAD")]
    goal_yaw: f64,
    /// Path iteration limit is max(width, height) times this factor (nav2 max_cycles_factor)
    #[arg(long, default_value_t = 4, value_name = "N")]
    max_cycles_factor: usize,
    /// The last pose faces along the final approach instead of the goal heading (nav2
    /// use_final_approach_orientation)
    #[arg(long)]
    use_final_approach_orientation: bool,
    /// Print one JSON document: summary, checks, every pose (x, y, yaw, z, quaternion)
    #[arg(long)]
    json: bool,
    /// Also print every pose after the summary, one `x y yaw` line each (metres, radians)
    #[arg(long)]
    poses: bool,
    /// Write the poses to this file, one `x y yaw` line each (metres, radians)
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Write a picture to this PNG file: map, potential heat map, path
    #[arg(long, value_name = "FILE")]
    png: Option<PathBuf>,
    /// Deprecated, the default now: a plan-check violation is a finding (exit 3)
    #[arg(long, hide = true)]
    checked: bool,
    /// The robot's body: with it, the costmap is inflated as nav2's InflationLayer does and
    /// the body swept along the plan is checked against the static map's lethal cells
    #[command(flatten)]
    body: BodyArgs,
    #[command(flatten)]
    inflation: InflationArgs,
    /// How far beyond the body lethal cells are looked for when reporting the clearance (m)
    #[arg(long, default_value_t = 2.0, value_name = "M")]
    clearance_window: f64,
}

/// Runs `vouch navfn plan`.
pub fn run(a: PlanArgs, ctx: &mut Ctx) -> CmdResult {
    if a.checked {
        ctx.note(
            "warning: --checked is deprecated and will be removed: a failed plan check is a \
             finding (exit 3) by default",
        );
    }
    let map = load_ros_map(&a.map, true).map_err(map_failure)?;
    let params = PlannerParams {
        tolerance: a.tolerance,
        use_astar: a.algo == AlgoArg::Astar,
        allow_unknown: !a.no_unknown,
        max_cycles_factor: a.max_cycles_factor,
        use_final_approach_orientation: a.use_final_approach_orientation,
    };
    let footprint = a.body.footprint()?;
    // with a body, NavFn plans on the inflated costmap, as in nav2
    let costs = match &footprint {
        Some(f) => inflate(&map, Some(f), a.inflation.params())?.0,
        None => map.costmap.clone(),
    };
    let mut planner = NavfnPlanner::new(&costs, map.width, map.height, map.world(), params)
        .map_err(Failure::rejected)?;
    let (start, goal) = if a.cells {
        let s = planner.cell_point(End::Start, a.start).map_err(Failure::rejected)?;
        (s, planner.cell_point(End::Goal, a.goal).map_err(Failure::rejected)?)
    } else {
        (a.start, a.goal)
    };
    let t0 = Instant::now();
    planner.check_end(End::Start, start).map_err(Failure::rejected)?;
    planner.check_end(End::Goal, goal).map_err(Failure::rejected)?;
    let start = Pose::from_xy_yaw(start[0], start[1], a.start_yaw);
    let goal = Pose::from_xy_yaw(goal[0], goal[1], a.goal_yaw);
    let PosePlan { plan, poses } = planner.create_plan_poses(&start, &goal);
    let elapsed_ms = t0.elapsed().as_secs_f64() * 1e3;
    let nav = planner.nav();
    let ran_navfn = plan.navfn_goal.is_some();
    let report = if ran_navfn { check_plan(&PlanView::of(nav)) } else { CheckReport::default() };
    let xyyaw: Vec<[f64; 3]> =
        poses.iter().map(|p| [p.position[0], p.position[1], p.yaw()]).collect();
    let body = footprint
        .as_ref()
        .map(|_| body_check(&map, &a.body, a.clearance_window, &xyyaw))
        .transpose()?;
    if let Some(png) = &a.png {
        if ran_navfn {
            let marks = body.as_ref().map(body_marks).unwrap_or_default();
            let mut pic = PictureInput::of(nav, true);
            pic.marks = &marks;
            // robot start in green, robot goal in blue (NavFn runs them swapped)
            pic.plan.start = nav.goal();
            pic.plan.goal = nav.start();
            save_png(png, &pic).map_err(|e| Failure::io(png, &e))?;
        } else {
            ctx.note(format_args!("no picture: NavFn did not run ({})", plan.status.name()));
        }
    }
    if let Some(path) = &a.output {
        write_file(path, poses_text(&poses).as_bytes())?;
    }
    if a.json {
        let ends = [start.xy(), goal.xy()];
        let mut doc = json_summary(&a, ends, &plan, &poses, &report, elapsed_ms);
        doc["body"] = serde_json::to_value(&body).unwrap_or_default();
        ctx.out.json(&doc)?;
    } else {
        print_summary(ctx, &a, &plan, &poses, &report, elapsed_ms)?;
        if let Some(b) = &body {
            print_body(ctx, b)?;
        }
    }
    let body_ok = body.as_ref().is_none_or(|b| b.is_ok());
    if !report.is_ok() || !body_ok {
        return Ok(Exit::Findings);
    }
    // nav2 answers a start equal to the goal with a one-pose path
    if !matches!(plan.status, PlanStatus::Ok | PlanStatus::StartEqualsGoal) {
        return Err(Failure::rejected(PlanError::NoPlan { status: plan.status }));
    }
    Ok(Exit::Ok)
}

fn poses_text(poses: &[Pose]) -> String {
    let mut s = String::new();
    for p in poses {
        let _ = writeln!(s, "{:.6} {:.6} {:.6}", p.position[0], p.position[1], p.yaw());
    }
    s
}

/// The version of `vouch navfn plan --json`; 2: poses always present, each as the `x y yaw` of
/// the text form plus `z` and the quaternion nav2 returns (`orientation`: x, y, z, w), `status`
/// in snake_case.
const PLAN_JSON_VERSION: u32 = 2;

fn json_summary(
    a: &PlanArgs,
    [start, goal]: [[f64; 2]; 2],
    plan: &PlannerPlan,
    poses: &[Pose],
    report: &CheckReport,
    elapsed_ms: f64,
) -> serde_json::Value {
    let poses: Vec<serde_json::Value> = poses
        .iter()
        .map(|p| {
            let [x, y, z] = p.position;
            serde_json::json!({"x": x, "y": y, "yaw": p.yaw(), "z": z, "orientation": p.orientation})
        })
        .collect();
    serde_json::json!({
        "version": PLAN_JSON_VERSION,
        "status": plan.status,
        "start": start, "goal": goal,
        "start_yaw": a.start_yaw, "goal_yaw": a.goal_yaw,
        "max_cycles_factor": a.max_cycles_factor,
        "use_final_approach_orientation": a.use_final_approach_orientation,
        "algo": if a.algo == AlgoArg::Astar { "astar" } else { "dijkstra" },
        "navfn_start": plan.navfn_start, "navfn_goal": plan.navfn_goal,
        "tolerance_used": plan.tol_used, "best_goal": plan.best,
        "navfn_points": plan.navfn_len, "pose_count": poses.len(),
        "checks": report, "time_ms": (elapsed_ms * 1e3).round() / 1e3,
        "poses": poses,
    })
}

fn print_summary(
    ctx: &mut Ctx,
    a: &PlanArgs,
    plan: &PlannerPlan,
    poses: &[Pose],
    report: &CheckReport,
    elapsed_ms: f64,
) -> Result<(), Failure> {
    let checks =
        if report.is_ok() { "ok".to_string() } else { format!("{} violations", report.count()) };
    writeln!(
        ctx.out,
        "status {}  poses {}  navfn points {}  tolerance used {}  checks {checks}  {elapsed_ms:.3} ms",
        plan.status.name(),
        poses.len(),
        plan.navfn_len,
        if plan.tol_used { "yes" } else { "no" },
    )?;
    for v in &report.violations {
        writeln!(ctx.out, "violation: {v}")?;
    }
    if a.poses {
        ctx.out.write_all(poses_text(poses).as_bytes())?;
    }
    Ok(())
}
