//! A C program compiled with the system's `cc` against `include/vouch_navfn.h` and the cdylib
//! plans on the five nav2 maps: as ROS costmaps (`suite_ros`) its status, NavFn path length,
//! potential hash, NavFn path and world poses equal the original C++ planner's goldens — the
//! lines `vouch navfn suite run --mode planner` reproduces — for every world case; as map_server
//! maps (YAML) its poses and orientations equal the library's (what `vouch navfn plan` prints);
//! every error comes back as a code and a message.

mod common;

use std::path::Path;
use std::process::Command;

use common::{build_dir, lib_dir, run, serial};

use vouch_navfn::maps::load_ros_map;
use vouch_navfn::planner::{NavfnPlanner, PlannerParams, Pose};

/// Cases of a test_world.txt (after its 3-line header; a line whose first number is exactly
/// −1 is a comment, as in the golden runs).
fn world_cases(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("test_world.txt")).expect("test_world.txt");
    let case = |l: &&str| {
        let first = l.split_whitespace().next().and_then(|t| t.parse::<f64>().ok());
        l.split_whitespace().count() == 4 && first != Some(-1.0)
    };
    text.lines().skip(3).filter(case).map(|l| format!("{l}\n")).collect()
}

fn field<'a>(line: &'a str, key: &str) -> &'a str {
    line.split_whitespace()
        .find_map(|t| t.strip_prefix(key).and_then(|r| r.strip_prefix('=')))
        .unwrap_or_else(|| panic!("{key} in {line}"))
}

#[test]
fn the_c_program_reproduces_the_cpp_planner_on_every_nav2_costmap() {
    let _one_at_a_time = serial();
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let prog = common::program(&cc, "plan_maps");
    let mut compared = 0;
    for (name, w, h, origin, res) in [
        ("400x400_ros", 400, 400, "0.0", "1.0"),
        ("empty_room", 200, 200, "-10.0", "0.1"),
        ("keepout_mask", 384, 384, "-10.0", "0.05"),
        ("map_circular", 384, 384, "-10.0", "0.05"),
        ("speed_mask", 384, 384, "-10.0", "0.05"),
    ] {
        let dir = shared.join("suite_ros").join(name);
        let bin = dir.join("map.bin");
        let (ws, hs) = (w.to_string(), h.to_string());
        let args = ["bin", bin.to_str().expect("utf-8"), &ws, &hs, origin, origin, res];
        let out = run(&prog, &args, &world_cases(&dir));
        let golden_path = shared.join(format!("golden/ros/ros_{name}_planner_dijkstra.hex.txt"));
        let golden = std::fs::read_to_string(golden_path).expect("golden");
        let g: Vec<&str> = golden.lines().filter(|l| !l.starts_with("MAP")).collect();
        let c: Vec<&str> = out.lines().filter(|l| !l.starts_with("CHECK")).collect();
        assert_eq!(c.len(), g.len(), "{name}: line count");
        for (gl, cl) in g.iter().zip(&c) {
            if gl.starts_with("CASE") {
                for key in ["status", "len", "pot_fnv"] {
                    assert_eq!(field(cl, key), field(gl, key), "{name}: {key}\n{gl}\n{cl}");
                }
                compared += 1;
            } else {
                assert_eq!(cl.trim_end(), gl.trim_end(), "{name}");
            }
        }
        assert!(
            out.lines().filter(|l| l.starts_with("CHECK")).all(|l| l == "CHECK 0"),
            "{name}: checks"
        );
    }
    eprintln!("{compared} world cases equal to the C++ goldens");
    assert!(compared > 250);
}

/// Cell plans on NavFn costs (the paper suite's nav2 maps and three spirals) equal the C++
/// NavFn's goldens in the planner's cell-level call sequence (`navfn_dijkstra.txt`).
#[test]
fn cell_plans_on_navfn_costs_equal_the_cpp_navfn() {
    let _one_at_a_time = serial();
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let prog = common::program(&cc, "plan_maps");
    let mut compared = 0;
    for dir in [
        "ROS/400x400_ros",
        "ROS/empty_room",
        "ROS/keepout_mask",
        "spiral/11x11_spiral",
        "spiral/14x17_spiral_random",
    ] {
        let suite = shared.join("suite").join(dir);
        let text = std::fs::read_to_string(suite.join("test.txt")).expect("test.txt");
        let mut lines = text.lines();
        let size: Vec<&str> = lines.next().expect("size").split_whitespace().collect();
        let map = suite.join(lines.next().expect("map name").trim());
        let cases: String = lines
            .skip(1)
            .filter(|l| l.split_whitespace().count() == 4 && !l.starts_with("-1"))
            .map(|l| format!("{l}\n"))
            .collect();
        let out = run(&prog, &["navfn", map.to_str().expect("utf-8"), size[0], size[1]], &cases);
        let golden =
            std::fs::read_to_string(shared.join("golden").join(dir).join("navfn_dijkstra.txt"))
                .expect("golden");
        let g: Vec<&str> =
            golden.lines().filter(|l| l.starts_with("CASE") || l.starts_with("PATH")).collect();
        let c: Vec<&str> = out.lines().collect();
        assert_eq!(c.len(), g.len(), "{dir}: line count");
        for (gl, cl) in g.iter().zip(&c) {
            if gl.starts_with("CASE") {
                for key in ["len", "pot_fnv"] {
                    assert_eq!(field(cl, key), field(gl, key), "{dir}: {key}\n{gl}\n{cl}");
                }
                compared += 1;
            } else {
                assert_eq!(cl.trim_end(), gl.trim_end(), "{dir}");
            }
        }
    }
    eprintln!("{compared} NavFn-cost cell cases equal to the C++ goldens");
    assert!(compared > 100);
}

