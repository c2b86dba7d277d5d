//! The nav2 `NavfnPlanner` layer around the core (SEMANTICS.md §8): world↔map conversions,
//! the robot-cell clearing, ROS cost conversion, the start/goal swap, the goal tolerance
//! search, path reversal to world poses and `smoothApproachToGoal`.

mod pose;
mod validate;

pub use pose::{IDENTITY, Pose, PosePlan, orientation_around_z};

pub use validate::{End, MAX_TOLERANCE_POINTS, PlanError};

use crate::core::{
    Cell, FREE_SPACE_ROS, NavFn, NoObserver, POT_HIGH, SearchObserver, ros_to_navfn_cost,
};
pub use crate::maps::WorldParams;

/// Planner parameters (nav2 defaults in `Default`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PlannerParams {
    /// Goal tolerance in metres (default 0.5).
    pub tolerance: f64,
    /// A* instead of Dijkstra (default false).
    pub use_astar: bool,
    /// Unknown cells (ROS 255) are traversable (default true).
    pub allow_unknown: bool,
    /// Path iteration limit is `max(nx, ny) * max_cycles_factor` (default 4).
    pub max_cycles_factor: usize,
    /// The last pose faces along the final approach instead of the goal's orientation
    /// (default false); affects orientations only.
    pub use_final_approach_orientation: bool,
}

impl Default for PlannerParams {
    fn default() -> Self {
        PlannerParams {
            tolerance: 0.5,
            use_astar: false,
            allow_unknown: true,
            max_cycles_factor: 4,
            use_final_approach_orientation: false,
        }
    }
}

/// Outcome of `createPlan`, named like nav2's exceptions; the `Ub*` statuses mark inputs on
/// which the real planner has undefined behaviour (a point rounding to index `size`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PlanStatus {
    /// A path was found.
    Ok,
    /// NavFn found no path (also after the tolerance search).
    NoValidPathCouldBeFound,
    /// The start is outside the costmap (truncation rule).
    StartOutsideMapBounds,
    /// The goal is outside the costmap (truncation rule).
    GoalOutsideMapBounds,
    /// The goal cell is lethal and the tolerance is 0.
    GoalOccupied,
    /// Start and goal poses are equal.
    StartEqualsGoal,
    /// The start rounds to index `size` (undefined behaviour in nav2).
    UbStartRoundsOutOfMap,
    /// The goal rounds to index `size` (undefined behaviour in nav2).
    UbGoalRoundsOutOfMap,
}

impl PlanStatus {
    /// The spelling of the golden files.
    pub fn name(self) -> &'static str {
        match self {
            PlanStatus::Ok => "OK",
            PlanStatus::NoValidPathCouldBeFound => "NoValidPathCouldBeFound",
            PlanStatus::StartOutsideMapBounds => "StartOutsideMapBounds",
            PlanStatus::GoalOutsideMapBounds => "GoalOutsideMapBounds",
            PlanStatus::GoalOccupied => "GoalOccupied",
            PlanStatus::StartEqualsGoal => "StartEqualsGoal",
            PlanStatus::UbStartRoundsOutOfMap => "UB_StartRoundsOutOfMap",
            PlanStatus::UbGoalRoundsOutOfMap => "UB_GoalRoundsOutOfMap",
        }
    }
}

/// Everything `createPlan` produced, plus the NavFn-level facts the golden lines print.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PlannerPlan {
    pub status: PlanStatus,
    /// NavFn start at the end (the cell path extraction used), if NavFn ran.
    pub navfn_start: Option<Cell>,
    /// NavFn goal (the robot start cell), if NavFn ran.
    pub navfn_goal: Option<Cell>,
    /// True when the goal cell was unreached and the tolerance search ran.
    pub tol_used: bool,
    /// The goal point actually planned to (the robot goal when no better point was found).
    pub best: Option<[f64; 2]>,
    /// NavFn path length (0 unless `status == Ok`).
    pub navfn_len: usize,
    /// A* only: `last_path_cost_`.
    pub last_path_cost: Option<f32>,
    /// Final world poses, robot start to goal.
    pub world: Vec<[f64; 2]>,
}

