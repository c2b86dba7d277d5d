//! The checks of one recorded plan on the costmap in force: nav2's planner replayed on the
//! same request (bit-exact comparison, and the potential that the path properties need), then
//! the properties of the recorded poses — on the map, in open cells (`ValidPath`), on reached
//! cells (`FinitePotentialPath`), straight steps that cross no lethal cell, no jump, potential
//! that keeps rising from the robot to the goal (`Progress` along the path), not much longer
//! than the replayed plan, and the end points of the request.

use crate::checks::{PlanView, check_potential};
use crate::core::{COST_OBS, Cell, POT_HIGH, ros_to_navfn_cost};
use crate::picture::{PictureInput, render, write_png};
use crate::planner::{NavfnPlanner, PlanStatus, PlannerParams, Pose, PosePlan};

use super::report::{PathViolation, PlanVerdict, Replay, ReplayMode, Request, Source};
use super::state::CostmapState;

/// Largest distance between consecutive poses, in cells: a gradient step is half a cell, a
/// grid-following step goes from a point less than one cell from its cell to a neighbour cell
/// (< 1 + √2), the goal appended by `smoothApproachToGoal` lies within half a cell (on each
/// axis) of the last NavFn point.
pub const MAX_STEP_CELLS: f64 = 2.5;
/// A recorded path longer than the replayed one by this factor plus [`DETOUR_CELLS`] is a
/// detour.
pub const DETOUR_FACTOR: f64 = 1.1;
/// See [`DETOUR_FACTOR`].
pub const DETOUR_CELLS: f64 = 3.0;

/// Sampling step of the straight segments between poses, in cells.
const SEGMENT_STEP: f64 = 0.2;

/// How one plan is checked beyond the costmap and the request.
#[derive(Clone, Copy, Debug)]
pub struct PlanCheck<'a> {
    /// The planner's parameters.
    pub params: PlannerParams,
    /// How replays count.
    pub mode: ReplayMode,
    /// Render a picture when the plan fails.
    pub picture: bool,
    /// Violations found beforehand (the body check), added before the verdict.
    pub found: &'a [PathViolation],
    /// Cells of the costmap to ring on the picture, with their colour.
    pub marks: &'a [([usize; 2], [u8; 3])],
}

/// Checks one recorded plan (`poses`, robot start to goal) against `cm`. `start`/`goal` are the
/// recorded request, when there is one; missing ends are taken from the plan itself.
pub fn check_plan_on(
    cm: &CostmapState,
    poses: &[Pose],
    start: Option<Pose>,
    goal: Option<Pose>,
    how: PlanCheck<'_>,
) -> PlanVerdict {
    let PlanCheck { params, mode, picture, found, marks } = how;
    let mut v = PlanVerdict::new(poses.len());
    let (Some(first), Some(last)) = (poses.first(), poses.last()) else {
        v.violations.push(PathViolation::EmptyPath);
        return v;
    };
    let request = Request {
        start: start.unwrap_or(*first),
        goal: goal.unwrap_or(*last),
        start_source: if start.is_some() { Source::Recorded } else { Source::Inferred },
        goal_source: if goal.is_some() { Source::Recorded } else { Source::Inferred },
    };
    v.request = Some(request);
    let mut planner = match NavfnPlanner::new(&cm.costs, cm.width, cm.height, cm.world, params) {
        Ok(p) => p,
        Err(e) => {
            v.violations.push(PathViolation::Unplannable { why: e.to_string() });
            return v;
        }
    };
    let replayed = planner.create_plan_poses(&request.start, &request.goal);
    v.replay = compare(poses, &replayed, mode);
    let ran = replayed.plan.navfn_goal.is_some();
    let nav = planner.nav();
    let (nx, ny) = (cm.width, cm.height);
    let costs: Vec<u8> = if ran {
        nav.costs().to_vec()
    } else {
        cm.costs.iter().map(|&c| ros_to_navfn_cost(c, params.allow_unknown)).collect()
    };
    let potential = ran.then(|| nav.potential());
    let cells: Vec<[f64; 2]> = poses.iter().map(|p| cell_coords(cm, p)).collect();
    let grid = Grid { nx, ny, costs: &costs, potential };
    check_poses(&grid, &cells, &mut v.violations);
    check_ends(cm, &planner, &grid, poses, &request, params.tolerance, &mut v.violations);
    if let Some(pot) = potential {
        check_progress(&grid, pot, &cells, &mut v.violations);
        if !replayed.poses.is_empty() {
            check_length(cm, poses, &replayed.poses, &mut v.violations);
        }
        let report = check_potential(&PlanView::of(nav));
        v.violations.extend(report.violations.into_iter().map(PathViolation::Potential));
    }
    v.violations.extend_from_slice(found);
    if picture && !v.passed(mode) {
        v.picture = Some(draw(cm, &costs, nav.potential(), ran, &cells, &request, marks));
    }
    v
}

