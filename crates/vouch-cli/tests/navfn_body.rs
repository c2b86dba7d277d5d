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
    let scratch = tempfile::tempdir().expect("scratch directory");
    let out = scratch.path().join("costmap.bin");
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
}

/// `vouch navfn plan` across map_circular, from (−8, −8) to (8, 8) on a costmap inflated with
/// a cost scaling factor of 3, with `body` (the robot, the inflation radius, outputs).
fn plan_across(body: &[&str]) -> std::process::Output {
    let mut args = vec![
        "navfn",
        "plan",
        CIRCULAR,
        "--start",
        "-8,-8",
        "--goal",
        "8,8",
        "--cost-scaling-factor",
        "3",
    ];
    args.extend_from_slice(body);
    vouch(&args)
}

/// [`plan_across`] with a disc robot of radius 0.3 m on a costmap inflated by `inflation`.
fn disc_plan(inflation: &str, outputs: &[&str]) -> std::process::Output {
    let mut args = vec!["--robot-radius", "0.3", "--inflation-radius", inflation];
    args.extend_from_slice(outputs);
    plan_across(&args)
}

fn plan(inflation: &str) -> std::process::Output {
    disc_plan(inflation, &["--checked", "--json"])
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
    let scratch = tempfile::tempdir().expect("scratch directory");
    let png = scratch.path().join("body.png");
    let text = disc_plan("0.1", &["--png", png.to_str().expect("utf-8")]);
    let stdout = String::from_utf8_lossy(&text.stdout);
    assert!(
        stdout.contains("body ") && stdout.contains(" contacts  min clearance 0.0000 m"),
        "{stdout}"
    );
    assert!(std::fs::read(&png).expect("picture").starts_with(b"\x89PNG"));
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

fn inflation(extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "navfn",
        "inflation",
        CIRCULAR,
        "--robot-radius",
        "0.3",
        "--cost-scaling-factor",
        "3",
        "--goals",
        "4",
        "--start-stride",
        "8",
        "--json",
    ];
    args.extend_from_slice(extra);
    vouch(&args)
}

/// Distance from the point `p` to the closed square of cell `c` (origin −10, −10; cells of
/// 0.05 m as a float), computed here, not by the library.
fn point_to_cell(p: [f64; 2], c: [usize; 2]) -> f64 {
    let res = f64::from(0.05f32);
    let (x0, y0) = (-10.0 + c[0] as f64 * res, -10.0 + c[1] as f64 * res);
    let dx = (x0 - p[0]).max(p[0] - x0 - res).max(0.0);
    let dy = (y0 - p[1]).max(p[1] - y0 - res).max(0.0);
    dx.hypot(dy)
}

/// With nav2's padding (inscribed radius 0.304 m for a 0.3 m robot) no inflation radius keeps
/// the body clear on this map: the inscribed ring is measured between cell centres, nav2 places
/// a path point at its cell's corner and the body meets the obstacle's square, so a path may
/// pass closer than the ring says; with a padding of 0.08 m (inscribed 0.372 m) the search
/// finds a radius for the sampled goals, and its counterexample at the radius below touches.
#[test]
fn inflation_search_finds_the_radius_and_a_real_counterexample() {
    if !shared() {
        return;
    }
    let o = inflation(&[]);
    assert_eq!(code(&o), 3, "{}", String::from_utf8_lossy(&o.stderr));
    assert!(json(&o)["smallest_safe_radius"].is_null());

    let dir = tempfile::tempdir().expect("temporary folder");
    let png = dir.path().join("counterexample.png");
    let png_arg = png.to_str().expect("utf-8");
    let o = inflation(&["--footprint-padding", "0.08", "--png", png_arg]);
    assert_eq!(code(&o), 0, "{}", String::from_utf8_lossy(&o.stderr));
    let r = json(&o);
    counterexample_is_drawn(&png);
    let safe = r["smallest_safe_radius"].as_f64().expect("a radius");
    let cx = &r["counterexample"];
    let failing = cx["inflation_radius"].as_f64().expect("failing radius");
    assert!((safe - failing - f64::from(0.05f32)).abs() < 1e-9, "{safe} {failing}");
    let poses = cx["poses"].as_array().expect("poses");
    let i = cx["contact"]["pose"].as_u64().expect("pose") as usize;
    let cell = [
        cx["contact"]["cell"][0].as_u64().expect("x") as usize,
        cx["contact"]["cell"][1].as_u64().expect("y") as usize,
    ];
    let xy = |k: usize| [poses[k][0].as_f64().expect("x"), poses[k][1].as_f64().expect("y")];
    // the disc swept from pose i to i+1 reaches the cell: the closer end, or a point between
    let (a, b) = (xy(i), xy((i + 1).min(poses.len() - 1)));
    let closest = (0..=100)
        .map(|t| {
            let t = t as f64 / 100.0;
            point_to_cell([a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t], cell)
        })
        .fold(f64::INFINITY, f64::min);
    assert!(closest <= 0.3 + 1e-6, "{closest}");
}