impl PlannerPlan {
    fn rejected(status: PlanStatus) -> Self {
        PlannerPlan {
            status,
            navfn_start: None,
            navfn_goal: None,
            tol_used: false,
            best: None,
            navfn_len: 0,
            last_path_cost: None,
            world: Vec::new(),
        }
    }
}

/// A nav2 `NavfnPlanner` over one ROS costmap (Costmap2D byte values, row 0 = bottom).
///
/// The costmap is borrowed and never written: nav2's `clearRobotCell` (the robot cell becomes
/// free space in the shared costmap) is applied to NavFn's own cost array after the conversion,
/// which gives the same costs without copying the map. Every plan therefore starts from the
/// caller's map, as the goldens do.
pub struct NavfnPlanner<'m> {
    costmap: &'m [u8],
    nx: usize,
    ny: usize,
    world: WorldParams,
    params: PlannerParams,
    nav: NavFn,
}

impl<'m> NavfnPlanner<'m> {
    /// A planner over `costmap` (`nx`×`ny` Costmap2D values). Rejects sizes NavFn cannot hold,
    /// a cost array of the wrong length, an unusable world frame, and parameters whose
    /// tolerance search would not finish in reasonable time ([`MAX_TOLERANCE_POINTS`]).
    pub fn new(
        costmap: &'m [u8],
        nx: usize,
        ny: usize,
        world: WorldParams,
        params: PlannerParams,
    ) -> Result<Self, PlanError> {
        validate::check_setup(costmap.len(), nx, ny, world, params)?;
        let nav = NavFn::new(nx, ny)?;
        Ok(NavfnPlanner { costmap, nx, ny, world, params, nav })
    }

    /// The NavFn of the last plan (potential, costs, path).
    pub fn nav(&self) -> &NavFn {
        &self.nav
    }
    /// The costmap planned on.
    pub fn costmap(&self) -> &[u8] {
        self.costmap
    }
    /// The world frame.
    pub fn world(&self) -> WorldParams {
        self.world
    }
    /// The planner parameters.
    pub fn params(&self) -> PlannerParams {
        self.params
    }
    /// Columns and rows.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// `createPlan(start, goal)` in world coordinates.
    pub fn create_plan(&mut self, start: [f64; 2], goal: [f64; 2]) -> PlannerPlan {
        self.create_plan_observed(start, goal, &mut NoObserver)
    }

    /// [`NavfnPlanner::create_plan`] with a search observer.
    pub fn create_plan_observed<O: SearchObserver>(
        &mut self,
        start: [f64; 2],
        goal: [f64; 2],
        obs: &mut O,
    ) -> PlannerPlan {
        let w = self.world;
        if w.costmap_world_to_map(start, self.nx, self.ny).is_none() {
            return PlannerPlan::rejected(PlanStatus::StartOutsideMapBounds);
        }
        let Some(goal_cell) = w.costmap_world_to_map(goal, self.nx, self.ny) else {
            return PlannerPlan::rejected(PlanStatus::GoalOutsideMapBounds);
        };
        if self.params.tolerance == 0.0
            && self.costmap[goal_cell.y * self.nx + goal_cell.x] == crate::core::COST_OBS
        {
            return PlannerPlan::rejected(PlanStatus::GoalOccupied);
        }
        if start[0] == goal[0] && start[1] == goal[1] {
            let mut p = PlannerPlan::rejected(PlanStatus::StartEqualsGoal);
            p.world.push(start);
            return p;
        }
        self.make_plan(start, goal, obs)
    }

