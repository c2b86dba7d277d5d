//! What `check-bag` reports: per plan its request, costmap, violations and replay outcome;
//! a summary over the bag.

use std::fmt;

use crate::checks::Violation;
use crate::planner::{PlanStatus, Pose};

use super::state::CostmapKind;

/// What to do with the replay.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReplayMode {
    /// Replay, and count a plan that differs from vouch's as failed.
    Check,
    /// Replay and report equal/different, without failing the plan on a difference.
    Report,
    /// No comparison (the replay still runs for the potential the properties need).
    Off,
}

/// Whether an end of the request was recorded or taken from the plan itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// From the goal topic, or the robot pose (`/amcl_pose` or the transform tree).
    Recorded,
    /// From the plan's own first or last pose.
    Inferred,
}

/// The request a plan answered.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Request {
    /// Robot pose.
    pub start: Pose,
    /// Goal pose.
    pub goal: Pose,
    /// Where the start came from.
    pub start_source: Source,
    /// Where the goal came from.
    pub goal_source: Source,
}

/// A property of a recorded plan that does not hold. Cells are in NavFn units
/// (`(w − origin) / resolution`, cell centres whole numbers).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PathViolation {
    /// No costmap had been recorded before the plan.
    NoCostmap,
    /// The plan's frame is not the costmap's.
    WrongFrame {
        /// The plan's frame.
        plan: String,
        /// The costmap's frame.
        costmap: String,
    },
    /// The plan has no pose.
    EmptyPath,
    /// The planner cannot be set up on this costmap.
    Unplannable {
        /// Why.
        why: String,
    },
    /// A pose lies off the map.
    OffMap {
        /// Pose index.
        index: usize,
        /// Its cell coordinates.
        cell: [f64; 2],
    },
    /// `ValidPath`: a pose lies in a lethal (or inscribed) cell.
    PoseInObstacle {
        /// Pose index.
        index: usize,
        /// Its cell coordinates.
        cell: [f64; 2],
    },
    /// The straight step to this pose crosses a lethal cell.
    SegmentThroughObstacle {
        /// Index of the pose the step ends at.
        index: usize,
        /// A point of the step inside the obstacle.
        cell: [f64; 2],
    },
    /// `FinitePotentialPath`: a pose lies where the planner's potential never reached.
    PoseOnUnreachedCell {
        /// Pose index.
        index: usize,
        /// Its cell coordinates.
        cell: [f64; 2],
    },
    /// Two consecutive poses are farther apart than any planner step.
    Jump {
        /// Index of the pose after the gap.
        index: usize,
        /// Length of the step, cells.
        cells: f64,
    },
    /// The potential falls back along the path: the path turns back towards the robot.
    TurnsBack {
        /// First pose where it does.
        index: usize,
        /// How far below the highest potential seen before.
        drop: f32,
    },
    /// The path is much longer than the planner's.
    Detour {
        /// Recorded length, cells.
        recorded_cells: f64,
        /// Replayed length, cells.
        replayed_cells: f64,
    },
    /// The first pose is not the robot's cell.
    StartMismatch {
        /// First pose (x, y).
        first: [f64; 2],
        /// Robot position.
        start: [f64; 2],
    },
    /// The last pose is not the goal (nor, when the goal is unreachable, within tolerance).
    GoalMismatch {
        /// Last pose (x, y).
        last: [f64; 2],
        /// Goal position.
        goal: [f64; 2],
    },
    /// The robot's body, swept from this pose to the next, touches a lethal cell of the static
    /// map (only with a footprint).
    BodyContact {
        /// Pose index.
        index: usize,
        /// The lethal cell (column, row).
        cell: [usize; 2],
    },
    /// `PositionSafe` or `Progress` of the planner's potential on this costmap.
    // Already tagged by the plan check's own `kind`.
    #[serde(untagged)]
    Potential(Violation),
}

impl PathViolation {
    /// The property's name (the JSON variant name).
    pub fn kind(&self) -> &'static str {
        use PathViolation::*;
        match self {
            NoCostmap => "NoCostmap",
            WrongFrame { .. } => "WrongFrame",
            EmptyPath => "EmptyPath",
            Unplannable { .. } => "Unplannable",
            OffMap { .. } => "OffMap",
            PoseInObstacle { .. } => "PoseInObstacle",
            SegmentThroughObstacle { .. } => "SegmentThroughObstacle",
            PoseOnUnreachedCell { .. } => "PoseOnUnreachedCell",
            Jump { .. } => "Jump",
            TurnsBack { .. } => "TurnsBack",
            Detour { .. } => "Detour",
            StartMismatch { .. } => "StartMismatch",
            GoalMismatch { .. } => "GoalMismatch",
            BodyContact { .. } => "BodyContact",
            Potential(_) => "Potential",
        }
    }
}

