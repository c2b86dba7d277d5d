//! Core semantics beyond the golden files: the observer hook, array reuse, the planner's
//! statuses and conversions, and facts of SEMANTICS.md measured on the C++ original.

mod common;

use vouch_navfn::core::{
    Algo, COST_OBS, Cell, CoreError, CycleView, NavFn, NoObserver, POT_HIGH, PathStartView,
    PropagationEnd, PropagationEndView, SearchObserver,
};
use vouch_navfn::planner::{End, NavfnPlanner, PlanError, PlanStatus, PlannerParams, WorldParams};
use vouch_navfn::suite::{CaseRunner, CostInput, MapRef};

/// Free map with a 1-cell border of obstacles.
fn open_map(nx: usize, ny: usize) -> Vec<u8> {
    let mut m = vec![50u8; nx * ny];
    for y in 0..ny {
        for x in 0..nx {
            if x == 0 || y == 0 || x == nx - 1 || y == ny - 1 {
                m[y * nx + x] = COST_OBS;
            }
        }
    }
    m
}

#[derive(Default)]
struct Recorder {
    cycles: Vec<(usize, f32, Vec<i32>)>,
    end: Option<(usize, PropagationEnd)>,
    path_starts: usize,
    queued_obstacle: bool,
    costs: Vec<u8>,
}

impl SearchObserver for Recorder {
    fn on_cycle(&mut self, v: &CycleView<'_>) {
        self.cycles.push((v.cycle, v.threshold, v.current.to_vec()));
        let bad = |b: &[i32]| b.iter().any(|&c| self.costs[c as usize] >= COST_OBS);
        self.queued_obstacle |= bad(v.current) || bad(v.next) || bad(v.overflow);
    }
    fn on_propagation_end(&mut self, v: &PropagationEndView<'_>) {
        self.end = Some((v.cycles, v.end));
    }
    fn on_path_start(&mut self, v: &PathStartView<'_>) {
        self.path_starts += 1;
        assert_eq!(v.potential.len(), self.costs.len());
    }
}

#[test]
fn observer_sees_every_cycle_and_changes_nothing() {
    let (nx, ny) = (9, 7);
    let mut map = open_map(nx, ny);
    map[3 * nx + 4] = COST_OBS;
    let mut plain = CaseRunner::new();
    let a =
        plain.run_paper(&map, nx, ny, Cell::new(1, 1), Cell::new(7, 5), &mut NoObserver).unwrap();
    let mut rec = Recorder { costs: map.clone(), ..Default::default() };
    let mut traced = CaseRunner::new();
    let b = traced.run_paper(&map, nx, ny, Cell::new(1, 1), Cell::new(7, 5), &mut rec).unwrap();
    assert_eq!(a, b);
    assert_eq!(plain.nav().potential(), traced.nav().potential());
    assert_eq!(plain.nav().path(), traced.nav().path());
    // first cycle: the goal's neighbours in push order k+1, k-1, k-nx, k+nx (k+1, k+nx are border)
    let k = 5 * nx + 7;
    assert_eq!(rec.cycles[0].2, vec![(k - 1) as i32, (k - nx) as i32]);
    assert!(rec.cycles.iter().enumerate().all(|(i, c)| c.0 == i));
    let (cycles, end) = rec.end.unwrap();
    assert_eq!(end, PropagationEnd::StartReached);
    assert_eq!(cycles + 1, rec.cycles.len());
    assert_eq!(rec.path_starts, 1);
    assert!(!rec.queued_obstacle);
}

#[test]
fn reused_arrays_give_the_same_result_as_fresh_ones() {
    let big = open_map(20, 15);
    let small = open_map(6, 5);
    let mut reused = CaseRunner::new();
    for (map, nx, ny) in [(&big, 20, 15), (&small, 6, 5), (&big, 20, 15)] {
        for algo in [Algo::Dijkstra, Algo::Astar] {
            let (from, to) = (Cell::new(1, 1), Cell::new(nx - 2, ny - 2));
            let m = MapRef { bytes: map, nx, ny, costs: CostInput::Raw };
            let r = reused.run_navfn(m, algo, from, to, &mut NoObserver).unwrap();
            let mut fresh = CaseRunner::new();
            let f = fresh.run_navfn(m, algo, from, to, &mut NoObserver).unwrap();
            assert_eq!(r, f);
            assert!(r.len > 0);
            assert_eq!(reused.nav().potential(), fresh.nav().potential());
            assert_eq!(reused.nav().path(), fresh.nav().path());
        }
    }
}

