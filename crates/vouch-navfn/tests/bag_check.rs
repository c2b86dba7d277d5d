//! `check-bag` on bags written by the ROS ecosystem's own writers (rosbags: rosbag2 folders
//! with sqlite3 and MCAP storage; mcap-ros2-support: a bare .mcap file), made from every nav2
//! map: plans from vouch's planner and deliberately corrupted copies (through an obstacle, a
//! jump, a detour, a truncated path). Every corrupted plan is reported with the property it
//! breaks, no good plan is, and every good plan replays bit-identically.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};
use vouch_navfn::bagcheck::{BagCheckOptions, PathViolation, Replay, check_bag_file};
use vouch_navfn::maps::{RosMap, WorldParams, load_ros_map};
use vouch_navfn::planner::{NavfnPlanner, PlanStatus, PlannerParams, Pose};

/// How a plan was corrupted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Corruption {
    Good,
    ThroughObstacle,
    Jump,
    Detour,
    Truncated,
}

/// The nav2 maps: (name, map file, suite_ros folder with world requests).
const MAPS: [(&str, &str, &str); 5] = [
    ("map", "map.pgm", "400x400_ros"),
    ("empty_room", "empty_room.yaml", "empty_room"),
    ("keepout_mask", "keepout_mask.yaml", "keepout_mask"),
    ("map_circular", "map_circular.yaml", "map_circular"),
    ("speed_mask", "speed_mask.yaml", "speed_mask"),
];

/// One map's scenario: its costmap as nav2 holds it and the plans to record.
struct Scenario {
    map: RosMap,
    world: WorldParams,
    plans: Vec<(Pose, Pose, Vec<Pose>, Corruption)>,
}

fn pose_json(p: &Pose) -> Value {
    json!([
        p.position[0],
        p.position[1],
        p.position[2],
        p.orientation[0],
        p.orientation[1],
        p.orientation[2],
        p.orientation[3]
    ])
}

/// World requests of a suite_ros folder (x0 y0 x1 y1 per line, after the 3-line header).
fn requests(dir: &Path) -> Vec<([f64; 2], [f64; 2])> {
    let text = std::fs::read_to_string(dir.join("test_world.txt")).expect("test_world.txt");
    let mut out: Vec<([f64; 2], [f64; 2])> = text
        .lines()
        .skip(3)
        .filter_map(|l| {
            let v: Vec<f64> = l.split_whitespace().filter_map(|t| t.parse().ok()).collect();
            (v.len() == 4).then(|| ([v[0], v[1]], [v[2], v[3]]))
        })
        .collect();
    // the long-range pairs are the last twenty
    out.reverse();
    out
}

fn scenario(shared: &Path, file: &str, folder: &str) -> Scenario {
    let mut map = load_ros_map(&shared.join("nav2_maps").join(file), true).expect("map loads");
    // Costmap2D holds the resolution the map message carries: a float32, widened
    let world = WorldParams {
        origin: map.world().origin,
        resolution: map.world().resolution as f32 as f64,
    };
    let pairs = requests(&shared.join("suite_ros").join(folder));
    if !map.costmap.contains(&254) {
        // a map without obstacles (speed_mask) gets a block across its first long request
        let (s, g) = pairs[0];
        let mid = [(s[0] + g[0]) / 2.0, (s[1] + g[1]) / 2.0];
        let c = world.costmap_world_to_map(mid, map.width, map.height).expect("on the map");
        for y in c.y - 4..=c.y + 4 {
            for x in c.x - 4..=c.x + 4 {
                map.occupancy[y * map.width + x] = 100;
                map.costmap[y * map.width + x] = 254;
            }
        }
    }
    let mut planner =
        NavfnPlanner::new(&map.costmap, map.width, map.height, world, PlannerParams::default())
            .expect("planner");
    let mut good = Vec::new();
    for (k, (s, g)) in pairs.into_iter().enumerate() {
        let start = Pose::from_xy_yaw(s[0], s[1], 0.1 * k as f64);
        let goal = Pose::from_xy_yaw(g[0], g[1], -0.2 * k as f64);
        if planner.check_end(vouch_navfn::planner::End::Start, s).is_err()
            || planner.check_end(vouch_navfn::planner::End::Goal, g).is_err()
        {
            continue;
        }
        let out = planner.create_plan_poses(&start, &goal);
        if out.plan.status == PlanStatus::Ok && out.poses.len() >= 60 {
            good.push((start, goal, out.poses));
        }
        if good.len() == 3 {
            break;
        }
    }
    assert!(good.len() >= 2, "{file}: too few long plans");
    let mut plans: Vec<_> =
        good.iter().map(|(s, g, p)| (*s, *g, p.clone(), Corruption::Good)).collect();
    let corruptions =
        [Corruption::ThroughObstacle, Corruption::Jump, Corruption::Detour, Corruption::Truncated];
    for (k, c) in corruptions.into_iter().enumerate() {
        let (s, g, p) = &good[k % good.len()];
        let bad = corrupt(&map, world, p, c).unwrap_or_else(|| panic!("{file}: no {c:?}"));
        plans.push((*s, *g, bad, c));
    }
    Scenario { map, world, plans }
}

