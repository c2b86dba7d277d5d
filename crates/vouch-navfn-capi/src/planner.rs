//! The planner behind a handle: a costmap it owns, the world frame, the parameters and the
//! results of the last plan. Safe Rust; the C entry points in `ffi.rs` call into it.

use vouch_navfn::NoObserver;
use vouch_navfn::checks::{CheckReport, PlanView, check_plan};
use vouch_navfn::core::{Algo, Cell};
use vouch_navfn::maps::{WorldParams, load_ros_map};
use vouch_navfn::planner::{End, NavfnPlanner, PlanStatus, PlannerParams, Pose};
use vouch_navfn::suite::{CaseRunner, CostInput, MapRef};

use crate::{VouchNavfnCostKind, VouchNavfnParams, VouchNavfnPlanStatus, VouchNavfnPose};

/// What a failed call reports: the status and a message.
pub(crate) type Failure = (crate::VouchNavfnStatus, String);

fn invalid(msg: impl std::fmt::Display) -> Failure {
    (crate::VouchNavfnStatus::InvalidArgument, msg.to_string())
}

/// The results of the last plan.
#[derive(Clone, Debug)]
pub(crate) struct LastPlan {
    pub status: Option<PlanStatus>,
    pub poses: Vec<Pose>,
    pub path: Vec<[f32; 2]>,
    pub potential: Vec<f32>,
    pub costs: Vec<u8>,
    pub start: Cell,
    pub goal: Cell,
    pub ran: bool,
}

impl Default for LastPlan {
    fn default() -> Self {
        LastPlan {
            status: None,
            poses: Vec::new(),
            path: Vec::new(),
            potential: Vec::new(),
            costs: Vec::new(),
            start: Cell::new(0, 0),
            goal: Cell::new(0, 0),
            ran: false,
        }
    }
}

/// A planner handle's state.
pub struct VouchNavfnPlanner {
    costs: Vec<u8>,
    kind: VouchNavfnCostKind,
    width: usize,
    height: usize,
    world: WorldParams,
    params: PlannerParams,
    pub(crate) last: LastPlan,
}

impl From<VouchNavfnParams> for PlannerParams {
    fn from(p: VouchNavfnParams) -> Self {
        PlannerParams {
            tolerance: p.tolerance,
            use_astar: p.use_astar,
            allow_unknown: p.allow_unknown,
            max_cycles_factor: p.max_cycles_factor as usize,
            use_final_approach_orientation: p.use_final_approach_orientation,
        }
    }
}

impl From<PlannerParams> for VouchNavfnParams {
    fn from(p: PlannerParams) -> Self {
        VouchNavfnParams {
            tolerance: p.tolerance,
            use_astar: p.use_astar,
            allow_unknown: p.allow_unknown,
            max_cycles_factor: p.max_cycles_factor.min(u32::MAX as usize) as u32,
            use_final_approach_orientation: p.use_final_approach_orientation,
        }
    }
}

pub(crate) fn to_pose(p: &VouchNavfnPose) -> Pose {
    Pose { position: [p.x, p.y, p.z], orientation: [p.qx, p.qy, p.qz, p.qw] }
}

pub(crate) fn from_pose(p: &Pose) -> VouchNavfnPose {
    let ([x, y, z], [qx, qy, qz, qw]) = (p.position, p.orientation);
    VouchNavfnPose { x, y, z, qx, qy, qz, qw }
}

pub(crate) fn plan_status(s: PlanStatus) -> VouchNavfnPlanStatus {
    match s {
        PlanStatus::Ok => VouchNavfnPlanStatus::Found,
        PlanStatus::NoValidPathCouldBeFound => VouchNavfnPlanStatus::NoValidPathCouldBeFound,
        PlanStatus::StartOutsideMapBounds => VouchNavfnPlanStatus::StartOutsideMapBounds,
        PlanStatus::GoalOutsideMapBounds => VouchNavfnPlanStatus::GoalOutsideMapBounds,
        PlanStatus::GoalOccupied => VouchNavfnPlanStatus::GoalOccupied,
        PlanStatus::StartEqualsGoal => VouchNavfnPlanStatus::StartEqualsGoal,
        PlanStatus::UbStartRoundsOutOfMap => VouchNavfnPlanStatus::UbStartRoundsOutOfMap,
        PlanStatus::UbGoalRoundsOutOfMap => VouchNavfnPlanStatus::UbGoalRoundsOutOfMap,
    }
}

impl VouchNavfnPlanner {
    /// A planner over a copy of `costs` (validated like [`NavfnPlanner::new`]).
    pub fn new(
        costs: &[u8],
        width: usize,
        height: usize,
        kind: VouchNavfnCostKind,
        world: WorldParams,
        params: PlannerParams,
    ) -> Result<VouchNavfnPlanner, Failure> {
        // the planner's own checks: sizes, frame, tolerance, cycle factor
        NavfnPlanner::new(costs, width, height, world, params).map_err(invalid)?;
        Ok(VouchNavfnPlanner {
            costs: costs.to_vec(),
            kind,
            width,
            height,
            world,
            params,
            last: LastPlan::default(),
        })
    }