#[test]
fn unreached_start_fails_through_int_min_grid_following() {
    // a wall splits the map: the start is never reached, the descent must return 0 at once
    let (nx, ny) = (7, 5);
    let mut map = open_map(nx, ny);
    for y in 0..ny {
        map[y * nx + 3] = COST_OBS;
    }
    let mut r = CaseRunner::new();
    let o = r.run_paper(&map, nx, ny, Cell::new(1, 2), Cell::new(5, 2), &mut NoObserver).unwrap();
    assert!(!o.prop);
    assert_eq!(o.len, 0);
    assert_eq!(o.last_path_cost, Some(POT_HIGH));
    // the start cell itself was recorded, then grid following kept it and gave up
    assert_eq!(r.nav().path_recorded(), &[[1.0, 2.0]]);
}

#[test]
fn start_equal_goal_gives_one_point() {
    let map = open_map(5, 5);
    let mut r = CaseRunner::new();
    let o = r.run_paper(&map, 5, 5, Cell::new(2, 2), Cell::new(2, 2), &mut NoObserver).unwrap();
    assert_eq!((o.prop, o.len), (true, 1));
    assert_eq!(r.nav().path(), &[[2.0, 2.0]]);
}

#[test]
fn core_rejects_cells_and_sizes_it_cannot_use() {
    assert!(NavFn::new(0, 3).is_err());
    let mut nav = NavFn::new(4, 4).unwrap();
    assert!(nav.set_start(Cell::new(4, 0)).is_err());
    assert!(nav.set_goal(Cell::new(0, 9)).is_err());
    assert!(nav.set_costs_raw(&[50; 15]).is_err());
}

fn planner(nx: usize, ny: usize, map: &[u8], world: WorldParams, tol: f64) -> NavfnPlanner<'_> {
    NavfnPlanner::new(map, nx, ny, world, PlannerParams { tolerance: tol, ..Default::default() })
        .unwrap()
}

#[test]
fn planner_statuses() {
    let w = WorldParams { origin: [-1.0, -1.0], resolution: 0.5 };
    let mut ros = vec![0u8; 10 * 10];
    ros[5 * 10 + 5] = 254;
    let mut p = planner(10, 10, &ros, w, 0.0);
    assert_eq!(p.create_plan([-1.5, 0.0], [1.0, 1.0]).status, PlanStatus::StartOutsideMapBounds);
    assert_eq!(p.create_plan([0.0, 0.0], [4.0, 1.0]).status, PlanStatus::GoalOutsideMapBounds);
    // cell (5,5) is lethal: (5*0.5-1, 5*0.5-1) = (1.5, 1.5)
    assert_eq!(p.create_plan([0.0, 0.0], [1.6, 1.6]).status, PlanStatus::GoalOccupied);
    assert_eq!(p.create_plan([0.0, 0.0], [0.0, 0.0]).status, PlanStatus::StartEqualsGoal);
    // x = 3.9 is valid for Costmap2D (truncates to 9) but rounds to 10 = size: UB upstream
    assert_eq!(p.create_plan([3.9, 0.0], [0.0, 1.0]).status, PlanStatus::UbStartRoundsOutOfMap);
    assert_eq!(p.create_plan([0.0, 0.0], [0.0, 3.9]).status, PlanStatus::UbGoalRoundsOutOfMap);
    let ok = p.create_plan([0.0, 0.0], [2.5, 2.0]);
    assert_eq!(ok.status, PlanStatus::Ok);
    // first pose: the robot cell's corner (2, 2) → origin + 2·res; last pose: the goal itself
    assert_eq!(ok.world.first(), Some(&[0.0, 0.0]));
    assert_eq!(ok.world.last(), Some(&[2.5, 2.0]));
}

#[test]
fn planner_tolerance_moves_an_unreachable_goal_to_the_nearest_reachable_point() {
    let w = WorldParams { origin: [0.0, 0.0], resolution: 1.0 };
    let mut ros = vec![0u8; 12 * 12];
    ros[6 * 12 + 6] = 254; // goal cell lethal
    let mut p = planner(12, 12, &ros, w, 1.0);
    let plan = p.create_plan([2.0, 2.0], [6.0, 6.0]);
    assert_eq!(plan.status, PlanStatus::Ok);
    assert!(plan.tol_used);
    let best = plan.best.unwrap();
    assert_eq!(best, [6.0, 5.0], "first point at distance 1 in scan order (y then x)");
    assert_eq!(plan.world.last(), Some(&best));
}