/// The cost and potential arrays the properties read.
struct Grid<'a> {
    nx: usize,
    ny: usize,
    costs: &'a [u8],
    potential: Option<&'a [f32]>,
}

impl Grid<'_> {
    /// The cells a point (in cell units) belongs to: |p − cell| ≤ 0.5 on both axes.
    fn belonging(&self, p: [f64; 2]) -> impl Iterator<Item = usize> + '_ {
        let axis = |c: f64, n: usize| -> [Option<usize>; 2] {
            let (lo, hi) = ((c - 0.5).ceil(), (c + 0.5).floor());
            let ok = |v: f64| (v >= 0.0 && v < n as f64).then_some(v as usize);
            [ok(lo), if hi != lo { ok(hi) } else { None }]
        };
        let (xs, ys) = (axis(p[0], self.nx), axis(p[1], self.ny));
        let nx = self.nx;
        xs.into_iter()
            .flatten()
            .flat_map(move |x| ys.into_iter().flatten().map(move |y| y * nx + x))
    }

    fn open(&self, p: [f64; 2]) -> bool {
        self.belonging(p).any(|i| self.costs[i] < COST_OBS)
    }

    fn reached(&self, pot: &[f32], p: [f64; 2]) -> bool {
        self.belonging(p).any(|i| pot[i] < POT_HIGH)
    }

    fn on_map(&self, p: [f64; 2]) -> bool {
        p.iter().all(|v| v.is_finite())
            && p[0] >= -0.5
            && p[1] >= -0.5
            && p[0] <= self.nx as f64 - 0.5
            && p[1] <= self.ny as f64 - 0.5
    }

    /// NavFn cost of the cell a point rounds to (254 off the map).
    fn cost_at(&self, p: [f64; 2]) -> f32 {
        let (x, y) = (p[0].round(), p[1].round());
        if x < 0.0 || y < 0.0 || x >= self.nx as f64 || y >= self.ny as f64 {
            return COST_OBS as f32;
        }
        self.costs[y as usize * self.nx + x as usize] as f32
    }

    /// Potential of the cell a point rounds to (NavFn's corner-aligned cells).
    fn potential_at(&self, pot: &[f32], p: [f64; 2]) -> f32 {
        let (x, y) = (p[0].round(), p[1].round());
        if x < 0.0 || y < 0.0 || x >= self.nx as f64 || y >= self.ny as f64 {
            return POT_HIGH;
        }
        pot[y as usize * self.nx + x as usize]
    }
}

/// A pose in NavFn cell units (`(w − origin) / resolution`; cell centres are whole numbers).
fn cell_coords(cm: &CostmapState, p: &Pose) -> [f64; 2] {
    let w = cm.world;
    [(p.position[0] - w.origin[0]) / w.resolution, (p.position[1] - w.origin[1]) / w.resolution]
}