    /// A planner over a map_server map (YAML naming a PGM/PNG, or an image), with nav2's
    /// static layer costs and the map's frame (the resolution as the map message carries it).
    pub fn from_map(
        path: &std::path::Path,
        params: PlannerParams,
    ) -> Result<VouchNavfnPlanner, Failure> {
        let map = load_ros_map(path, true)
            .map_err(|e| (crate::VouchNavfnStatus::MapError, e.located()))?;
        let world = map.world();
        VouchNavfnPlanner::new(
            &map.costmap,
            map.width,
            map.height,
            VouchNavfnCostKind::Ros,
            world,
            params,
        )
    }

    /// Columns and rows.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The world frame.
    pub fn world(&self) -> WorldParams {
        self.world
    }

    /// The costs as given.
    pub fn costs(&self) -> &[u8] {
        &self.costs
    }

    /// Replaces the costmap (same size).
    pub fn set_costs(&mut self, costs: &[u8], kind: VouchNavfnCostKind) -> Result<(), Failure> {
        if costs.len() != self.costs.len() {
            let want = self.costs.len();
            return Err(invalid(format!("{} costs given, the map has {want} cells", costs.len())));
        }
        self.costs.copy_from_slice(costs);
        self.kind = kind;
        self.last = LastPlan::default();
        Ok(())
    }

    /// nav2's `createPlan` in world coordinates (ROS costs only).
    pub fn plan_world(&mut self, start: &Pose, goal: &Pose) -> Result<(), Failure> {
        if self.kind != VouchNavfnCostKind::Ros {
            return Err(invalid("world plans need Costmap2D (ROS) costs; use a cell plan"));
        }
        let mut p =
            NavfnPlanner::new(&self.costs, self.width, self.height, self.world, self.params)
                .map_err(invalid)?;
        let out = p.create_plan_poses(start, goal);
        let nav = p.nav();
        let ran = out.plan.navfn_goal.is_some();
        self.last = LastPlan {
            status: Some(out.plan.status),
            poses: out.poses,
            path: if out.plan.status == PlanStatus::Ok { nav.path().to_vec() } else { Vec::new() },
            potential: if ran { nav.potential().to_vec() } else { Vec::new() },
            costs: if ran { nav.costs().to_vec() } else { Vec::new() },
            start: nav.start(),
            goal: nav.goal(),
            ran,
        };
        Ok(())
    }

    /// A plan between two cells (column, row): with ROS costs nav2's `createPlan` from cell
    /// corner to cell corner; with NavFn costs the planner's cell-level call sequence (swap,
    /// Dijkstra with `atStart` or A*, `calcPath(max(nx, ny)·4)` as in the goldens).
    pub fn plan_cells(&mut self, start: [u32; 2], goal: [u32; 2]) -> Result<(), Failure> {
        if self.kind == VouchNavfnCostKind::Ros {
            let p =
                NavfnPlanner::new(&self.costs, self.width, self.height, self.world, self.params)
                    .map_err(invalid)?;
            let s =
                p.cell_point(End::Start, [start[0] as f64, start[1] as f64]).map_err(invalid)?;
            let g = p.cell_point(End::Goal, [goal[0] as f64, goal[1] as f64]).map_err(invalid)?;
            let q = |xy: [f64; 2]| Pose::from_xy_yaw(xy[0], xy[1], 0.0);
            return self.plan_world(&q(s), &q(g));
        }
        let (nx, ny) = (self.width, self.height);
        let cell = |c: [u32; 2], what: &str| {
            let (x, y) = (c[0] as usize, c[1] as usize);
            if x < nx && y < ny {
                Ok(Cell::new(x, y))
            } else {
                Err(invalid(format!("{what} cell ({x}, {y}) is not a cell of the {nx}x{ny} map")))
            }
        };
        let (from, to) = (cell(start, "start")?, cell(goal, "goal")?);
        let algo = if self.params.use_astar { Algo::Astar } else { Algo::Dijkstra };
        let map = MapRef { bytes: &self.costs, nx, ny, costs: CostInput::Raw };
        let mut runner = CaseRunner::new();
        let out = runner.run_navfn(map, algo, from, to, &mut NoObserver).map_err(invalid)?;
        let nav = runner.nav();
        let found = out.len > 0;
        // the path from the robot's side, as the planner reverses it; world poses at the
        // corner-aligned cell coordinates
        let poses = if found {
            let w = self.world;
            nav.path()
                .iter()
                .rev()
                .map(|p| {
                    let xy = w.navfn_to_world(*p);
                    Pose::from_xy_yaw(xy[0], xy[1], 0.0)
                })
                .collect()
        } else {
            Vec::new()
        };
        self.last = LastPlan {
            status: Some(if found { PlanStatus::Ok } else { PlanStatus::NoValidPathCouldBeFound }),
            poses,
            path: if found { nav.path().to_vec() } else { Vec::new() },
            potential: nav.potential().to_vec(),
            costs: nav.costs().to_vec(),
            start: nav.start(),
            goal: nav.goal(),
            ran: true,
        };
        Ok(())
    }

    /// The run-time checks of the last plan (potential properties and the NavFn path).
    pub fn check(&self) -> Option<CheckReport> {
        let l = &self.last;
        if !l.ran {
            return None;
        }
        let view = PlanView {
            nx: self.width,
            ny: self.height,
            costs: &l.costs,
            potential: &l.potential,
            path: &l.path,
            start: l.start,
            goal: l.goal,
        };
        Some(check_plan(&view))
    }
}
