//! Values that GENERATOR_FACTS.md reports from running the upstream generator on the corpus,
//! and vouch's deliberate departures from upstream bugs.

mod common;

use vouch_fpl::emit::{EmitOptions, compile_plan};
use vouch_fpl::pipeline::compile_file;

fn header(rel: &str) -> Option<String> {
    let dir = common::corpus_dir()?;
    Some(
        compile_file(&dir.join(rel), &EmitOptions::default())
            .map_err(|e| e.listing())
            .expect("compiles"),
    )
}

fn define<'a>(h: &'a str, name: &str) -> &'a str {
    let prefix = format!("#define {name} ");
    h.lines()
        .find_map(|l| l.strip_prefix(prefix.as_str()))
        .unwrap_or_else(|| panic!("no #define {name}"))
}

#[test]
fn basic_reference_and_home_row_differ_by_the_utm_round_trip() {
    let Some(h) = header("basic.xml") else { return };
    // GENERATOR_FACTS §10: "basic.xml: 434622300 vs 434622299". NAV_LAT0 is
    // trunc(1e7 * (43.46223*pi/180)*180/pi) = trunc(434622300.00000006); the HOME row went
    // through UTM and back and lands one unit lower.
    assert_eq!(define(&h, "NAV_LAT0"), "434622300 /* 1e7deg */");
    let home_row = h
        .lines()
        .skip_while(|l| !l.starts_with("#define WAYPOINTS_LLA {"))
        .nth(2)
        .expect("HOME row");
    assert!(home_row.starts_with(" {.lat=434622299, "), "{home_row}");
}

#[test]
fn relative_waypoints_are_prepended() {
    let Some(h) = header("competitions/EMAV2006.xml") else { return };
    // GENERATOR_FACTS §12: `WP_A_0_20 1`, `WP_HOME_0_50 2`, `WP_HOME 3`.
    assert_eq!(define(&h, "WP_A_0_20"), "1");
    assert_eq!(define(&h, "WP_HOME_0_50"), "2");
    assert_eq!(define(&h, "WP_HOME"), "3");
}

#[test]
fn corpus_maxima_match_the_facts() {
    let Some(dir) = common::corpus_dir() else { return };
    let mut max_block = 0;
    let mut max_wp = 0;
    for p in common::corpus_plans(&dir) {
        let h = compile_file(&p, &EmitOptions::default()).expect("compiles");
        max_block = max_block.max(define(&h, "NB_BLOCK").parse::<usize>().expect("number"));
        max_wp = max_wp.max(define(&h, "NB_WAYPOINT").parse::<usize>().expect("number"));
    }
    // GENERATOR_FACTS §14 quirk 2: NB_BLOCK 49 (including HOME), NB_WAYPOINT 54.
    assert_eq!((max_block, max_wp), (49, 54));
}

#[test]
fn exceeding_time_is_negated_as_a_whole() {
    let xml = r#"<flight_plan name="t" lat0="43.46" lon0="1.27" alt="200" ground_alt="150" security_height="25" max_dist_from_home="1000">
<waypoints><waypoint name="HOME" x="0" y="0"/><waypoint name="A" x="10" y="0"/></waypoints>
<blocks><block name="b"><go wp="A" exceeding_time="a+b"/><go wp="A" exceeding_time="3"/></block></blocks></flight_plan>"#;
    let p = vouch_fpl::front::parse_str("t.xml", xml).expect("parses");
    let h = compile_plan(&p, &EmitOptions::default()).expect("compiles");
    // Upstream prints NavApproaching(2,-a+b) (quirk 7); vouch negates the whole time.
    assert!(h.contains("if (NavApproaching(2,-(a+b))) {"), "{h}");
    assert!(h.contains("if (NavApproaching(2,-3)) {"));
}

#[test]
fn exceeding_time_under_upstream_compat_is_upstreams_text_with_a_warning() {
    use vouch_fpl::diag::ErrorKind;
    use vouch_fpl::emit::compile_plan_full;
    let xml = r#"<flight_plan name="t" lat0="43.46" lon0="1.27" alt="200" ground_alt="150" security_height="25" max_dist_from_home="1000">
<waypoints><waypoint name="HOME" x="0" y="0"/><waypoint name="A" x="10" y="0"/></waypoints>
<blocks><block name="b"><go wp="A" exceeding_time="a+b"/><go wp="A" from="HOME" exceeding_time="3"/></block></blocks></flight_plan>"#;
    let p = vouch_fpl::front::parse_str("t.xml", xml).expect("parses");
    let compat = EmitOptions { upstream_compat: true, ..EmitOptions::default() };
    let e = compile_plan_full(&p, &compat).expect("compiles");
    // Upstream's bytes (quirk 7): the minus sign before the raw text.
    assert!(e.header.contains("if (NavApproaching(2,-a+b)) {"), "{}", e.header);
    assert!(e.header.contains("if (NavApproachingFrom(2,1,-3)) {"));
    let w: Vec<_> = e.notices.iter().filter(|d| d.kind == ErrorKind::UpstreamMistake).collect();
    assert_eq!(w.len(), 1);
    assert!(w[0].message.contains("first term") && w[0].message.contains("upstream"));
    assert_eq!(w[0].line, Some(3), "located at the attribute");
    assert!(e.corrections.is_empty() && !e.notices.iter().any(|d| d.kind == ErrorKind::Correction));
    // By default the correction and its announcement.
    let e = compile_plan_full(&p, &EmitOptions::default()).expect("compiles");
    assert!(e.header.contains("if (NavApproaching(2,-(a+b))) {"));
    let c: Vec<_> = e.notices.iter().filter(|d| d.kind == ErrorKind::Correction).collect();
    assert_eq!(c.len(), 1);
    assert!(c[0].message.contains("upstream prints -a+b"), "{}", c[0].message);
}

