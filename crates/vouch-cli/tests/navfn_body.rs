//! The robot's body: `vouch navfn costmap` (nav2's inflation, against the goldens of nav2's
//! layer), `plan --robot-radius/--footprint` (planning on the inflated costmap, the swept body
//! checked against the static map) and `check-bag` with a footprint.

mod common;

use common::{code, vouch_at_root as vouch};
use serde_json::Value;

const CIRCULAR: &str = "../shared/navfn/nav2_maps/map_circular.yaml";

fn shared() -> bool {
    vouch_testkit::shared("navfn", "SEMANTICS.md").is_some()
}

fn json(o: &std::process::Output) -> Value {
    serde_json::from_slice(&o.stdout).expect("JSON on stdout")
}

#[test]
fn costmap_command_writes_nav2_layer_bytes() {
    if !shared() {
        return;
    }
    let out = std::env::temp_dir().join(format!("vouch-costmap-{}.bin", std::process::id()));
    let o = vouch(&[
        "navfn",
        "costmap",
        CIRCULAR,
        "--robot-radius",
        "0.22",
        "--inflation-radius",
        "0.55",
        "--cost-scaling-factor",
        "3.0",
        "-o",
        out.to_str().expect("utf-8"),
        "--json",
    ]);
    assert_eq!(code(&o), 0, "{}", String::from_utf8_lossy(&o.stderr));
    // the golden of nav2's layer for map_circular × p1 (crates/vouch-navfn/tests/data/inflation)
    let golden = "6c105d83d8c3544590a8ce8c40a02dbe582b0ef1a2d4ebd2c9486315a6c6fe87";
    assert_eq!(json(&o)["sha256"], golden);
    let bytes = std::fs::read(&out).expect("written");
    assert_eq!(bytes.len(), 384 * 384);
    let _ = std::fs::remove_file(out);
}

fn plan(inflation: &str) -> std::process::Output {
    vouch(&[
        "navfn",
        "plan",
        CIRCULAR,
        "--start",
        "-8,-8",
        "--goal",
        "8,8",
        "--robot-radius",
        "0.3",
        "--inflation-radius",
        inflation,
        "--cost-scaling-factor",
        "3",
        "--checked",
        "--json",
    ])
}

/// A body of radius 0.3 m on a costmap inflated by only 0.1 m: NavFn's path may pass 0.15 m
/// from a wall, so the body touches it; inflated by 0.55 m (beyond the body), every cell within
/// 0.3 m of a wall costs 253 or more and the plan keeps the body clear.
#[test]
fn body_touches_walls_when_inflation_is_smaller_than_the_robot() {
    if !shared() {
        return;
    }
    let o = plan("0.1");
    assert_eq!(code(&o), 3, "{}", String::from_utf8_lossy(&o.stdout));
    let v = json(&o);
    let contacts = v["body"]["violations"].as_array().expect("violations");
    assert!(!contacts.is_empty());
    assert_eq!(v["body"]["min"]["clearance"], 0.0);

    let o = plan("0.55");
    assert_eq!(code(&o), 0, "{}", String::from_utf8_lossy(&o.stdout));
    let v = json(&o);
    assert!(v["body"]["violations"].as_array().expect("violations").is_empty());
    let clearance = v["body"]["min"]["clearance"].as_f64().expect("a clearance");
    assert!(clearance > 0.0 && clearance < 2.0, "{clearance}");
}

#[test]
fn check_bag_reports_body_contacts() {
    let bag = "examples/navfn/warehouse_bag";
    let o = vouch(&["navfn", "check-bag", bag, "--replay", "off", "--json"]);
    let without = json(&o);
    let o =
        vouch(&["navfn", "check-bag", bag, "--replay", "off", "--json", "--robot-radius", "1.0"]);
    assert_eq!(code(&o), 3);
    let with = json(&o);
    let contacts = |v: &Value, i: usize| {
        v["plans"][i]["violations"]
            .as_array()
            .expect("violations")
            .iter()
            .filter(|x| x["kind"] == "body_contact" || x.get("BodyContact").is_some())
            .count()
    };
    // the plans were made for a point robot on an uninflated map: a body 2 m wide touches shelves
    assert_eq!(contacts(&without, 0), 0);
    assert!(contacts(&with, 0) > 0, "{}", with["plans"][0]["violations"]);
    assert!(with["plans"][0]["body"]["min"].is_object());
}

#[test]
fn bad_footprints_are_rejected_with_a_code() {
    let o =
        vouch(&["navfn", "costmap", "examples/navfn/warehouse.yaml", "--footprint", "[[1,2],[3]]"]);
    assert_eq!(code(&o), 1);
    assert!(String::from_utf8_lossy(&o.stderr).contains("navfn::E120"));
    let o = vouch(&[
        "navfn",
        "costmap",
        "examples/navfn/warehouse.yaml",
        "--robot-radius",
        "0.2",
        "--inflation-radius=-1",
    ]);
    assert_eq!(code(&o), 1);
    assert!(String::from_utf8_lossy(&o.stderr).contains("navfn::E121"));
}