/// The counterexample's picture: a PNG of the map's size (times the picture's scale), with the
/// contact marked in magenta and the plan in red.
fn counterexample_is_drawn(png: &std::path::Path) {
    let file = std::fs::File::open(png).expect("the picture was written");
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut pixels).expect("one frame");
    assert_eq!((info.width % 384, info.height % 384), (0, 0), "map_circular is 384×384");
    let rgb = &pixels[..info.buffer_size()];
    let count = |c: [u8; 3]| rgb.chunks_exact(3).filter(|p| *p == c).count();
    assert!(count([255, 0, 255]) > 0, "a contact in magenta");
    assert!(count([230, 20, 20]) > 0, "the path in red");
}

/// Shards split the goals; merged, they give the unsharded answer.
#[test]
fn inflation_search_shards_merge_to_the_whole() {
    if !shared() {
        return;
    }
    let whole = json(&inflation(&["--footprint-padding", "0.08"]));
    let scratch = tempfile::tempdir().expect("scratch directory");
    let mut files = Vec::new();
    for i in 0..2 {
        let f = scratch.path().join(format!("part-{i}.json"));
        let spec = format!("{i}/2");
        let o = inflation(&[
            "--footprint-padding",
            "0.08",
            "--shard",
            &spec,
            "-o",
            f.to_str().expect("utf-8"),
        ]);
        assert!(code(&o) == 0 || code(&o) == 3);
        files.push(f);
    }
    let mut args = vec!["navfn", "inflation", "--json", "--merge"];
    args.extend(files.iter().map(|f| f.to_str().expect("utf-8")));
    let merged = json(&vouch(&args));
    assert_eq!(merged["smallest_safe_radius"], whole["smallest_safe_radius"]);
    assert_eq!(
        merged["counterexample"]["inflation_radius"],
        whole["counterexample"]["inflation_radius"]
    );
    assert_eq!(merged["shards"], serde_json::json!(["0/2", "1/2"]));
}

/// A polygon footprint: nav2's inscribed radius of the padded rectangle drives the costmap, the
/// rectangle as given is swept along the plan.
#[test]
fn plan_with_a_footprint_polygon() {
    if !shared() {
        return;
    }
    let o = plan_across(&[
        "--footprint",
        "[[0.25,0.2],[0.25,-0.2],[-0.25,-0.2],[-0.25,0.2]]",
        "--inflation-radius",
        "0.7",
        "--json",
    ]);
    let v = json(&o);
    assert_eq!(v["status"], "ok");
    let body = &v["body"];
    assert!(body["motions"].as_u64().expect("motions") > 100);
    let clearance = body["min"]["clearance"].as_f64().expect("a clearance within 2 m");
    assert!(clearance >= 0.0);
    let touches = !body["violations"].as_array().expect("violations").is_empty();
    assert_eq!(touches, clearance == 0.0);
    // A body that touches an obstacle is a finding (exit 3), as a failed plan check is.
    let expected = if touches { 3 } else { 0 };
    assert_eq!(code(&o), expected, "{}", String::from_utf8_lossy(&o.stderr));
}
