//! Property tests on random maps: the run-time checks hold on every plan NavFn returns, and
//! corrupting a plan (path or potential) is caught by the checks.

use proptest::prelude::*;
use vouch_navfn::checks::{PlanView, Violation, check_plan};
use vouch_navfn::core::{Algo, COST_OBS, Cell, NoObserver, POT_HIGH};
use vouch_navfn::suite::{CaseRunner, CostInput, MapRef};

/// A random map in NavFn costs (border 254, interior 50..=253 or 254) with two open cells.
fn map_strategy() -> impl Strategy<Value = (usize, usize, Vec<u8>, Cell, Cell)> {
    (4usize..24, 4usize..24).prop_flat_map(|(nx, ny)| {
        let cells = proptest::collection::vec(
            prop_oneof![6 => Just(50u8), 3 => 50u8..=253, 2 => Just(COST_OBS)],
            nx * ny,
        );
        (Just(nx), Just(ny), cells, 1..nx - 1, 1..ny - 1, 1..nx - 1, 1..ny - 1).prop_map(
            |(nx, ny, mut cost, sx, sy, gx, gy)| {
                for y in 0..ny {
                    for x in 0..nx {
                        if x == 0 || y == 0 || x == nx - 1 || y == ny - 1 {
                            cost[y * nx + x] = COST_OBS;
                        }
                    }
                }
                cost[sy * nx + sx] = 50;
                cost[gy * nx + gx] = 50;
                (nx, ny, cost, Cell::new(sx, sy), Cell::new(gx, gy))
            },
        )
    })
}

#[derive(Clone, Copy, Debug)]
enum Mode {
    Paper,
    NavfnDijkstra,
    NavfnAstar,
}

fn run(
    runner: &mut CaseRunner,
    mode: Mode,
    nx: usize,
    ny: usize,
    map: &[u8],
    from: Cell,
    to: Cell,
) -> usize {
    let o = match mode {
        Mode::Paper => runner.run_paper(map, nx, ny, from, to, &mut NoObserver),
        Mode::NavfnDijkstra => {
            runner.run_navfn(raw(map, nx, ny), Algo::Dijkstra, from, to, &mut NoObserver)
        }
        Mode::NavfnAstar => {
            runner.run_navfn(raw(map, nx, ny), Algo::Astar, from, to, &mut NoObserver)
        }
    };
    o.expect("valid case").len
}

