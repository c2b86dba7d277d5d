//! `check-bag`: every plan recorded in a rosbag2 bag checked on the costmap in force when it
//! was recorded, and replayed with vouch's planner on the recorded request (`plan_check.rs`).
//! The driver walks the messages in log-time order and keeps the state (`state.rs`): the latest
//! map, global costmap (as published, with its updates, or raw), goal, robot pose and
//! transforms. The costmap in force is the most exact one received so far: raw, then
//! translated, then the map through the static layer.

mod plan_check;
mod report;
mod state;

use std::collections::BTreeSet;
use std::path::Path;

pub use plan_check::{DETOUR_CELLS, DETOUR_FACTOR, MAX_STEP_CELLS, PlanCheck, check_plan_on};
pub use report::{
    BAG_REPORT_VERSION, BagReport, CostmapUsed, PathViolation, PlanVerdict, Replay, ReplayMode,
    Request, Source, Summary,
};
pub use state::{CostmapKind, CostmapState, TfTree, translate_cost, untranslate};

use crate::costmap::{Body, BodyCheck, BodyReport};
use crate::planner::{PlannerParams, Pose};
use crate::rosbag::msgs::{NavMessage, decode};
use crate::rosbag::{Bag, BagError, read_bag};

/// Topic names and frames (nav2's defaults in `Default`).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Topics {
    /// map_server's map (`nav_msgs/OccupancyGrid`).
    pub map: String,
    /// The global costmap as published (`nav_msgs/OccupancyGrid`).
    pub costmap: String,
    /// Its updates (`map_msgs/OccupancyGridUpdate`).
    pub costmap_updates: String,
    /// The global costmap's bytes (`nav2_msgs/Costmap`).
    pub costmap_raw: String,
    /// Plans (`nav_msgs/Path`).
    pub plan: String,
    /// Goals (`geometry_msgs/PoseStamped`).
    pub goal: String,
    /// Robot pose (`geometry_msgs/PoseWithCovarianceStamped` or `PoseStamped`).
    pub robot_pose: String,
    /// Transforms (`tf2_msgs/TFMessage`), used when no robot pose topic was recorded.
    pub tf: String,
    /// The global frame.
    pub global_frame: String,
    /// The robot's base frame.
    pub robot_frame: String,
}

impl Default for Topics {
    fn default() -> Self {
        Topics {
            map: "/map".into(),
            costmap: "/global_costmap/costmap".into(),
            costmap_updates: "/global_costmap/costmap_updates".into(),
            costmap_raw: "/global_costmap/costmap_raw".into(),
            plan: "/plan".into(),
            goal: "/goal_pose".into(),
            robot_pose: "/amcl_pose".into(),
            tf: "/tf".into(),
            global_frame: "map".into(),
            robot_frame: "base_link".into(),
        }
    }
}

impl Topics {
    fn all(&self) -> BTreeSet<String> {
        [
            &self.map,
            &self.costmap,
            &self.costmap_updates,
            &self.costmap_raw,
            &self.plan,
            &self.goal,
            &self.robot_pose,
            &self.tf,
        ]
        .into_iter()
        .cloned()
        .collect()
    }
}

/// How a bag is checked.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BagCheckOptions {
    /// Topic names and frames.
    pub topics: Topics,
    /// The planner's parameters (as configured on the robot).
    pub params: PlannerParams,
    /// How replays count.
    pub replay: ReplayMode,
    /// Render a picture of every failing plan.
    pub pictures: bool,
    /// The robot's body: when given, each plan's swept body is checked against the static map
    /// (the map topic's grid; the costmap in force when no map was recorded).
    pub body: Option<Body>,
    /// How far beyond the body lethal cells are looked for (metres).
    pub body_window: f64,
}

impl Default for BagCheckOptions {
    fn default() -> Self {
        BagCheckOptions {
            topics: Topics::default(),
            params: PlannerParams::default(),
            replay: ReplayMode::Check,
            pictures: false,
            body: None,
            body_window: 2.0,
        }
    }
}

/// Reads the bag at `path` and checks every plan in it; a bag without plans is an error
/// ([`BagError::NoPlans`]).
pub fn check_bag_file(path: &Path, opts: &BagCheckOptions) -> Result<BagReport, BagError> {
    let bag = read_bag(path, &opts.topics.all())?;
    let report = check_bag(&bag, opts)?;
    // A bag without plans would pass vacuously: refused, so that no check reads as a pass.
    if report.plans.is_empty() {
        return Err(BagError::no_plans(path, &opts.topics.plan));
    }
    Ok(report)
}

/// The state while walking a bag.
#[derive(Default)]
struct Walk {
    map: Option<CostmapState>,
    translated: Option<CostmapState>,
    raw: Option<CostmapState>,
    goal: Option<Pose>,
    robot: Option<Pose>,
    tf: TfTree,
    grids: usize,
}

impl Walk {
    fn in_force(&self) -> Option<&CostmapState> {
        self.raw.as_ref().or(self.translated.as_ref()).or(self.map.as_ref())
    }
}