impl fmt::Display for PathViolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use PathViolation::*;
        match self {
            NoCostmap => write!(f, "no costmap recorded before the plan"),
            WrongFrame { plan, costmap } => {
                write!(f, "plan frame `{plan}` is not the costmap frame `{costmap}`")
            }
            EmptyPath => write!(f, "the plan has no pose"),
            Unplannable { why } => write!(f, "the planner cannot run on this costmap: {why}"),
            OffMap { index, cell } => {
                write!(f, "pose {index} at cell ({:.2}, {:.2}) is off the map", cell[0], cell[1])
            }
            PoseInObstacle { index, cell } => write!(
                f,
                "pose {index} at cell ({:.2}, {:.2}) lies in an obstacle (ValidPath)",
                cell[0], cell[1]
            ),
            SegmentThroughObstacle { index, cell } => write!(
                f,
                "the step to pose {index} crosses an obstacle at cell ({:.2}, {:.2})",
                cell[0], cell[1]
            ),
            PoseOnUnreachedCell { index, cell } => write!(
                f,
                "pose {index} at cell ({:.2}, {:.2}) lies where the potential never reached (FinitePotentialPath)",
                cell[0], cell[1]
            ),
            BodyContact { index, cell } => write!(
                f,
                "the body moving from pose {index} touches the lethal cell ({}, {}) of the static map",
                cell[0], cell[1]
            ),
            Jump { index, cells } => {
                write!(f, "pose {index} is {cells:.2} cells from the previous one (a jump)")
            }
            TurnsBack { index, drop } => write!(
                f,
                "at pose {index} the potential falls {drop:.1} below its highest value: the path turns back (Progress)"
            ),
            Detour { recorded_cells, replayed_cells } => write!(
                f,
                "the path is {recorded_cells:.1} cells long, the planner's {replayed_cells:.1} (a detour)"
            ),
            StartMismatch { first, start } => write!(
                f,
                "the first pose ({}, {}) is not the robot's cell (robot at {}, {})",
                first[0], first[1], start[0], start[1]
            ),
            GoalMismatch { last, goal } => write!(
                f,
                "the last pose ({}, {}) is not the goal ({}, {})",
                last[0], last[1], goal[0], goal[1]
            ),
            Potential(v) => write!(f, "{v}"),
        }
    }
}

/// The replay's verdict.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum Replay {
    /// Every pose bit-identical.
    Equal,
    /// The first pose that differs (or the shorter length).
    Different {
        /// Index of the first differing pose.
        first_pose: usize,
        /// The recorded pose there.
        recorded: Option<Pose>,
        /// vouch's pose there.
        replayed: Option<Pose>,
        /// Recorded pose count.
        recorded_len: usize,
        /// vouch's pose count.
        replayed_len: usize,
    },
    /// vouch's planner found no plan for the request.
    NoPlan {
        /// Its status.
        status: PlanStatus,
    },
    /// Not compared.
    Skipped,
}

/// The costmap a plan was checked on.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CostmapUsed {
    /// Topic.
    pub topic: String,
    /// How its cells were read.
    pub kind: CostmapKind,
    /// Log time of its last message, ns.
    pub log_time: u64,
    /// Columns, rows.
    pub size: [usize; 2],
    /// Metres per cell.
    pub resolution: f64,
    /// Every cell value exactly known (replays are meaningful bit for bit).
    pub exact: bool,
}

/// One plan's verdict.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PlanVerdict {
    /// Index among the plans of the bag (0-based).
    pub index: usize,
    /// Topic.
    pub topic: String,
    /// Log time, ns.
    pub log_time: u64,
    /// Number of poses.
    pub poses: usize,
    /// The costmap in force.
    pub costmap: Option<CostmapUsed>,
    /// The request.
    pub request: Option<Request>,
    /// Properties that do not hold.
    pub violations: Vec<PathViolation>,
    /// The replay.
    pub replay: Replay,
    /// The body check (with a footprint).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub body: Option<crate::costmap::BodyReport>,
    /// A PNG picture of the plan when it failed and pictures were asked for.
    #[serde(skip)]
    pub picture: Option<Vec<u8>>,
}

impl PlanVerdict {
    pub(super) fn new(poses: usize) -> Self {
        PlanVerdict {
            index: 0,
            topic: String::new(),
            log_time: 0,
            poses,
            costmap: None,
            request: None,
            violations: Vec::new(),
            replay: Replay::Skipped,
            body: None,
            picture: None,
        }
    }

    /// Whether the plan passed: no violation, and (in [`ReplayMode::Check`]) a replay that
    /// is not different.
    pub fn passed(&self, mode: ReplayMode) -> bool {
        let replay_ok =
            mode != ReplayMode::Check || matches!(self.replay, Replay::Equal | Replay::Skipped);
        self.violations.is_empty() && replay_ok
    }
}

/// Counts over a bag.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Summary {
    /// Plans checked.
    pub plans: usize,
    /// Plans that passed.
    pub passed: usize,
    /// Plans that failed.
    pub failed: usize,
    /// Replays bit-identical.
    pub replay_equal: usize,
    /// Replays that differ.
    pub replay_different: usize,
    /// Replays without a plan from vouch.
    pub replay_no_plan: usize,
    /// Plans whose request (start and goal) was recorded.
    pub requests_recorded: usize,
    /// Grid messages read (maps, costmaps, updates).
    pub costmaps: usize,
}

/// The version of the report's JSON form; 2: kinds and verdicts in snake_case, violations and
/// replays as objects tagged by `kind` and `verdict`.
pub const BAG_REPORT_VERSION: u32 = 2;

/// The whole bag's report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BagReport {
    /// [`BAG_REPORT_VERSION`].
    pub version: u32,
    /// How replays were judged.
    pub replay_mode: ReplayMode,
    /// Per plan.
    pub plans: Vec<PlanVerdict>,
    /// Counts.
    pub summary: Summary,
}

impl BagReport {
    /// Whether every plan passed.
    pub fn passed(&self) -> bool {
        self.summary.failed == 0
    }
}