#[test]
fn nav2_default_pair_point_counts_match_the_cpp() {
    let Some(shared) = common::shared_navfn() else { return };
    let bytes = std::fs::read(shared.join("suite_ros/400x400_ros/map.bin")).unwrap();
    // SEMANTICS.md §10: Dijkstra (atStart) 1,070 points, A* 929
    for (astar, points) in [(false, 1070), (true, 929)] {
        let params = PlannerParams { use_astar: astar, ..PlannerParams::default() };
        let mut p = NavfnPlanner::new(&bytes, 400, 400, WorldParams::default(), params).unwrap();
        let plan = p.create_plan([390.0, 10.0], [10.0, 390.0]);
        assert_eq!(plan.status, PlanStatus::Ok);
        assert_eq!(plan.navfn_len, points, "astar={astar}");
    }
    // full Dijkstra (atStart=false): 1,072 points
    let mut nav = NavFn::new(400, 400).unwrap();
    nav.set_costs_ros(
        &{
            let mut b = bytes.clone();
            b[10 * 400 + 390] = 0; // clearRobotCell
            b
        },
        true,
    )
    .unwrap();
    nav.set_start(Cell::new(10, 390)).unwrap();
    nav.set_goal(Cell::new(390, 10)).unwrap();
    nav.calc_dijkstra(false, &mut NoObserver);
    assert_eq!(nav.calc_path(1600, &mut NoObserver), 1072);
}

#[test]
fn planner_refuses_setups_whose_tolerance_search_would_not_finish() {
    let ros = vec![0u8; 10 * 10];
    let w = WorldParams { origin: [0.0, 0.0], resolution: 0.1 };
    let with = |tolerance: f64, world: WorldParams| {
        let params = PlannerParams { tolerance, ..PlannerParams::default() };
        NavfnPlanner::new(&ros, 10, 10, world, params).err()
    };
    assert!(matches!(with(1e9, w), Some(PlanError::BadTolerance { .. })));
    assert!(matches!(with(-0.5, w), Some(PlanError::BadTolerance { .. })));
    assert!(matches!(with(f64::NAN, w), Some(PlanError::BadTolerance { .. })));
    // (2·tol/res + 1)² = 1e8 points at most: 499.95 m at 0.1 m is the edge
    assert!(with(499.9, w).is_none());
    let bad_res = WorldParams { resolution: -1.0, ..w };
    assert!(matches!(with(0.5, bad_res), Some(PlanError::BadWorld { .. })));
    let bad_origin = WorldParams { origin: [f64::INFINITY, 0.0], ..w };
    assert!(matches!(with(0.5, bad_origin), Some(PlanError::BadWorld { .. })));
    let short = NavfnPlanner::new(&ros[..99], 10, 10, w, PlannerParams::default());
    assert!(matches!(short.err(), Some(PlanError::Core(CoreError::CostLength { .. }))));
}

#[test]
fn checked_plans_refuse_ends_off_the_map_or_in_obstacles() {
    let mut ros = vec![0u8; 10 * 10];
    ros[3 * 10 + 4] = 254;
    let w = WorldParams { origin: [-1.0, -1.0], resolution: 0.5 };
    let mut p = NavfnPlanner::new(&ros, 10, 10, w, PlannerParams::default()).unwrap();
    let outside = p.plan_checked([0.0, 0.0], [4.0, 0.0]).unwrap_err();
    assert!(matches!(outside, PlanError::OutsideMap { end: End::Goal, .. }), "{outside}");
    assert!(outside.to_string().contains("x from -1.0000 to 4.0000"), "{outside}");
    let blocked = p.plan_checked([1.1, 0.6], [0.0, 0.0]).unwrap_err();
    assert!(matches!(blocked, PlanError::InObstacle { end: End::Start, .. }), "{blocked}");
    assert_eq!(p.cell_point(End::Start, [2.0, 3.0]), Ok([0.0, 0.5]));
    assert!(p.cell_point(End::Goal, [2.5, 3.0]).is_err());
    assert!(p.cell_point(End::Goal, [10.0, 0.0]).is_err());
    let ok = p.plan_checked([0.0, 0.0], [2.5, 2.0]).unwrap();
    assert_eq!(ok.status, PlanStatus::Ok);
    // the caller's costmap is never written (nav2's robot-cell clearing happens on NavFn's costs)
    let mut q = NavfnPlanner::new(&ros, 10, 10, w, PlannerParams::default()).unwrap();
    let _ = q.create_plan([1.0, 0.5], [0.0, 0.0]);
    assert_eq!(q.costmap()[3 * 10 + 4], 254);
    assert_eq!(q.nav().costs()[3 * 10 + 4], 50, "robot cell cleared for the plan");
}
