//! What was in force when a plan was recorded: the costmap (from the map, the published global
//! costmap and its updates, or the raw costmap), the latest goal and robot pose, the transform
//! tree.

use std::collections::BTreeMap;

use crate::maps::{WorldParams, static_layer_value};
use crate::planner::Pose;
use crate::rosbag::msgs::{Grid, GridCells, GridUpdate, PoseMsg, Transform};

/// Where a costmap came from, which decides how its cells become Costmap2D values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CostmapKind {
    /// map_server's occupancy grid (`/map`), through nav2's static layer (trinary, unknown kept).
    Map,
    /// The global costmap as nav2's costmap publisher translates it (`OccupancyGrid`, lossy
    /// between 1 and 98).
    Translated,
    /// The global costmap's own bytes (`nav2_msgs/Costmap`).
    Raw,
}

/// A costmap as the planner would see it.
#[derive(Clone, Debug, PartialEq)]
pub struct CostmapState {
    /// Where it came from.
    pub kind: CostmapKind,
    /// Topic.
    pub topic: String,
    /// Log time of its last message (grid or update), ns.
    pub log_time: u64,
    /// Frame of the grid.
    pub frame_id: String,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// The world frame (origin x, y; the message's float resolution widened to double, as
    /// Costmap2D holds it).
    pub world: WorldParams,
    /// Costmap2D values, row 0 first.
    pub costs: Vec<u8>,
    /// Every value is known exactly (a translated costmap is exact only while it holds free,
    /// inscribed, lethal and unknown cells alone).
    pub exact: bool,
}

/// nav2's costmap publisher translation (Costmap2D value → OccupancyGrid value).
pub fn translate_cost(cost: u8) -> i8 {
    match cost {
        0 => 0,
        253 => 99,
        254 => 100,
        255 => -1,
        c => (1 + (97 * (c as u32 - 1)) / 251) as i8,
    }
}

/// The smallest Costmap2D value the publisher translates to `v` (its inverse where it is one).
pub fn untranslate(v: i8) -> u8 {
    match v {
        0 => 0,
        99 => 253,
        100 => 254,
        v if !(1..=98).contains(&v) => 255,
        v => (1..=252u8).find(|&c| translate_cost(c) == v).unwrap_or(252),
    }
}

impl CostmapState {
    /// A costmap from a whole grid message.
    pub fn from_grid(kind: CostmapKind, topic: &str, log_time: u64, g: &Grid) -> CostmapState {
        let (costs, exact) = match &g.cells {
            GridCells::Costs(c) => (c.clone(), true),
            GridCells::Occupancy(o) if kind == CostmapKind::Map => {
                (o.iter().map(|&v| static_layer_value(v, true)).collect(), true)
            }
            GridCells::Occupancy(o) => (
                o.iter().map(|&v| untranslate(v)).collect(),
                o.iter().all(|&v| matches!(v, 0 | 99 | 100 | -1)),
            ),
        };
        CostmapState {
            kind,
            topic: topic.to_string(),
            log_time,
            frame_id: g.frame_id.clone(),
            width: g.width,
            height: g.height,
            world: WorldParams {
                origin: [g.origin.position.x, g.origin.position.y],
                resolution: g.resolution as f64,
            },
            costs,
            exact,
        }
    }

    /// Applies a `costmap_updates` rectangle; `false` when it does not fit the grid.
    pub fn apply_update(&mut self, u: &GridUpdate, log_time: u64) -> bool {
        let fits = u.x >= 0
            && u.y >= 0
            && (u.x as usize).checked_add(u.width).is_some_and(|e| e <= self.width)
            && (u.y as usize).checked_add(u.height).is_some_and(|e| e <= self.height);
        if !fits {
            return false;
        }
        for row in 0..u.height {
            for col in 0..u.width {
                let v = u.data[row * u.width + col];
                let i = (u.y as usize + row) * self.width + u.x as usize + col;
                self.costs[i] = untranslate(v);
                self.exact &= matches!(v, 0 | 99 | 100 | -1);
            }
        }
        self.log_time = log_time;
        true
    }
}

/// The transform tree: the latest transform of every child frame.
#[derive(Clone, Debug, Default)]
pub struct TfTree {
    parents: BTreeMap<String, (String, PoseMsg)>,
}