/// Poses on a straight line from `a` to `b` (excluding `a`) in steps of half a cell.
fn walk(a: [f64; 2], b: [f64; 2], res: f64) -> Vec<Pose> {
    let d = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let n = (d / (0.5 * res)).ceil().max(1.0) as usize;
    (1..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            Pose::from_xy_yaw(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, 0.0)
        })
        .collect()
}

/// An excursion from pose `i` to `to` and back, inserted after pose `i`.
fn excursion(poses: &[Pose], i: usize, to: [f64; 2], res: f64) -> Vec<Pose> {
    let at = poses[i].xy();
    let mut out = poses[..=i].to_vec();
    out.extend(walk(at, to, res));
    out.extend(walk(to, at, res));
    out.extend_from_slice(&poses[i + 1..]);
    out
}

fn cost_at(map: &RosMap, world: WorldParams, p: [f64; 2]) -> Option<u8> {
    let c = world.costmap_world_to_map(p, map.width, map.height)?;
    Some(map.costmap[c.y * map.width + c.x])
}

fn corrupt(map: &RosMap, w: WorldParams, poses: &[Pose], c: Corruption) -> Option<Vec<Pose>> {
    let n = poses.len();
    let res = w.resolution;
    match c {
        Corruption::Good => Some(poses.to_vec()),
        Corruption::Truncated => Some(poses[..n - n / 4].to_vec()),
        Corruption::Jump => {
            // drop poses until the gap is at least six cells
            let from = n / 3;
            let to = (from + 2..n - 1).find(|&j| {
                let (a, b) = (poses[from].xy(), poses[j].xy());
                ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt() >= 6.0 * res
            })?;
            Some([&poses[..=from], &poses[to..]].concat())
        }
        Corruption::ThroughObstacle => {
            // out to the nearest lethal cell and back
            let i = n / 2;
            let c0 = w.costmap_world_to_map(poses[i].xy(), map.width, map.height)?;
            let lethal = (1..400i64).find_map(|r| {
                (-r..=r).flat_map(|dy| (-r..=r).map(move |dx| (dx, dy))).find_map(|(dx, dy)| {
                    let (x, y) = (c0.x as i64 + dx, c0.y as i64 + dy);
                    let inside =
                        x >= 0 && y >= 0 && (x as usize) < map.width && (y as usize) < map.height;
                    (inside && map.costmap[y as usize * map.width + x as usize] == 254)
                        .then_some((x, y))
                })
            })?;
            let to = [w.origin[0] + lethal.0 as f64 * res, w.origin[1] + lethal.1 as f64 * res];
            Some(excursion(poses, i, to, res))
        }
        Corruption::Detour => {
            // back and to the side (or straight back), through free cells only, and back
            for cells in [12.0, 10.0, 8.0, 6.0] {
                for i in (n / 6..5 * n / 6).step_by(3) {
                    let (a, b) = (poses[i - 2].xy(), poses[i + 2].xy());
                    let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
                    let t = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
                    for side in [1.0, -1.0, 0.0] {
                        let dir = [-t[0] - side * t[1], -t[1] + side * t[0]];
                        let norm = (dir[0].powi(2) + dir[1].powi(2)).sqrt();
                        let at = poses[i].xy();
                        let to = [
                            at[0] + dir[0] / norm * cells * res,
                            at[1] + dir[1] / norm * cells * res,
                        ];
                        let free = walk(at, to, res)
                            .iter()
                            .all(|p| matches!(cost_at(map, w, p.xy()), Some(0 | 255)));
                        if free {
                            return Some(excursion(poses, i, to, res));
                        }
                    }
                }
            }
            None
        }
    }
}

/// The messages of one bag: the map, the raw costmap (optional), then per plan its goal, the
/// robot pose (amcl or tf) and the plan.
fn messages(s: &Scenario, raw_costmap: bool, robot_by_tf: bool) -> Value {
    let origin = [s.world.origin[0], s.world.origin[1], 0.0, 0.0, 0.0, 0.0, 1.0];
    let res = s.world.resolution as f32;
    let mut msgs = vec![json!({
        "t": 1_000_000_000u64, "topic": "/map", "kind": "occupancy_grid",
        "width": s.map.width, "height": s.map.height, "resolution": res,
        "origin": origin, "data": s.map.occupancy,
    })];
    if raw_costmap {
        msgs.push(json!({
            "t": 1_500_000_000u64, "topic": "/global_costmap/costmap_raw", "kind": "costmap",
            "width": s.map.width, "height": s.map.height, "resolution": res,
            "origin": origin, "data": s.map.costmap,
        }));
    }
    for (k, (start, goal, poses, _)) in s.plans.iter().enumerate() {
        let t = 10_000_000_000u64 + k as u64 * 1_000_000_000;
        msgs.push(
            json!({"t": t, "topic": "/goal_pose", "kind": "pose_stamped", "pose": pose_json(goal)}),
        );
        if robot_by_tf {
            // map → odom shifted by one metre, odom → base_link the rest
            let odom = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
            let mut base = pose_json(start);
            base[0] = json!(start.position[0] - 1.0);
            msgs.push(json!({"t": t + 1, "topic": "/tf", "kind": "tf",
                "transforms": [["map", "odom", odom], ["odom", "base_link", base]]}));
        } else {
            msgs.push(json!({"t": t + 1, "topic": "/amcl_pose", "kind": "pose_cov", "pose": pose_json(start)}));
        }
        let ps: Vec<Value> = poses.iter().map(pose_json).collect();
        msgs.push(json!({"t": t + 100_000_000, "topic": "/plan", "kind": "path", "poses": ps}));
    }
    json!({ "messages": msgs })
}

