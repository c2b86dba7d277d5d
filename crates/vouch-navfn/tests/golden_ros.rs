//! The five nav2 maps as ROS costmaps (`shared/navfn/suite_ros`), bit-exact against
//! `shared/navfn/golden/ros/`: navfn mode with the ROS cost conversion, and the world-level
//! planner emulation, each with Dijkstra and A*.

mod common;

use vouch_navfn::core::Algo;
use vouch_navfn::maps::{read_suite_file, read_world_params};
use vouch_navfn::planner::WorldParams;
use vouch_navfn::suite::{CostInput, SuiteMode, SuiteOptions, run_file};

const MAPS: [(&str, usize, usize); 5] = [
    // (map, navfn cases, planner cases) as listed in golden/README.md
    ("400x400_ros", 56, 56),
    ("empty_room", 54, 54),
    ("keepout_mask", 55, 55),
    ("map_circular", 55, 54),
    ("speed_mask", 65, 65),
];

fn check(mode: SuiteMode, algo: Algo) {
    let Some(shared) = common::shared_navfn() else { return };
    let (mode_name, test_name) = match mode {
        SuiteMode::Planner => ("planner", "test_world.txt"),
        _ => ("navfn", "test.txt"),
    };
    let algo_name = if algo == Algo::Astar { "astar" } else { "dijkstra" };
    let mut failures = Vec::new();
    let (mut total, mut equal) = (0, 0);
    for (map, navfn_cases, planner_cases) in MAPS {
        let dir = shared.join("suite_ros").join(map);
        let file = read_suite_file(&dir.join(test_name)).expect("suite_ros file parses");
        let world = match mode {
            SuiteMode::Planner => read_world_params(&dir.join("params.txt")).expect("params"),
            _ => WorldParams::default(),
        };
        let opts = SuiteOptions { mode, algo, costs: CostInput::Ros, world };
        let mut out = String::new();
        run_file(&file, &opts, &mut out).expect("cases run");
        let golden_path =
            shared.join("golden/ros").join(format!("ros_{map}_{mode_name}_{algo_name}.hex.txt"));
        let golden = std::fs::read_to_string(&golden_path).expect("golden present");
        let (n, eq, diff) = common::compare(&out, &golden);
        let want = if mode == SuiteMode::Planner { planner_cases } else { navfn_cases };
        assert_eq!(n, want, "{map}: golden case count");
        total += n;
        equal += eq;
        if let Some(d) = diff {
            failures.push(format!("{map}: {eq}/{n} equal; first difference {d}"));
        }
    }
    println!("ros {mode_name} {algo_name}: {equal} / {total} cases bit-exact");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn ros_navfn_dijkstra() {
    check(SuiteMode::Navfn, Algo::Dijkstra);
}
#[test]
fn ros_navfn_astar() {
    check(SuiteMode::Navfn, Algo::Astar);
}
#[test]
fn ros_planner_dijkstra() {
    check(SuiteMode::Planner, Algo::Dijkstra);
}
#[test]
fn ros_planner_astar() {
    check(SuiteMode::Planner, Algo::Astar);
}