impl TfTree {
    /// Records transforms.
    pub fn insert(&mut self, ts: &[Transform]) {
        for t in ts {
            self.parents.insert(t.child.clone(), (t.parent.clone(), t.pose));
        }
    }

    /// The pose of `frame` in `target`, walking up at most 32 parents.
    pub fn lookup(&self, target: &str, frame: &str) -> Option<PoseMsg> {
        let mut pose = PoseMsg { orientation: quat_identity(), ..PoseMsg::default() };
        let mut at = frame.to_string();
        for _ in 0..32 {
            if at == target {
                return Some(pose);
            }
            let (parent, t) = self.parents.get(&at)?;
            pose = compose(t, &pose);
            at = parent.clone();
        }
        None
    }
}

fn quat_identity() -> crate::rosbag::msgs::Quaternion {
    crate::rosbag::msgs::Quaternion { x: 0.0, y: 0.0, z: 0.0, w: 1.0 }
}

/// `a ∘ b`: the pose `b` (given in frame A) expressed in `a`'s parent frame.
fn compose(a: &PoseMsg, b: &PoseMsg) -> PoseMsg {
    use crate::rosbag::msgs::{Point, Quaternion};
    let q = a.orientation;
    let p = b.position;
    // v' = q v q*, expanded
    let (qx, qy, qz, qw) = (q.x, q.y, q.z, q.w);
    let tx = 2.0 * (qy * p.z - qz * p.y);
    let ty = 2.0 * (qz * p.x - qx * p.z);
    let tz = 2.0 * (qx * p.y - qy * p.x);
    let rotated = Point {
        x: p.x + qw * tx + (qy * tz - qz * ty),
        y: p.y + qw * ty + (qz * tx - qx * tz),
        z: p.z + qw * tz + (qx * ty - qy * tx),
    };
    let r = b.orientation;
    PoseMsg {
        position: Point {
            x: a.position.x + rotated.x,
            y: a.position.y + rotated.y,
            z: a.position.z + rotated.z,
        },
        orientation: Quaternion {
            x: qw * r.x + qx * r.w + qy * r.z - qz * r.y,
            y: qw * r.y - qx * r.z + qy * r.w + qz * r.x,
            z: qw * r.z + qx * r.y - qy * r.x + qz * r.w,
            w: qw * r.w - qx * r.x - qy * r.y - qz * r.z,
        },
    }
}

/// A message pose as a planner pose.
pub fn to_pose(p: &PoseMsg) -> Pose {
    Pose {
        position: [p.position.x, p.position.y, p.position.z],
        orientation: [p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_publisher_translation_is_inverted_where_it_can_be() {
        for c in [0u8, 253, 254, 255] {
            assert_eq!(untranslate(translate_cost(c)), c);
        }
        for c in 1..=252u8 {
            assert_eq!(translate_cost(untranslate(translate_cost(c))), translate_cost(c));
        }
        assert_eq!(translate_cost(252), 98);
        assert_eq!(translate_cost(1), 1);
    }

    #[test]
    fn transforms_chain_from_the_robot_to_the_map() {
        use crate::rosbag::msgs::{Point, Quaternion};
        let half = std::f64::consts::FRAC_1_SQRT_2;
        let mut tf = TfTree::default();
        let at = |x, y, z: f64, w: f64| PoseMsg {
            position: Point { x, y, z: 0.0 },
            orientation: Quaternion { x: 0.0, y: 0.0, z, w },
        };
        tf.insert(&[
            Transform {
                parent: "map".into(),
                child: "odom".into(),
                pose: at(1.0, 2.0, half, half),
            },
            Transform {
                parent: "odom".into(),
                child: "base_link".into(),
                pose: at(3.0, 0.0, 0.0, 1.0),
            },
        ]);
        let p = tf.lookup("map", "base_link").expect("chain");
        // odom is turned by 90°: 3 m along odom's x is 3 m along the map's y
        assert!((p.position.x - 1.0).abs() < 1e-12 && (p.position.y - 5.0).abs() < 1e-12);
        assert!((p.orientation.z - half).abs() < 1e-12);
        assert!(tf.lookup("map", "nowhere").is_none());
    }
}
