//! The run-time checks hold on every plan of the paper's suite (both modes): 2 × 121,404
//! plans of the real NavFn semantics, so a check that is too strict would show up here.

mod common;

use vouch_navfn::checks::{PlanView, Violation, check_plan};
use vouch_navfn::core::NoObserver;
use vouch_navfn::maps::{find_test_files, read_suite_file};
use vouch_navfn::suite::{CaseRunner, CostInput, RunMode};

#[test]
fn checks_hold_on_every_suite_plan() {
    let Some(shared) = common::shared_navfn() else { return };
    let files = find_test_files(&shared.join("suite"), "test.txt").expect("suite readable");
    let mut runner = CaseRunner::new();
    let (mut plans, mut paths) = (0usize, 0usize);
    let mut bad = Vec::new();
    for f in &files {
        let file = read_suite_file(f).expect("parses");
        for case in &file.cases {
            for mode in [RunMode::Paper, RunMode::NavfnDijkstra] {
                let o =
                    runner.run_case(&file, case, mode, CostInput::Raw, &mut NoObserver).unwrap();
                let report = check_plan(&PlanView::of(runner.nav()));
                plans += 1;
                paths += (o.len > 0) as usize;
                if !report.is_ok() && bad.len() < 10 {
                    bad.push(format!(
                        "{} case {} {mode:?}: {:?}",
                        f.display(),
                        case.number,
                        report.violations
                    ));
                }
            }
        }
    }
    println!("checked {plans} plans ({paths} with a path)");
    assert_eq!(plans, 2 * 121_404);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The same on the five nav2 maps as ROS costmaps: cell-level (both algorithms) and the
/// world-level planner (the plan's NavFn arrays after `createPlan`).
#[test]
fn checks_hold_on_every_ros_plan() {
    use vouch_navfn::maps::read_world_params;
    use vouch_navfn::planner::{NavfnPlanner, PlanStatus, PlannerParams};
    let Some(shared) = common::shared_navfn() else { return };
    let mut runner = CaseRunner::new();
    let (mut plans, mut ok_plans, mut blocked_ends) = (0usize, 0usize, 0usize);
    for map in ["400x400_ros", "empty_room", "keepout_mask", "map_circular", "speed_mask"] {
        let dir = shared.join("suite_ros").join(map);
        let cells = read_suite_file(&dir.join("test.txt")).unwrap();
        for case in &cells.cases {
            for mode in [RunMode::NavfnAstar, RunMode::NavfnDijkstra] {
                runner.run_case(&cells, case, mode, CostInput::Ros, &mut NoObserver).unwrap();
                let nav = runner.nav();
                let r = check_plan(&PlanView::of(nav));
                plans += 1;
                // Without the planner's clearRobotCell, a robot start on an inscribed (253) cell
                // is a NavFn obstacle; NavFn still gives it potential 0 and ends the path there.
                // The check rightly flags that last point; nothing else may be flagged.
                let goal = nav.goal();
                let goal_blocked = nav.costs()[goal.y * nav.nx() + goal.x] >= 254;
                let last = nav.path().len().wrapping_sub(1);
                let unexplained: Vec<_> = r
                    .violations
                    .iter()
                    .filter(|v| !(goal_blocked && matches!(v, Violation::PoseInObstacle { index, .. } if *index == last)))
                    .collect();
                assert!(unexplained.is_empty(), "{map} case {}: {:?}", case.number, unexplained);
                blocked_ends += (!r.is_ok()) as usize;
            }
        }
        let world = read_suite_file(&dir.join("test_world.txt")).unwrap();
        let params = read_world_params(&dir.join("params.txt")).unwrap();
        for use_astar in [false, true] {
            let pp = PlannerParams { use_astar, ..PlannerParams::default() };
            let mut planner =
                NavfnPlanner::new(&world.map, world.width, world.height, params, pp).unwrap();
            for case in &world.cases {
                let [x0, y0, x1, y1] = case.coords;
                let plan = planner.create_plan([x0, y0], [x1, y1]);
                if plan.status == PlanStatus::Ok {
                    let r = check_plan(&PlanView::of(planner.nav()));
                    assert!(r.is_ok(), "{map} planner case {}: {:?}", case.number, r.violations);
                    ok_plans += 1;
                }
            }
        }
    }
    println!(
        "checked {plans} cell-level plans ({blocked_ends} end in the robot's own obstacle cell) \
         and {ok_plans} planner plans on the nav2 maps"
    );
    assert!(ok_plans > 400);
}