fn write_bag(py: &str, spec: &Value, out: &Path, format: &str) {
    let dir = out.parent().expect("parent");
    std::fs::create_dir_all(dir).expect("dir");
    let spec_path = dir.join(format!("{}.json", out.file_name().unwrap().to_string_lossy()));
    std::fs::write(&spec_path, spec.to_string()).expect("spec written");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bags/write_bag.py");
    let o = Command::new(py)
        .arg(&script)
        .arg(&spec_path)
        .arg(out)
        .arg(format)
        .output()
        .expect("python runs");
    assert!(o.status.success(), "writer failed: {}", String::from_utf8_lossy(&o.stderr));
}

/// The test process's private scratch directory (`tempfile`, under the target directory).
fn scratch() -> &'static Path {
    static DIR: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        tempfile::Builder::new()
            .prefix("bags-")
            .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
            .expect("temporary directory")
    })
    .path()
}

fn tmp(name: &str) -> PathBuf {
    scratch().join(name)
}

#[test]
fn check_bag_reports_every_corrupted_plan_and_no_good_one_on_every_nav2_map() {
    let Some(shared) = common::shared_navfn() else { return };
    let Some(py) = vouch_testkit::python_with(&["rosbags", "mcap_ros2", "numpy"]) else { return };
    let (mut bags, mut checked, mut good_equal, mut corrupted_caught) = (0, 0, 0, 0);
    for (name, file, folder) in MAPS {
        let s = scenario(&shared, file, folder);
        for (format, raw, by_tf) in
            [("sqlite3", false, false), ("mcap", true, true), ("mcap_ros2", false, false)]
        {
            let out = tmp(&format!("{name}-{format}"));
            let out = if format == "mcap_ros2" { out.with_extension("mcap") } else { out };
            write_bag(&py, &messages(&s, raw, by_tf), &out, format);
            let report = check_bag_file(&out, &BagCheckOptions::default())
                .unwrap_or_else(|e| panic!("{name} {format}: {e}"));
            bags += 1;
            assert_eq!(report.plans.len(), s.plans.len(), "{name} {format}");
            for (verdict, (_, _, _, corruption)) in report.plans.iter().zip(&s.plans) {
                checked += 1;
                let label = format!("{name} {format} plan {} ({corruption:?})", verdict.index);
                let r = verdict.request.expect("request");
                assert_eq!(r.start_source, vouch_navfn::bagcheck::Source::Recorded, "{label}");
                assert_eq!(r.goal_source, vouch_navfn::bagcheck::Source::Recorded, "{label}");
                let used = verdict.costmap.as_ref().expect("costmap");
                assert!(used.exact, "{label}");
                if *corruption == Corruption::Good {
                    assert!(verdict.violations.is_empty(), "{label}: {:?}", verdict.violations);
                    assert_eq!(verdict.replay, Replay::Equal, "{label}");
                    good_equal += 1;
                    continue;
                }
                assert!(matches!(verdict.replay, Replay::Different { .. }), "{label}");
                let v = &verdict.violations;
                let caught = match corruption {
                    Corruption::ThroughObstacle => v.iter().any(|x| {
                        matches!(
                            x,
                            PathViolation::PoseInObstacle { .. }
                                | PathViolation::SegmentThroughObstacle { .. }
                        )
                    }),
                    Corruption::Jump => v.iter().any(|x| matches!(x, PathViolation::Jump { .. })),
                    Corruption::Detour => v.iter().any(|x| {
                        matches!(x, PathViolation::TurnsBack { .. } | PathViolation::Detour { .. })
                    }),
                    Corruption::Truncated => {
                        v.iter().any(|x| matches!(x, PathViolation::GoalMismatch { .. }))
                    }
                    Corruption::Good => unreachable!(),
                };
                assert!(caught, "{label}: {v:?}");
                corrupted_caught += 1;
            }
            assert_eq!(report.summary.failed, 4, "{name} {format}");
        }
    }
    eprintln!(
        "bags {bags}, plans checked {checked}: good plans replayed bit-identically {good_equal}, corrupted plans reported {corrupted_caught}"
    );
    assert_eq!(bags, 15);
    let _ = std::fs::remove_dir_all(tmp(""));
}