/// Checks every plan of a bag already read.
pub fn check_bag(bag: &Bag, opts: &BagCheckOptions) -> Result<BagReport, BagError> {
    let t = &opts.topics;
    let mut w = Walk::default();
    let mut plans = Vec::new();
    for m in &bag.messages {
        let msg = decode(m)?;
        let topic = m.topic.as_str();
        match msg {
            NavMessage::Grid(g) => {
                let kind = if topic == t.costmap_raw {
                    CostmapKind::Raw
                } else if topic == t.costmap {
                    CostmapKind::Translated
                } else {
                    CostmapKind::Map
                };
                let state = CostmapState::from_grid(kind, topic, m.log_time, &g);
                w.grids += 1;
                match kind {
                    CostmapKind::Raw => w.raw = Some(state),
                    CostmapKind::Translated => w.translated = Some(state),
                    CostmapKind::Map => w.map = Some(state),
                }
            }
            NavMessage::GridUpdate(u) => {
                w.grids += 1;
                let fits = w.translated.as_mut().is_some_and(|c| c.apply_update(&u, m.log_time));
                if !fits {
                    return Err(BagError::Decode {
                        topic: m.topic.clone(),
                        type_name: m.type_name.clone(),
                        log_time: m.log_time,
                        why: "an update outside the costmap received before it".into(),
                    });
                }
            }
            NavMessage::Pose(frame, p) if frame == t.global_frame || frame.is_empty() => {
                if topic == t.goal {
                    w.goal = Some(state::to_pose(&p));
                } else if topic == t.robot_pose {
                    w.robot = Some(state::to_pose(&p));
                }
            }
            NavMessage::Pose(..) => {}
            NavMessage::Transforms(ts) => w.tf.insert(&ts),
            NavMessage::Path(frame, poses) if topic == t.plan => {
                let poses: Vec<Pose> = poses.iter().map(state::to_pose).collect();
                let mut v = check_one(&w, &frame, &poses, opts);
                v.index = plans.len();
                v.topic = m.topic.clone();
                v.log_time = m.log_time;
                plans.push(v);
            }
            NavMessage::Path(..) => {}
        }
    }
    let summary = summarise(&plans, w.grids, opts.replay);
    Ok(BagReport { version: BAG_REPORT_VERSION, replay_mode: opts.replay, plans, summary })
}

/// One plan against the state at its time.
fn check_one(w: &Walk, frame: &str, poses: &[Pose], opts: &BagCheckOptions) -> PlanVerdict {
    let Some(cm) = w.in_force() else {
        let mut v = PlanVerdict::new(poses.len());
        v.violations.push(PathViolation::NoCostmap);
        return v;
    };
    let robot = w.robot.or_else(|| {
        w.tf.lookup(&opts.topics.global_frame, &opts.topics.robot_frame).map(|p| state::to_pose(&p))
    });
    let body =
        opts.body.as_ref().map(|b| body_report(w.map.as_ref().unwrap_or(cm), b, poses, opts));
    let found: Vec<PathViolation> = body
        .iter()
        .flat_map(|r| &r.violations)
        .map(|c| PathViolation::BodyContact { index: c.pose, cell: c.cell })
        .collect();
    // the body check's cells are the map's; the picture is of the costmap in force
    let marks: Vec<([usize; 2], [u8; 3])> = body
        .iter()
        .flat_map(|r| {
            r.violations
                .iter()
                .map(|c| (c, [255, 0, 255]))
                .chain(r.min.as_ref().map(|m| (m, [0, 230, 230])))
        })
        .filter_map(|(c, colour)| {
            let cell = cm.world.costmap_world_to_map(c.cell_xy, cm.width, cm.height)?;
            Some(([cell.x, cell.y], colour))
        })
        .collect();
    let how = PlanCheck {
        params: opts.params,
        mode: opts.replay,
        picture: opts.pictures,
        found: &found,
        marks: &marks,
    };
    let mut v = check_plan_on(cm, poses, robot, w.goal, how);
    if !frame.is_empty() && !cm.frame_id.is_empty() && frame != cm.frame_id {
        v.violations.insert(
            0,
            PathViolation::WrongFrame { plan: frame.to_string(), costmap: cm.frame_id.clone() },
        );
    }
    v.body = body;
    v.costmap = Some(CostmapUsed {
        topic: cm.topic.clone(),
        kind: cm.kind,
        log_time: cm.log_time,
        size: [cm.width, cm.height],
        resolution: cm.world.resolution,
        exact: cm.exact,
    });
    v
}

/// The body swept along `poses` against the lethal cells of `map`.
fn body_report(
    map: &CostmapState,
    body: &Body,
    poses: &[Pose],
    opts: &BagCheckOptions,
) -> BodyReport {
    let check = BodyCheck {
        costs: &map.costs,
        width: map.width,
        height: map.height,
        world: map.world,
        body: body.clone(),
        window: opts.body_window,
    };
    let xyyaw: Vec<[f64; 3]> =
        poses.iter().map(|p| [p.position[0], p.position[1], p.yaw()]).collect();
    check.check(&xyyaw)
}

fn summarise(plans: &[PlanVerdict], grids: usize, mode: ReplayMode) -> Summary {
    let mut s = Summary { plans: plans.len(), costmaps: grids, ..Summary::default() };
    for p in plans {
        if p.passed(mode) {
            s.passed += 1;
        } else {
            s.failed += 1;
        }
        match p.replay {
            Replay::Equal => s.replay_equal += 1,
            Replay::Different { .. } => s.replay_different += 1,
            Replay::NoPlan { .. } => s.replay_no_plan += 1,
            Replay::Skipped => {}
        }
        if p.request.is_some_and(|r| {
            r.start_source == Source::Recorded && r.goal_source == Source::Recorded
        }) {
            s.requests_recorded += 1;
        }
    }
    s
}
