//! `vouch navfn check-bag` as a user runs it: on the bundled example bag (a rosbag2 folder,
//! sqlite3 storage, written by rosbags from the warehouse example with two plans of vouch and
//! one that cuts through a shelf) and on bags written here by rosbags and mcap-ros2-support;
//! exit codes 0 / 1 / 2 / 3, `--json`, a PNG per failing plan.

mod common;

use common::{code, vouch_at_root as vouch};
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};
use vouch_navfn::maps::{WorldParams, load_ros_map};
use vouch_navfn::planner::{NavfnPlanner, PlannerParams, Pose};

const BAG: &str = "examples/navfn/warehouse_bag";

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("navfn_check_bag");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    dir.join(name)
}

fn pose_json(p: &Pose) -> Value {
    let (q, o) = (p.position, p.orientation);
    json!([q[0], q[1], q[2], o[0], o[1], o[2], o[3]])
}

/// The example's messages: the warehouse map, then two requests answered by vouch's planner
/// and a third whose plan is replaced by a straight line through the shelves.
fn example_spec() -> Value {
    let map = load_ros_map(&repo().join("examples/navfn/warehouse.yaml"), true).expect("map");
    let world = WorldParams {
        origin: map.world().origin,
        resolution: map.world().resolution as f32 as f64,
    };
    let mut planner =
        NavfnPlanner::new(&map.costmap, map.width, map.height, world, PlannerParams::default())
            .expect("planner");
    let origin = [world.origin[0], world.origin[1], 0.0, 0.0, 0.0, 0.0, 1.0];
    let mut msgs = vec![json!({
        "t": 1_000_000_000u64, "topic": "/map", "kind": "occupancy_grid", "width": map.width,
        "height": map.height, "resolution": world.resolution as f32, "origin": origin,
        "data": map.occupancy,
    })];
    let requests = [([1.0, 1.0], [8.5, 6.5]), ([8.5, 1.0], [1.0, 6.5]), ([1.0, 1.0], [8.5, 6.5])];
    for (k, (s, g)) in requests.into_iter().enumerate() {
        let start = Pose::from_xy_yaw(s[0], s[1], 0.0);
        let goal = Pose::from_xy_yaw(g[0], g[1], 1.0);
        let mut poses = planner.create_plan_poses(&start, &goal).poses;
        if k == 2 {
            // the straight line from start to goal, in half-cell steps
            let first = poses[0];
            let n = 200;
            poses = (0..=n)
                .map(|i| {
                    let t = i as f64 / n as f64;
                    let x = first.position[0] + (g[0] - first.position[0]) * t;
                    let y = first.position[1] + (g[1] - first.position[1]) * t;
                    Pose::from_xy_yaw(x, y, 0.0)
                })
                .collect();
            poses[n].orientation = goal.orientation;
        }
        let t = 10_000_000_000u64 * (k as u64 + 1);
        msgs.push(json!({"t": t, "topic": "/goal_pose", "kind": "pose_stamped", "pose": pose_json(&goal)}));
        msgs.push(json!({"t": t + 1, "topic": "/amcl_pose", "kind": "pose_cov", "pose": pose_json(&start)}));
        let ps: Vec<Value> = poses.iter().map(pose_json).collect();
        msgs.push(json!({"t": t + 50_000_000, "topic": "/plan", "kind": "path", "poses": ps}));
    }
    json!({ "messages": msgs })
}

