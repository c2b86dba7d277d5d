//! Inflation and the body check from C: `tests/c/costmap_body.c`, compiled with the system's
//! `cc` against `include/vouch_navfn.h` and the cdylib, inflates map_server maps (the bundled
//! warehouse; the nav2 maps of ../shared when present) to the bytes the library's
//! `inflated_costmap` gives in this process (what `vouch navfn costmap` writes; the library is
//! held to nav2's own layer by `vouch-navfn/tests/costmap_inflation.rs`), checks bodies on a
//! crafted wall with contacts and clearances worked out by hand and on a planned path against
//! the library's `BodyCheck` (what `vouch navfn plan` reports), and gets codes and messages for
//! bad input.

mod common;

use std::path::Path;

use common::{program, run, serial};
use vouch_navfn::costmap::{
    Body, BodyCheck, DEFAULT_PADDING, Footprint, FootprintSpec, InflationParams, inflated_costmap,
};
use vouch_navfn::maps::{RosMap, WorldParams, load_ros_map};
use vouch_navfn::planner::{NavfnPlanner, PlannerParams, Pose};

const RECTANGLE: &str = "[[0.3,0.25],[0.3,-0.25],[-0.3,-0.25],[-0.3,0.25]]";

/// One inflation request: robot (radius or footprint string), radius, k, the two unknown
/// flags, padding.
struct Inflation {
    robot: &'static str,
    radius: f64,
    k: f64,
    unknown: bool,
    around: bool,
    padding: f64,
}

/// The C program's bytes for `case` on `map`, and the library's.
fn inflate_both(prog: &Path, map: &RosMap, case: &Inflation) -> (Vec<u8>, Vec<u8>) {
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).expect("temporary directory");
    let (bin, out) = (dir.path().join("map.bin"), dir.path().join("out.bin"));
    std::fs::write(&bin, &map.costmap).expect("map written");
    let flag = |b: bool| if b { "1" } else { "0" };
    // `{:?}` prints the shortest decimal that reads back as the same double
    let args = [
        "inflate".to_string(),
        bin.display().to_string(),
        map.width.to_string(),
        map.height.to_string(),
        format!("{:?}", map.meta.resolution),
        case.robot.to_string(),
        out.display().to_string(),
        format!("{:?}", case.radius),
        format!("{:?}", case.k),
        flag(case.unknown).to_string(),
        flag(case.around).to_string(),
        format!("{:?}", case.padding),
    ];
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    run(prog, &args, "");
    let from_c = std::fs::read(&out).expect("the C program's output");
    let footprint = if case.robot.starts_with('[') {
        Footprint::from_polygon_str(case.robot, case.padding)
    } else {
        Footprint::from_radius(case.robot.parse().expect("a radius"), case.padding)
    }
    .expect("footprint");
    let params = InflationParams {
        inflation_radius: case.radius,
        cost_scaling_factor: case.k,
        inflate_unknown: case.unknown,
        inflate_around_unknown: case.around,
    };
    (from_c, inflated_costmap(map, &footprint, params).expect("library inflation"))
}

