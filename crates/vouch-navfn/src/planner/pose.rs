//! Poses as nav2's `NavfnPlanner::createPlan` returns them: positions from the plan, every
//! orientation the identity quaternion except the last pose, which is the goal pose (its
//! orientation and height, at the position planned to); with `use_final_approach_orientation`
//! the last orientation instead faces along the final approach (`atan2` of the last step, turned
//! into a quaternion by tf2's `setRPY(0, 0, θ)`); a start equal to the goal gives the start pose
//! with the goal's orientation (or the start's, with final approach orientation).

use super::{NavfnPlanner, PlanStatus, PlannerPlan};

/// A pose in the map frame, as `geometry_msgs/Pose`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Pose {
    /// x, y, z in metres.
    pub position: [f64; 3],
    /// Quaternion x, y, z, w.
    pub orientation: [f64; 4],
}

/// The identity quaternion nav2 gives every pose but the last.
pub const IDENTITY: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

impl Pose {
    /// A pose at (x, y, 0) facing `yaw` radians (quaternion as tf2 builds it).
    pub fn from_xy_yaw(x: f64, y: f64, yaw: f64) -> Pose {
        Pose { position: [x, y, 0.0], orientation: orientation_around_z(yaw) }
    }

    /// (x, y) of the position.
    pub fn xy(&self) -> [f64; 2] {
        [self.position[0], self.position[1]]
    }

    /// The heading of the orientation about z (radians, `atan2` of the quaternion's
    /// rotation of the x axis).
    pub fn yaw(&self) -> f64 {
        let [x, y, z, w] = self.orientation;
        (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
    }
}

/// `nav2_util::geometry_utils::orientationAroundZAxis(angle)`: tf2's `setRPY(0, 0, angle)`,
/// evaluated with the same products and sums (roll and pitch are zero) so that signs of zero
/// and roundings agree.
pub fn orientation_around_z(angle: f64) -> [f64; 4] {
    let (half_yaw, half_pitch, half_roll) = (angle * 0.5, 0.0f64 * 0.5, 0.0f64 * 0.5);
    let (cos_yaw, sin_yaw) = (half_yaw.cos(), half_yaw.sin());
    let (cos_pitch, sin_pitch) = (half_pitch.cos(), half_pitch.sin());
    let (cos_roll, sin_roll) = (half_roll.cos(), half_roll.sin());
    [
        sin_roll * cos_pitch * cos_yaw - cos_roll * sin_pitch * sin_yaw,
        cos_roll * sin_pitch * cos_yaw + sin_roll * cos_pitch * sin_yaw,
        cos_roll * cos_pitch * sin_yaw - sin_roll * sin_pitch * cos_yaw,
        cos_roll * cos_pitch * cos_yaw + sin_roll * sin_pitch * sin_yaw,
    ]
}

/// A plan with the poses nav2 publishes.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PosePlan {
    /// The plan (status, NavFn facts, world positions).
    pub plan: PlannerPlan,
    /// The poses of `nav_msgs/Path` (empty unless the plan succeeded or start equals goal).
    pub poses: Vec<Pose>,
}

impl NavfnPlanner<'_> {
    /// `createPlan(start, goal)` with full poses: the positions of
    /// [`NavfnPlanner::create_plan`] and nav2's orientations.
    pub fn create_plan_poses(&mut self, start: &Pose, goal: &Pose) -> PosePlan {
        let plan = self.create_plan(start.xy(), goal.xy());
        let final_approach = self.params().use_final_approach_orientation;
        let poses = match plan.status {
            PlanStatus::StartEqualsGoal => {
                let mut pose = *start;
                if start.orientation != goal.orientation && !final_approach {
                    pose.orientation = goal.orientation;
                }
                vec![pose]
            }
            PlanStatus::Ok => path_poses(&plan.world, start, goal, final_approach),
            _ => Vec::new(),
        };
        PosePlan { plan, poses }
    }
}

/// The poses of a found path: identity orientations, the goal pose at the end (at the
/// position planned to), then the final approach orientation if asked for.
fn path_poses(world: &[[f64; 2]], start: &Pose, goal: &Pose, final_approach: bool) -> Vec<Pose> {
    let mut poses: Vec<Pose> =
        world.iter().map(|p| Pose { position: [p[0], p[1], 0.0], orientation: IDENTITY }).collect();
    if let Some(last) = poses.last_mut() {
        last.position[2] = goal.position[2];
        last.orientation = goal.orientation;
    }
    if final_approach {
        let n = poses.len();
        if n == 1 {
            poses[0].orientation = start.orientation;
        } else if n > 1 {
            let last = poses[n - 1].position;
            let mut approach = poses[n - 2].position;
            // NavFn can end with two equal poses: face along the step before them
            if (last[0] - approach[0]).abs() < 0.0001
                && (last[1] - approach[1]).abs() < 0.0001
                && n > 2
            {
                approach = poses[n - 3].position;
            }
            let theta = (last[1] - approach[1]).atan2(last[0] - approach[0]);
            poses[n - 1].orientation = orientation_around_z(theta);
        }
    }
    poses
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternions_about_z_have_tf2_signs() {
        assert_eq!(orientation_around_z(0.0), [0.0, 0.0, 0.0, 1.0]);
        let q = orientation_around_z(std::f64::consts::PI);
        assert_eq!(q[2], 1.0);
        assert!(q[3].abs() < 1e-16);
        let q = orientation_around_z(-std::f64::consts::FRAC_PI_2);
        assert!((q[2] + std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
        assert!(
            (Pose { position: [0.0; 3], orientation: q }.yaw() + std::f64::consts::FRAC_PI_2).abs()
                < 1e-12
        );
    }
}