    /// `makePlan`: NavFn set-up with the swap, propagation, tolerance search, extraction.
    fn make_plan<O: SearchObserver>(
        &mut self,
        start: [f64; 2],
        goal: [f64; 2],
        obs: &mut O,
    ) -> PlannerPlan {
        let (w, nx, ny) = (self.world, self.nx, self.ny);
        let Some(start_cell) = w.planner_world_to_map(start, nx, ny) else {
            return PlannerPlan::rejected(PlanStatus::UbStartRoundsOutOfMap);
        };
        let Some(goal_cell) = w.planner_world_to_map(goal, nx, ny) else {
            return PlannerPlan::rejected(PlanStatus::UbGoalRoundsOutOfMap);
        };
        let nav = &mut self.nav;
        // sizes and cells were validated above, so these cannot fail
        let _ = nav.resize(nx, ny);
        let allow_unknown = self.params.allow_unknown;
        let _ = nav.set_costs_ros(self.costmap, allow_unknown);
        // clearRobotCell: the robot cell is FREE_SPACE when the costmap is converted
        let _ = nav.set_cost(start_cell, ros_to_navfn_cost(FREE_SPACE_ROS, allow_unknown));
        let _ = nav.set_start(goal_cell);
        let _ = nav.set_goal(start_cell);
        let last_path_cost = if self.params.use_astar {
            nav.calc_astar(obs);
            Some(nav.last_path_cost())
        } else {
            nav.calc_dijkstra(true, obs);
            None
        };
        let mut plan = PlannerPlan {
            status: PlanStatus::NoValidPathCouldBeFound,
            navfn_start: Some(goal_cell),
            navfn_goal: Some(start_cell),
            tol_used: false,
            best: Some(goal),
            navfn_len: 0,
            last_path_cost,
            world: Vec::new(),
        };
        let best = if self.point_potential(goal) < POT_HIGH as f64 {
            Some(goal)
        } else {
            plan.tol_used = true;
            self.tolerance_search(goal)
        };
        let Some(best) = best else {
            return plan;
        };
        plan.best = Some(best);
        let Some(best_cell) = w.planner_world_to_map(best, nx, ny) else {
            return plan;
        };
        plan.navfn_start = Some(best_cell);
        let nav = &mut self.nav;
        let _ = nav.set_start(best_cell);
        let len = nav.calc_path(nx.max(ny) * self.params.max_cycles_factor, obs);
        if len == 0 {
            return plan;
        }
        plan.navfn_len = len;
        plan.world = nav.path().iter().rev().map(|p| w.navfn_to_world(*p)).collect();
        smooth_approach_to_goal(best, &mut plan.world);
        plan.status = PlanStatus::Ok;
        plan
    }

    /// `getPointPotential`: potential at the rounded cell, `f64::MAX` outside the map.
    fn point_potential(&self, p: [f64; 2]) -> f64 {
        match self.world.planner_world_to_map(p, self.nx, self.ny) {
            Some(c) => self.nav.potential()[c.y * self.nx + c.x] as f64,
            None => f64::MAX,
        }
    }

    /// The tolerance search of `makePlan`: world grid around the goal with steps of one
    /// resolution accumulated in double; first point of strictly smallest squared distance.
    fn tolerance_search(&self, goal: [f64; 2]) -> Option<[f64; 2]> {
        let tol = self.params.tolerance;
        let res = self.world.resolution;
        let mut best = None;
        let mut best_sdist = f64::MAX;
        let mut y = goal[1] - tol;
        while y <= goal[1] + tol {
            let mut x = goal[0] - tol;
            while x <= goal[0] + tol {
                let pot = self.point_potential([x, y]);
                let sdist = squared_distance([x, y], goal);
                if pot < POT_HIGH as f64 && sdist < best_sdist {
                    best_sdist = sdist;
                    best = Some([x, y]);
                }
                // a step that no longer moves x (huge coordinates) would loop forever upstream
                if x + res == x {
                    break;
                }
                x += res;
            }
            if y + res == y {
                break;
            }
            y += res;
        }
        best
    }
}

fn squared_distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    let dx = a[0] - b[0];
    let dy = a[1] - b[1];
    dx * dx + dy * dy
}

/// `smoothApproachToGoal`: replace the last pose by the goal when the goal is nearer to the
/// second-to-last pose, or when the last pose already (almost) equals it; else append it.
fn smooth_approach_to_goal(goal: [f64; 2], poses: &mut Vec<[f64; 2]>) {
    if let [.., second, last] = poses.as_mut_slice()
        && (squared_distance(*last, *second) > squared_distance(goal, *second)
            || squared_distance(*last, goal) < 1e-6)
    {
        *last = goal;
        return;
    }
    poses.push(goal);
}