#[test]
fn inflation_from_c_equals_the_library_byte_for_byte() {
    let _one_at_a_time = serial();
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let prog = program(&cc, "costmap_body");
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let pad = DEFAULT_PADDING;
    let warehouse = load_ros_map(&repo.join("examples/navfn/warehouse.yaml"), true).expect("map");
    let mut maps = vec![("warehouse", warehouse)];
    if let Some(shared) = vouch_testkit::shared("navfn", "SEMANTICS.md") {
        for name in ["map_circular", "keepout_mask"] {
            let yaml = shared.join(format!("nav2_maps/{name}.yaml"));
            maps.push((name, load_ros_map(&yaml, true).expect("nav2 map")));
        }
    }
    let cases = [
        Inflation {
            robot: "0.22",
            radius: 0.55,
            k: 3.0,
            unknown: false,
            around: false,
            padding: pad,
        },
        Inflation {
            robot: RECTANGLE,
            radius: 1.0,
            k: 2.5,
            unknown: false,
            around: true,
            padding: pad,
        },
        // the inflation radius below the robot's, both unknown flags, a wider padding
        Inflation {
            robot: "0.5",
            radius: 0.35,
            k: 10.0,
            unknown: true,
            around: true,
            padding: 0.08,
        },
    ];
    // a 0.5 m square without padding on a 0.05 m map: a cell 5 cells from an obstacle is
    // 0.25 m away at 0.05 but not at nav2's float resolution, 0.05000000074505806 (there it
    // costs 251, not 253): the resolution must be read as the map message carries it
    let square = Inflation {
        robot: "[[0.25,0.25],[0.25,-0.25],[-0.25,-0.25],[-0.25,0.25]]",
        radius: 0.55,
        k: 3.0,
        unknown: false,
        around: false,
        padding: 0.0,
    };
    let mut compared = 0;
    for (name, map) in maps.iter().filter(|(name, _)| *name != "warehouse") {
        let (from_c, expected) = inflate_both(&prog, map, &square);
        assert!(from_c == expected, "{name}, square: the C bytes differ from the library's");
        compared += 1;
    }
    for (name, map) in &maps {
        for (i, case) in cases.iter().enumerate() {
            let (from_c, expected) = inflate_both(&prog, map, case);
            assert!(from_c == expected, "{name}, case {i}: the C bytes differ from the library's");
            let changed = expected.iter().zip(&map.costmap).filter(|(a, b)| a != b).count();
            assert!(changed > 100, "{name}, case {i}: only {changed} cells inflated");
            compared += 1;
        }
    }
    eprintln!("{compared} inflated costmaps from C equal to the library's");
    assert!(compared >= 3);
}

/// A 40×30 map at 0.1 m, origin (−1, −0.5): a wall in column 20 (x ∈ [1.0, 1.1]) over rows
/// 0–19 (y ∈ [−0.5, 1.5]), free elsewhere.
fn wall_map() -> (Vec<u8>, usize, usize) {
    let (w, h) = (40, 30);
    let mut costs = vec![0u8; w * h];
    for row in 0..20 {
        costs[row * w + 20] = 254;
    }
    (costs, w, h)
}

/// The C program's body check: the BODY line's fields, the contacts (pose, column, row,
/// clearance), the message.
struct CBody {
    fields: Vec<(String, String)>,
    contacts: Vec<(usize, usize, usize, f64)>,
    message: String,
}

impl CBody {
    fn get(&self, key: &str) -> &str {
        &self.fields.iter().find(|(k, _)| k == key).unwrap_or_else(|| panic!("{key}")).1
    }
    fn num(&self, key: &str) -> f64 {
        self.get(key).parse().expect("a number")
    }
}

fn body_from_c(
    prog: &Path,
    (costs, w, h): (&[u8], usize, usize),
    world: WorldParams,
    robot: &str,
    poses: &[[f64; 3]],
) -> CBody {
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).expect("temporary directory");
    let bin = dir.path().join("map.bin");
    std::fs::write(&bin, costs).expect("map written");
    let stdin: String =
        poses.iter().map(|p| format!("{:?} {:?} {:?}\n", p[0], p[1], p[2])).collect();
    let args = [
        "body".to_string(),
        bin.display().to_string(),
        w.to_string(),
        h.to_string(),
        format!("{:?}", world.origin[0]),
        format!("{:?}", world.origin[1]),
        format!("{:?}", world.resolution),
        robot.to_string(),
        "2.0".to_string(),
    ];
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = run(prog, &args, &stdin);
    let line = |key: &str| out.lines().find(|l| l.starts_with(key)).unwrap_or("").to_string();
    let fields = line("BODY ")
        .split_whitespace()
        .skip(1)
        .filter_map(|t| t.split_once('=').map(|(k, v)| (k.to_string(), v.to_string())))
        .collect();
    let contacts = out
        .lines()
        .filter_map(|l| l.strip_prefix("CONTACT "))
        .map(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            let n = |i: usize| t[i].parse::<usize>().expect("an index");
            (n(0), n(1), n(2), t[3].parse::<f64>().expect("a clearance"))
        })
        .collect();
    let message = line("MESSAGE ").trim_start_matches("MESSAGE").trim().to_string();
    CBody { fields, contacts, message }
}