#[test]
fn the_c_program_reads_map_server_maps_like_the_library() {
    let _one_at_a_time = serial();
    let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") else { return };
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let prog = common::program(&cc, "plan_maps");
    for (yaml, folder) in [
        ("empty_room.yaml", "empty_room"),
        ("keepout_mask.yaml", "keepout_mask"),
        ("map_circular.yaml", "map_circular"),
        ("speed_mask.yaml", "speed_mask"),
    ] {
        let path = shared.join("nav2_maps").join(yaml);
        let cases: String = world_cases(&shared.join("suite_ros").join(folder))
            .lines()
            .rev()
            .take(5)
            .map(|l| format!("{l}\n"))
            .collect();
        let out = run(&prog, &["yaml", path.to_str().expect("utf-8")], &cases);
        // the same requests through the library (vouch navfn plan's code path)
        let map = load_ros_map(&path, true).expect("map");
        let mut p = NavfnPlanner::new(
            &map.costmap,
            map.width,
            map.height,
            map.world(),
            PlannerParams::default(),
        )
        .expect("planner");
        let mut expected: Vec<Vec<f64>> = Vec::new();
        for l in cases.lines() {
            let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().expect("number")).collect();
            let start = Pose::from_xy_yaw(v[0], v[1], 0.0);
            let goal = Pose { position: [v[2], v[3], 0.0], orientation: [0.0, 0.0, 0.6, 0.8] };
            let poses = p.create_plan_poses(&start, &goal).poses;
            expected.push(vec![poses.len() as f64]);
            for q in &poses {
                expected.push(vec![
                    q.position[0],
                    q.position[1],
                    q.orientation[2],
                    q.orientation[3],
                ]);
            }
            expected.push(vec![0.0]);
        }
        // %.17g prints every double exactly: parsed back, the values must be bit-identical
        let got: Vec<Vec<f64>> = out
            .lines()
            .map(|l| l.split_whitespace().filter_map(|t| t.parse::<f64>().ok()).collect())
            .collect();
        let bits = |rows: &[Vec<f64>]| -> Vec<Vec<u64>> {
            rows.iter().map(|r| r.iter().map(|x| x.to_bits()).collect()).collect()
        };
        assert!(
            bits(&got) == bits(&expected),
            "{yaml}: the C program's poses differ from the library's"
        );
        assert!(got.len() > 50, "{yaml}: too few poses compared");
    }
}

#[test]
fn errors_come_back_as_codes_and_messages() {
    let _one_at_a_time = serial();
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let out = run(&common::program(&cc, "plan_maps"), &["errors"], "");
    let line = |key: &str| {
        out.lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("{key}\n{out}"))
            .to_string()
    };
    assert!(line("null_costs ").starts_with("null_costs 1 costs is NULL"), "{out}");
    assert!(line("bad_resolution ").starts_with("bad_resolution 2 world frame"), "{out}");
    assert!(line("bad_tolerance ").starts_with("bad_tolerance 2 tolerance -1"), "{out}");
    assert!(
        line("missing_map ").starts_with("missing_map 3 ")
            && line("missing_map ").contains("no/such/map.yaml"),
        "{out}"
    );
    assert_eq!(line("created "), "created 0");
    assert!(
        line("world_on_navfn_costs ").starts_with("world_on_navfn_costs 2 world plans need"),
        "{out}"
    );
    assert!(line("cell_off_map ").starts_with("cell_off_map 2 goal cell (7, 7)"), "{out}");
    assert!(
        line("no_result ").starts_with("no_result 0"),
        "an empty result is not an error: {out}"
    );
    assert!(line("null_planner ").starts_with("null_planner 1 planner is NULL"), "{out}");
    assert!(line("short_costmap ").starts_with("short_costmap 2 4 costs given"), "{out}");
}

/// README's C example compiles against the header and prints what the library computes.
#[test]
fn the_readme_c_example_runs() {
    let _one_at_a_time = serial();
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = build_dir().join("plan_warehouse");
    let lib = lib_dir();
    let o = Command::new(&cc)
        .args(["-std=c99", "-Wall", "-Werror", "-I"])
        .arg(crate_dir.join("include"))
        .arg(repo.join("examples/navfn/plan_warehouse.c"))
        .arg("-L")
        .arg(&lib)
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .args(["-lvouch_navfn_c", "-o"])
        .arg(&exe)
        .output()
        .expect("cc runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let yaml = repo.join("examples/navfn/warehouse.yaml");
    let out = run(&exe, &[yaml.to_str().expect("utf-8")], "");
    let map = load_ros_map(&repo.join("examples/navfn/warehouse.yaml"), true).expect("map");
    let params = PlannerParams { use_final_approach_orientation: true, ..Default::default() };
    let mut p = NavfnPlanner::new(&map.costmap, map.width, map.height, map.world(), params)
        .expect("planner");
    let poses = p
        .create_plan_poses(&Pose::from_xy_yaw(1.0, 1.0, 0.0), &Pose::from_xy_yaw(8.5, 6.5, 0.0))
        .poses;
    let last = poses[poses.len() - 1];
    let expected = format!(
        "{} poses, last ({:.3}, {:.3}) facing qz={:.4} qw={:.4}, 0 violations\n",
        poses.len(),
        last.position[0],
        last.position[1],
        last.orientation[2],
        last.orientation[3]
    );
    assert_eq!(out, expected);
}