fn write_bag(py: &str, out: &Path, format: &str) {
    let spec = tmp(&format!("{format}.json"));
    std::fs::write(&spec, example_spec().to_string()).expect("spec");
    let script = repo().join("crates/vouch-navfn/tests/bags/write_bag.py");
    let o = Command::new(py).arg(script).arg(&spec).arg(out).arg(format).output().expect("python");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The bundled bag: two plans pass and replay bit-identically, the third fails (exit 3).
#[test]
fn the_example_bag_has_one_failing_plan_and_its_picture() {
    let png_dir = tmp("pictures");
    let _ = std::fs::remove_dir_all(&png_dir);
    let o = vouch(&["navfn", "check-bag", BAG, "--png-dir", png_dir.to_str().expect("utf-8")]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(code(&o), 3, "{out}{}", String::from_utf8_lossy(&o.stderr));
    let lines: Vec<&str> = out.lines().filter(|l| l.starts_with("plan ")).collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].contains(": ok,") && lines[0].contains("replay equal"), "{out}");
    assert!(lines[1].contains(": ok,") && lines[1].contains("replay equal"), "{out}");
    assert!(lines[2].contains("FAILED") && lines[2].contains("replay different"), "{out}");
    assert!(out.contains("lies in an obstacle (ValidPath)"), "{out}");
    assert!(out.contains("summary: 3 plans, 2 passed, 1 failed"), "{out}");
    let pictures: Vec<_> = std::fs::read_dir(&png_dir).expect("png dir").flatten().collect();
    assert_eq!(pictures.len(), 1);
    let png = std::fs::read(png_dir.join("plan-2.png")).expect("plan-2.png");
    assert!(png.starts_with(b"\x89PNG"));

    let o = vouch(&["navfn", "check-bag", BAG, "--json"]);
    assert_eq!(code(&o), 3);
    let v: Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    assert_eq!(v["summary"]["replay_equal"].as_u64(), Some(2));
    assert_eq!(v["version"], 2);
    assert_eq!(v["replay_mode"], "check");
    assert_eq!(v["plans"][0]["replay"]["verdict"], "equal");
    assert_eq!(v["plans"][2]["violations"][0]["kind"], "pose_in_obstacle");
    assert!(v["plans"][2]["violations"][0]["index"].is_u64());
}

#[test]
fn unreadable_and_malformed_bags_exit_2_and_1() {
    let o = vouch(&["navfn", "check-bag", "no/such/bag"]);
    assert_eq!(code(&o), 2);
    let junk = tmp("junk.mcap");
    std::fs::write(&junk, b"\x89MCAP0\r\nnot really").expect("written");
    let o = vouch(&["navfn", "check-bag", junk.to_str().expect("utf-8")]);
    assert_eq!(code(&o), 1, "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("navfn::E032"));
    let text = tmp("notes.db3");
    std::fs::write(&text, "plain text").expect("written");
    let o = vouch(&["navfn", "check-bag", text.to_str().expect("utf-8")]);
    assert_eq!(code(&o), 1);
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a rosbag2 bag"));
}

/// The same recording written by each writer gives the same verdicts; `--replay off` keeps the
/// property failures. With `VOUCH_BLESS_EXAMPLE_BAG=1` the sqlite3 bag is written to
/// `examples/navfn/warehouse_bag`.
#[test]
fn bags_from_every_writer_give_the_same_verdicts() {
    let Some(py) = vouch_testkit::python_with(&["rosbags", "mcap_ros2", "numpy"]) else { return };
    if std::env::var("VOUCH_BLESS_EXAMPLE_BAG").is_ok_and(|v| v == "1") {
        let out = repo().join(BAG);
        let _ = std::fs::remove_dir_all(&out);
        write_bag(&py, &out, "sqlite3");
    }
    for format in ["sqlite3", "mcap", "mcap_ros2"] {
        let out = tmp(&format!("bag-{format}"));
        let out = if format == "mcap_ros2" { out.with_extension("mcap") } else { out };
        let _ = std::fs::remove_dir_all(&out);
        let _ = std::fs::remove_file(&out);
        write_bag(&py, &out, format);
        let o = vouch(&["navfn", "check-bag", out.to_str().expect("utf-8"), "--json"]);
        assert_eq!(code(&o), 3, "{format}");
        let v: Value = serde_json::from_slice(&o.stdout).expect("JSON");
        assert_eq!(v["summary"]["passed"].as_u64(), Some(2), "{format}");
        assert_eq!(v["summary"]["replay_equal"].as_u64(), Some(2), "{format}");
        let o = vouch(&["navfn", "check-bag", out.to_str().expect("utf-8"), "--replay", "off"]);
        assert_eq!(code(&o), 3, "{format}: the obstacle is a property failure");
    }
}