#[test]
fn the_body_check_from_c_finds_the_wall_and_clears_the_open_side() {
    let _one_at_a_time = serial();
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let prog = program(&cc, "costmap_body");
    let (costs, w, h) = wall_map();
    let world = WorldParams { origin: [-1.0, -0.5], resolution: 0.1 };
    // across the wall at y = 0.5, x from 0 to 2 in steps of 0.25, a disc of 0.2 m: the
    // segments from x = 0.75, 1.0 and 1.25 (poses 3, 4, 5) reach into [1.0, 1.1]; the one from
    // 0.5 stops 0.05 m short, the one from 1.5 passes 0.2 m beyond
    let across: Vec<[f64; 3]> = (0..9).map(|i| [0.25 * i as f64, 0.5, 0.0]).collect();
    let b = body_from_c(&prog, (&costs, w, h), world, "0.2", &across);
    assert_eq!((b.get("ok"), b.get("contacts"), b.get("motions")), ("0", "3", "9"));
    assert_eq!(b.num("clearance"), 0.0);
    let poses: Vec<usize> = b.contacts.iter().map(|c| c.0).collect();
    assert_eq!(poses, [3, 4, 5]);
    assert!(b.contacts.iter().all(|c| c.1 == 20 && c.2 < 20 && c.3 == 0.0), "{:?}", b.contacts);
    assert!(
        b.message.starts_with("body contact: pose 3 → 4 touches lethal cell 20,"),
        "{}",
        b.message
    );
    // beside the wall, x = 0, y from 0 to 1: 1.0 m to the wall's face, 0.8 m beyond the disc
    let beside: Vec<[f64; 3]> =
        (0..5).map(|i| [0.0, 0.25 * i as f64, std::f64::consts::FRAC_PI_2]).collect();
    let b = body_from_c(&prog, (&costs, w, h), world, "0.2", &beside);
    assert_eq!((b.get("ok"), b.get("contacts"), b.get("has_min")), ("1", "0", "1"));
    assert!((b.num("clearance") - 0.8).abs() < 1e-12, "{}", b.num("clearance"));
    assert!(b.get("cell").starts_with("20,"), "{}", b.get("cell"));
    assert!(b.contacts.is_empty() && b.message.is_empty());
    // the 0.6×0.5 m rectangle facing +y along that line: its side (0.25 m from its centre)
    // is 0.75 m from the wall
    let b = body_from_c(&prog, (&costs, w, h), world, RECTANGLE, &beside);
    assert_eq!(b.get("ok"), "1");
    assert!((b.num("clearance") - 0.75).abs() < 1e-12, "{}", b.num("clearance"));
}

#[test]
fn the_body_check_from_c_equals_the_library_on_a_plan() {
    let _one_at_a_time = serial();
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let prog = program(&cc, "costmap_body");
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let map = load_ros_map(&repo.join("examples/navfn/warehouse.yaml"), true).expect("map");
    // as `vouch navfn plan --robot-radius 0.3 --inflation-radius 0.1`: a plan on the costmap
    // inflated less than the robot, so that it grazes the shelves
    let footprint = Footprint::from_radius(0.3, DEFAULT_PADDING).expect("footprint");
    let params = InflationParams { inflation_radius: 0.1, ..InflationParams::default() };
    let costs = inflated_costmap(&map, &footprint, params).expect("inflation");
    let mut planner =
        NavfnPlanner::new(&costs, map.width, map.height, map.world(), PlannerParams::default())
            .expect("planner");
    let poses = planner
        .create_plan_poses(&Pose::from_xy_yaw(1.0, 1.0, 0.0), &Pose::from_xy_yaw(8.5, 6.5, 0.0))
        .poses;
    let xyyaw: Vec<[f64; 3]> =
        poses.iter().map(|p| [p.position[0], p.position[1], p.yaw()]).collect();
    assert!(xyyaw.len() > 50);
    // the body as `vouch navfn plan` takes it: the disc, or the polygon's numbers read as floats
    // and widened (nav2's footprint parameter)
    let polygon = match Footprint::from_polygon_str(RECTANGLE, 0.0).expect("footprint").spec {
        FootprintSpec::Polygon(p) => p,
        FootprintSpec::Radius(_) => unreachable!("a polygon string"),
    };
    assert_ne!(polygon[0][0], 0.3, "floats widened");
    for (robot, body) in [("0.3", Body::Disc(0.3)), (RECTANGLE, Body::Polygon(polygon))] {
        let lib = BodyCheck {
            costs: &map.costmap,
            width: map.width,
            height: map.height,
            world: map.world(),
            body,
            window: 2.0,
        }
        .check(&xyyaw);
        let b =
            body_from_c(&prog, (&map.costmap, map.width, map.height), map.world(), robot, &xyyaw);
        let min = lib.min.expect("a lethal cell within 2 m");
        assert_eq!(b.get("ok"), if lib.is_ok() { "1" } else { "0" }, "{robot}");
        assert_eq!(b.get("contacts"), lib.violations.len().to_string(), "{robot}");
        assert_eq!(b.get("motions"), lib.motions.to_string(), "{robot}");
        assert_eq!(b.num("clearance").to_bits(), min.clearance.to_bits(), "{robot}");
        assert_eq!(b.get("pose"), min.pose.to_string(), "{robot}");
        assert_eq!(b.get("cell"), format!("{},{}", min.cell[0], min.cell[1]), "{robot}");
        let expected: Vec<_> =
            lib.violations.iter().map(|v| (v.pose, v.cell[0], v.cell[1], v.clearance)).collect();
        assert_eq!(b.contacts, expected, "{robot}");
    }
}