#[test]
fn waypoints_outside_the_inverse_utm_domain_are_located_errors() {
    // UPSTREAM_CHECKS.md H12d: upstream stops with Invalid_argument "Latlong.of_utm" when the
    // reference's UTM position plus the waypoint's offset leaves x in [0, 1e7] or y in
    // [-1e7, 1e7]. At 43.46N 1.27E (zone 31, centre 3E) the reference lies near UTM x 360 km.
    let plan = |x: &str, y: &str| {
        format!(
            r#"<flight_plan name="t" lat0="43.46" lon0="1.27" alt="200" ground_alt="150" security_height="25" max_dist_from_home="1000">
<waypoints><waypoint name="HOME" x="0" y="0"/>
<waypoint name="FAR" x="{x}" y="{y}"/></waypoints>
<blocks><block name="b"><go wp="FAR"/></block></blocks></flight_plan>"#
        )
    };
    for (x, y) in [("-400000", "0"), ("9700000", "0"), ("0", "-15000000"), ("0", "6000000")] {
        let p = vouch_fpl::front::parse_str("t.xml", &plan(x, y)).expect("parses");
        let e = compile_plan(&p, &EmitOptions::default()).expect_err(&format!("x={x} y={y}"));
        assert!(e.message.contains("FAR") && e.message.contains("Latlong.of_utm"), "{}", e.message);
        assert_eq!(e.span.map(|s| s.line), Some(3), "located at the waypoint");
    }
    // Inside the domain (far from HOME: only the distance warning) it compiles.
    for (x, y) in [("-300000", "0"), ("0", "5000000")] {
        let p = vouch_fpl::front::parse_str("t.xml", &plan(x, y)).expect("parses");
        compile_plan(&p, &EmitOptions::default()).expect("inside the UTM domain");
    }
}

#[test]
fn labels_restart_for_each_plan() {
    // Quirk 14: upstream numbers labels across plans generated in one process; vouch does not.
    let Some(a) = header("basic.xml") else { return };
    let b = header("basic.xml").expect("again");
    assert_eq!(a, b);
    if a.contains("Label(while_") {
        assert!(a.contains("Label(while_1)"));
    }
}

#[test]
fn geoid_height_at_a_grid_node_matches_the_egm96_reference() {
    use vouch_fpl::emit::geo::rad_of_deg;
    use vouch_fpl::emit::geoid::Geoid;
    // NGA EGM96 calculator at 41N 1E: 49.83 m (value quoted in Paparazzi's latlong.ml).
    let model = Geoid::model();
    let n = model.node(rad_of_deg(41.0), rad_of_deg(1.0)).expect("node").metres();
    assert!((n - 49.83).abs() <= 0.02, "{n}");
    // Truncation toward zero: 41.9N 1.9E uses the same node.
    assert_eq!(model.node(rad_of_deg(41.9), rad_of_deg(1.9)).expect("node").metres(), n);
    // The grid Paparazzi ships (bzip2) agrees, and reads -13.97 m at 41N 111W.
    let Some(home) = vouch_testkit::shared("fpl/paparazzi_home", "data/srtm/WW15MGH.DAC.bz2")
    else {
        return;
    };
    let grid = Geoid::of_home(&home).expect("the .bz2 grid decompresses");
    assert_eq!(grid.node(rad_of_deg(41.0), rad_of_deg(1.0)).expect("node").metres(), 49.83);
    let west = grid.node(rad_of_deg(41.5), rad_of_deg(-111.5)).expect("node");
    assert_eq!((west.metres(), west.upstream()), (-13.97, 641.39));
    grid.check_complete().expect("the whole grid decompresses");
}

#[test]
fn ltp_frame_enu_rows_are_the_written_coordinates() {
    // GENERATOR_FACTS §10: in LTP frame the ENU row is (x, y, ALT - ground_alt).
    // ENAC/demo_aruco_drop_indoor.xml: alt 148, ground_alt 146, STDBY at x=-0.7 y=-0.8.
    let Some(h) = header("ENAC/demo_aruco_drop_indoor.xml") else { return };
    let rows: Vec<&str> = h
        .lines()
        .skip_while(|l| !l.starts_with("#define WAYPOINTS_ENU {"))
        .skip(1)
        .take(3)
        .collect();
    assert_eq!(rows[0], " {0.00, 0.00, 2.00}, /* ENU in meters  */ \\");
    assert_eq!(rows[2], " {-0.70, -0.80, 2.00}, /* ENU in meters  */ \\");
}
