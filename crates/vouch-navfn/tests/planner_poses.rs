//! Poses as nav2's planner returns them: identity orientations, the goal's orientation (and
//! height) on the last pose, the final approach orientation on request, the one-pose answer to
//! a start equal to the goal, and `max_cycles_factor` as the path iteration limit.

use vouch_navfn::planner::{IDENTITY, NavfnPlanner, PlanStatus, PlannerParams, Pose, WorldParams};

/// A 20×20 free map with a wall, 0.1 m cells.
fn map() -> Vec<u8> {
    let mut m = vec![0u8; 400];
    for y in 3..17 {
        m[y * 20 + 10] = 254;
    }
    m
}

fn planner(costs: &[u8], params: PlannerParams) -> NavfnPlanner<'_> {
    let world = WorldParams { origin: [-1.0, -1.0], resolution: 0.1 };
    NavfnPlanner::new(costs, 20, 20, world, params).expect("valid set-up")
}

#[test]
fn the_last_pose_is_the_goal_pose_and_the_others_face_nowhere() {
    let costs = map();
    let mut p = planner(&costs, PlannerParams::default());
    let start = Pose::from_xy_yaw(-0.7, -0.2, 0.3);
    let mut goal = Pose::from_xy_yaw(0.6, 0.1, -2.0);
    goal.position[2] = 0.25;
    let out = p.create_plan_poses(&start, &goal);
    assert_eq!(out.plan.status, PlanStatus::Ok);
    assert_eq!(out.poses.len(), out.plan.world.len());
    let (last, rest) = out.poses.split_last().expect("poses");
    assert_eq!(last.position, [0.6, 0.1, 0.25]);
    assert_eq!(last.orientation, goal.orientation);
    for (pose, xy) in rest.iter().zip(&out.plan.world) {
        assert_eq!(pose.orientation, IDENTITY);
        assert_eq!(pose.position, [xy[0], xy[1], 0.0]);
    }
    // the quaternion of a yaw: rotation about z only, unit length, the same heading back
    let q = goal.orientation;
    assert_eq!((q[0], q[1]), (0.0, 0.0));
    assert!((q[2] * q[2] + q[3] * q[3] - 1.0).abs() < 1e-15);
    assert!((goal.yaw() + 2.0).abs() < 1e-12);
}

#[test]
fn final_approach_orientation_faces_along_the_last_step() {
    let costs = map();
    let params = PlannerParams { use_final_approach_orientation: true, ..Default::default() };
    let mut p = planner(&costs, params);
    let start = Pose::from_xy_yaw(-0.7, -0.2, 0.3);
    let goal = Pose::from_xy_yaw(0.6, 0.1, -2.0);
    let out = p.create_plan_poses(&start, &goal);
    let n = out.poses.len();
    let last = out.poses[n - 1].position;
    let mut before = out.poses[n - 2].position;
    if (last[0] - before[0]).abs() < 1e-4 && (last[1] - before[1]).abs() < 1e-4 {
        before = out.poses[n - 3].position;
    }
    let heading = (last[1] - before[1]).atan2(last[0] - before[0]);
    assert!((out.poses[n - 1].yaw() - heading).abs() < 1e-12);
    assert_ne!(out.poses[n - 1].orientation, goal.orientation);
    assert!(out.poses[..n - 1].iter().all(|p| p.orientation == IDENTITY));
}

#[test]
fn start_equal_to_goal_is_one_pose_with_the_goal_or_start_orientation() {
    let costs = map();
    let start = Pose::from_xy_yaw(0.2, 0.2, 0.5);
    let goal = Pose::from_xy_yaw(0.2, 0.2, 1.5);
    let out = planner(&costs, PlannerParams::default()).create_plan_poses(&start, &goal);
    assert_eq!(out.plan.status, PlanStatus::StartEqualsGoal);
    assert_eq!(out.poses, vec![Pose { orientation: goal.orientation, ..start }]);
    let params = PlannerParams { use_final_approach_orientation: true, ..Default::default() };
    let out = planner(&costs, params).create_plan_poses(&start, &goal);
    assert_eq!(out.poses, vec![start]);
}

#[test]
fn max_cycles_factor_bounds_the_path_extraction() {
    let costs = map();
    let start = Pose::from_xy_yaw(-0.7, -0.2, 0.0);
    let goal = Pose::from_xy_yaw(0.6, 0.1, 0.0);
    let full = planner(&costs, PlannerParams::default()).create_plan_poses(&start, &goal);
    assert_eq!(full.plan.status, PlanStatus::Ok);
    // the path needs more than max(20, 20) · 1 = 20 NavFn iterations
    assert!(full.plan.navfn_len > 20, "{}", full.plan.navfn_len);
    let params = PlannerParams { max_cycles_factor: 1, ..Default::default() };
    let short = planner(&costs, params).create_plan_poses(&start, &goal);
    assert_eq!(short.plan.status, PlanStatus::NoValidPathCouldBeFound);
    assert!(short.poses.is_empty());
}