#[test]
fn bad_input_comes_back_as_codes_and_messages() {
    let _one_at_a_time = serial();
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let out = run(&program(&cc, "costmap_body"), &["errors"], "");
    let line = |key: &str| {
        out.lines()
            .find(|l| l.starts_with(&format!("{key} ")))
            .unwrap_or_else(|| panic!("{key}\n{out}"))
            .to_string()
    };
    for (key, starts) in [
        ("inflate_null_costs", "1 costs is NULL"),
        ("inflate_null_out", "1 out is NULL"),
        ("inflate_short_costs", "2 3 costs given, a 4x4 map has 16 cells"),
        ("inflate_small_buffer", "5 the buffer holds 8 bytes, 16 are needed"),
        ("inflate_bad_footprint", "2 navfn::E120: footprint `[[1,1],[1,-1]`"),
        ("inflate_two_points", "2 navfn::E120: footprint `[[1,1],[1,-1]]`"),
        ("inflate_negative_radius", "2 navfn::E121: robot_radius = -1 is out of range"),
        ("inflate_bad_resolution", "2 navfn::E121: resolution = 0 is out of range"),
        ("inflate_negative_k", "2 navfn::E121: cost_scaling_factor = -2 is out of range"),
        ("inflate_negative_padding", "2 navfn::E121: footprint_padding = -0.5 is out of range"),
        ("inflate_ok", "0 "),
        ("body_null_costs", "1 costs is NULL"),
        ("body_null_report", "1 report is NULL"),
        ("body_null_yaw", "1 yaw is NULL"),
        ("body_long_costs", "2 16 costs given, a 3x4 map has 12 cells"),
        ("body_empty_map", "2 a 0x4 map has no cells"),
        ("body_bad_footprint", "2 navfn::E120: footprint `[[0,0],[1,x]]`"),
        ("body_negative_radius", "2 navfn::E121: robot_radius = -0.3 is out of range"),
        ("body_nan_pose", "2 pose 1 (NaN, 0.5, 0) is not finite"),
        ("body_negative_window", "2 window -1 must be finite and ≥ 0"),
        ("body_bad_resolution", "2 resolution 0 must be finite and > 0"),
        ("body_no_poses", "0 "),
        ("body_clear", "0 "),
        ("body_small_buffer", "5 the buffer holds 0 contacts, 1 found"),
        ("body_contact", "0 body contact: pose 0 → 1 touches lethal cell 1,1"),
    ] {
        let l = line(key);
        assert!(l[key.len() + 1..].starts_with(starts), "{key}: {l}");
    }
    assert_eq!(line("body_no_poses_report"), "body_no_poses_report ok=1 motions=0");
    let clear = line("body_clear_report");
    assert!(clear.starts_with("body_clear_report ok=1 contacts=0 clearance=0.2"), "{clear}");
    assert_eq!(line("body_small_buffer_report"), "body_small_buffer_report ok=0 contacts=1");
    assert_eq!(line("body_contact_report"), "body_contact_report ok=0 contacts=1 cell=1,1");
}