fn mode_strategy() -> impl Strategy<Value = Mode> {
    prop_oneof![Just(Mode::Paper), Just(Mode::NavfnDijkstra), Just(Mode::NavfnAstar)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1500, max_global_rejects: 1_000_000, ..ProptestConfig::default() })]

    #[test]
    fn checks_hold_on_every_plan((nx, ny, map, a, b) in map_strategy(), mode in mode_strategy()) {
        let mut runner = CaseRunner::new();
        run(&mut runner, mode, nx, ny, &map, a, b);
        let report = check_plan(&PlanView::of(runner.nav()));
        prop_assert!(report.is_ok(), "{:?}", report.violations);
    }

    #[test]
    fn moving_a_path_point_into_an_obstacle_is_caught(
        (nx, ny, map, a, b) in map_strategy(), mode in mode_strategy(), pick in any::<prop::sample::Index>()
    ) {
        let mut runner = CaseRunner::new();
        let len = run(&mut runner, mode, nx, ny, &map, a, b);
        prop_assume!(len >= 1);
        let nav = runner.nav();
        let mut path = nav.path().to_vec();
        let i = pick.index(path.len());
        // the border ring is always an obstacle after set-up
        path[i] = [0.0, path[i][1]];
        let view = PlanView { path: &path, ..PlanView::of(nav) };
        let report = check_plan(&view);
        let caught = report.violations.iter().any(|v| matches!(v, Violation::PoseInObstacle { index, .. } if *index == i));
        prop_assert!(caught, "{:?}", report);
    }

    #[test]
    fn corrupting_the_potential_is_caught(
        (nx, ny, map, a, b) in map_strategy(), mode in mode_strategy(), pick in any::<prop::sample::Index>(),
        kind in 0u8..2
    ) {
        let mut runner = CaseRunner::new();
        run(&mut runner, mode, nx, ny, &map, a, b);
        let goal = runner.nav().goal();
        let costs = runner.nav().costs().to_vec();
        let pot = runner.nav_mut().potential_mut();
        let goal_i = goal.y * nx + goal.x;
        if kind == 0 {
            // give an obstacle a finite potential: PositionSafe must fail
            let obstacles: Vec<usize> = (0..nx * ny).filter(|&i| costs[i] >= COST_OBS && i != goal_i).collect();
            let i = obstacles[pick.index(obstacles.len())];
            pot[i] = 123.0;
            let report = check_plan(&PlanView::of(runner.nav()));
            let caught = report.violations.iter().any(|v| matches!(v, Violation::PotentialOnObstacle { cell } if cell.y * nx + cell.x == i));
            prop_assert!(caught, "{:?}", report);
        } else {
            // make a reached non-goal cell a local minimum: Progress must fail
            let reached: Vec<usize> = (0..nx * ny).filter(|&i| pot[i] < POT_HIGH && i != goal_i).collect();
            prop_assume!(!reached.is_empty());
            let i = reached[pick.index(reached.len())];
            pot[i] = -1.0;
            let report = check_plan(&PlanView::of(runner.nav()));
            let caught = report.violations.iter().any(|v| matches!(v, Violation::NoProgress { cell } if cell.y * nx + cell.x == i));
            prop_assert!(caught, "{:?}", report);
        }
    }
}

/// Hand-made corruptions of a known plan, one per remaining violation kind.
#[test]
fn end_point_and_unreached_corruptions_are_caught() {
    let (nx, ny) = (8, 6);
    let mut map = vec![50u8; nx * ny];
    for y in 0..ny {
        for x in 0..nx {
            if x == 0 || y == 0 || x == nx - 1 || y == ny - 1 || (x == 4 && y < 4) {
                map[y * nx + x] = COST_OBS;
            }
        }
    }
    let mut runner = CaseRunner::new();
    let len = runner
        .run_paper(&map, nx, ny, Cell::new(1, 1), Cell::new(6, 1), &mut NoObserver)
        .unwrap()
        .len;
    assert!(len > 2, "the plan around the wall exists");
    let nav = runner.nav();
    assert!(check_plan(&PlanView::of(nav)).is_ok());

    let path = nav.path()[1..].to_vec();
    let r = check_plan(&PlanView { path: &path, ..PlanView::of(nav) });
    assert!(r.violations.iter().any(|v| matches!(v, Violation::WrongFirstPoint { .. })));

    let path = nav.path()[..len - 1].to_vec();
    let r = check_plan(&PlanView { path: &path, ..PlanView::of(nav) });
    assert!(r.violations.iter().any(|v| matches!(v, Violation::WrongLastPoint { .. })));

    let mut pot = nav.potential().to_vec();
    let p = nav.path()[1];
    for dx in [-0.5f32, 0.0, 0.5] {
        for dy in [-0.5f32, 0.0, 0.5] {
            let (x, y) = ((p[0] + dx).round() as usize, (p[1] + dy).round() as usize);
            pot[y * nx + x] = POT_HIGH;
        }
    }
    let r = check_plan(&PlanView { potential: &pot, ..PlanView::of(nav) });
    assert!(
        r.violations.iter().any(|v| matches!(v, Violation::PoseOnUnreachedCell { index: 1, .. }))
    );
}

/// A map of raw NavFn costs.
fn raw(bytes: &[u8], nx: usize, ny: usize) -> MapRef<'_> {
    MapRef { bytes, nx, ny, costs: CostInput::Raw }
}