/// Per pose and per step: on the map, open, reached, no jump, no lethal cell crossed.
fn check_poses(g: &Grid, cells: &[[f64; 2]], out: &mut Vec<PathViolation>) {
    for (index, &p) in cells.iter().enumerate() {
        if !g.on_map(p) {
            out.push(PathViolation::OffMap { index, cell: p });
            continue;
        }
        if !g.open(p) {
            out.push(PathViolation::PoseInObstacle { index, cell: p });
        }
        if let Some(pot) = g.potential
            && !g.reached(pot, p)
        {
            out.push(PathViolation::PoseOnUnreachedCell { index, cell: p });
        }
    }
    for (index, pair) in cells.windows(2).enumerate() {
        let (a, b) = (pair[0], pair[1]);
        let d = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if d.is_nan() || d > MAX_STEP_CELLS {
            out.push(PathViolation::Jump { index: index + 1, cells: d });
            continue;
        }
        let steps = (d / SEGMENT_STEP).ceil() as usize;
        let crossing = (1..steps).map(|k| k as f64 / steps as f64).find_map(|t| {
            let p = [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
            (g.on_map(p) && !g.open(p)).then_some(p)
        });
        if let Some(cell) = crossing {
            out.push(PathViolation::SegmentThroughObstacle { index: index + 1, cell });
        }
    }
}

/// The first pose is the robot's cell (the planner's rounding), the last one the goal (or,
/// when the goal cell was not reached, a point within the tolerance square around it).
fn check_ends(
    cm: &CostmapState,
    planner: &NavfnPlanner,
    g: &Grid,
    poses: &[Pose],
    r: &Request,
    tolerance: f64,
    out: &mut Vec<PathViolation>,
) {
    let w = cm.world;
    let eps = w.resolution * 1e-6;
    let near =
        |a: [f64; 2], b: [f64; 2], d: f64| (a[0] - b[0]).abs() <= d && (a[1] - b[1]).abs() <= d;
    let first = poses[0].xy();
    let last = poses[poses.len() - 1].xy();
    if r.start_source == Source::Recorded {
        let expected = w
            .planner_world_to_map(r.start.xy(), cm.width, cm.height)
            .map(|c: Cell| w.navfn_to_world([c.x as f32, c.y as f32]));
        if !expected.is_some_and(|e| near(first, e, eps)) {
            out.push(PathViolation::StartMismatch { first, start: r.start.xy() });
        }
    }
    if r.goal_source == Source::Recorded && poses.len() > 1 {
        let goal = r.goal.xy();
        let goal_reached = g.potential.is_some_and(|pot| {
            planner
                .world()
                .planner_world_to_map(goal, cm.width, cm.height)
                .is_some_and(|c| pot[c.y * cm.width + c.x] < POT_HIGH)
        });
        let ok =
            if goal_reached { near(last, goal, eps) } else { near(last, goal, tolerance + eps) };
        if !ok {
            out.push(PathViolation::GoalMismatch { last, goal });
        }
    }
}

/// Along the path the potential (distance to the robot) must keep rising: it may fall below
/// the highest value seen by less than the cost of the cell it is in (one cell's worth; a
/// planner's path, sampled at the cells it rounds to, falls by a fraction of that at most).
fn check_progress(g: &Grid, pot: &[f32], cells: &[[f64; 2]], out: &mut Vec<PathViolation>) {
    let mut highest = 0.0f32;
    for (index, &p) in cells.iter().enumerate() {
        let here = g.potential_at(pot, p);
        if here >= POT_HIGH {
            continue; // reported as PoseOnUnreachedCell
        }
        if here + g.cost_at(p) < highest {
            out.push(PathViolation::TurnsBack { index, drop: highest - here });
            return;
        }
        highest = highest.max(here);
    }
}

/// A recorded path much longer than the replayed one is a detour.
fn check_length(
    cm: &CostmapState,
    poses: &[Pose],
    replayed: &[Pose],
    out: &mut Vec<PathViolation>,
) {
    let len = |ps: &[Pose]| -> f64 {
        ps.windows(2)
            .map(|w| {
                ((w[1].position[0] - w[0].position[0]).powi(2)
                    + (w[1].position[1] - w[0].position[1]).powi(2))
                .sqrt()
            })
            .sum::<f64>()
            / cm.world.resolution
    };
    let (recorded, replayed) = (len(poses), len(replayed));
    if recorded > replayed * DETOUR_FACTOR + DETOUR_CELLS {
        out.push(PathViolation::Detour { recorded_cells: recorded, replayed_cells: replayed });
    }
}

/// Bit-exact comparison of the recorded poses with the replay.
fn compare(recorded: &[Pose], replayed: &PosePlan, mode: ReplayMode) -> Replay {
    if mode == ReplayMode::Off {
        return Replay::Skipped;
    }
    if !matches!(replayed.plan.status, PlanStatus::Ok | PlanStatus::StartEqualsGoal) {
        return Replay::NoPlan { status: replayed.plan.status };
    }
    let first = recorded.iter().zip(&replayed.poses).position(|(a, b)| !same_pose(a, b));
    match first {
        None if recorded.len() == replayed.poses.len() => Replay::Equal,
        _ => {
            let index = first.unwrap_or(recorded.len().min(replayed.poses.len()));
            Replay::Different {
                first_pose: index,
                recorded: recorded.get(index).copied(),
                replayed: replayed.poses.get(index).copied(),
                recorded_len: recorded.len(),
                replayed_len: replayed.poses.len(),
            }
        }
    }
}

/// Bit equality of position and orientation (the same doubles, +0 and −0 told apart).
fn same_pose(a: &Pose, b: &Pose) -> bool {
    let bits = |p: &Pose| {
        let mut v = [0u64; 7];
        for (slot, x) in v.iter_mut().zip(p.position.iter().chain(&p.orientation)) {
            *slot = x.to_bits();
        }
        v
    };
    bits(a) == bits(b)
}

/// The picture of a failing plan: the costmap, the replay's potential, the recorded path, the
/// robot's cell in green and the goal's in blue.
fn draw(
    cm: &CostmapState,
    costs: &[u8],
    potential: &[f32],
    ran: bool,
    cells: &[[f64; 2]],
    r: &Request,
    marks: &[([usize; 2], [u8; 3])],
) -> Vec<u8> {
    let unreached = vec![POT_HIGH; costs.len()];
    let path: Vec<[f32; 2]> = cells.iter().map(|p| [p[0] as f32, p[1] as f32]).collect();
    let cell_of = |p: &Pose| {
        cm.world.planner_world_to_map(p.xy(), cm.width, cm.height).unwrap_or(Cell::new(0, 0))
    };
    let view = PlanView {
        nx: cm.width,
        ny: cm.height,
        costs,
        potential: if ran { potential } else { &unreached },
        path: &path,
        start: cell_of(&r.start),
        goal: cell_of(&r.goal),
    };
    let mut png = Vec::new();
    // encoding into memory cannot fail for a well-formed image
    let _ = write_png(&mut png, &render(&PictureInput { plan: view, flip_y: true, marks }));
    png
}
