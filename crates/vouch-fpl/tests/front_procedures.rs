//! Include/procedure expansion as upstream's fp_proc does it (GENERATOR_FACTS.md section 11),
//! checked on the corpus: renaming, deroute rewriting, re-printed procedure texts, appended
//! lists, header concatenation; plus paths and relative waypoints (section 12).

use vouch_fpl::ast::{FlightPlan, StageKind, WaypointOrigin};
use vouch_fpl::expr::print_upstream;
use vouch_fpl::front::parse_file;

fn load(rel: &str) -> Option<FlightPlan> {
    let p = vouch_testkit::shared("fpl/corpus", "INDEX.tsv")?.join(rel);
    Some(parse_file(&p).unwrap_or_else(|d| panic!("{rel}: {}", d.listing())))
}

#[test]
fn landing_procedure_is_renamed_and_reprinted() {
    let Some(p) = load("competitions/EMAV2009.xml") else { return };
    let right =
        p.blocks.iter().find(|b| b.name.value == "L.Land Right AF-TD").expect("prefixed block");
    assert_eq!(right.procedure.as_deref(), Some("L"));
    let StageKind::Set(set) = &right.stages[0].kind else { panic!("set") };
    assert_eq!(set.value.text.value, "DEFAULT_CIRCLE_RADIUS");
    let StageKind::Deroute(d) = &right.stages[1].kind else { panic!("deroute") };
    assert_eq!(d.block.name, "L.land");
    assert_eq!(p.blocks[d.block.id.0].name.value, "L.land");

    let left = p.blocks.iter().find(|b| b.name.value == "L.Land Left AF-TD").unwrap();
    let StageKind::Set(set) = &left.stages[0].kind else { panic!("set") };
    assert_eq!(
        set.value.text.value, "-(DEFAULT_CIRCLE_RADIUS)",
        "re-printed by the procedure expansion"
    );

    let land = p.blocks.iter().find(|b| b.name.value == "L.land").unwrap();
    let StageKind::CallOnce(c) = &land.stages[0].kind else { panic!("call_once") };
    assert_eq!(c.fun.value, "nav_compute_baseleg(WP_AF,WP_TD,WP__BASELEG,nav_radius)");

    let fin = p.blocks.iter().find(|b| b.name.value == "L.final").unwrap();
    assert_eq!(fin.exceptions.len(), 1);
    assert_eq!(fin.exceptions[0].deroute.name, "L.flare");
    assert_eq!(print_upstream(&fin.exceptions[0].cond.expr), "((GetAltRef()+10)>GetPosAlt())");

    let flare = p.blocks.iter().find(|b| b.name.value == "L.flare").unwrap();
    let StageKind::Go(g) = &flare.stages[0].kind else { panic!("go") };
    assert_eq!(g.vertical.throttle.as_ref().unwrap().text.value, "0.000000");
    assert_eq!(g.approaching_time.as_ref().unwrap().value, "0");

    // Procedure waypoints are appended, not prefixed.
    assert!(p.waypoints.iter().any(|w| w.name.value == "_BASELEG"
        && w.origin == WaypointOrigin::Procedure { include: "L".into() }));
    // HOME block stays last.
    assert!(p.blocks.last().unwrap().implicit);
}

#[test]
fn header_concatenates_main_and_procedure_texts() {
    let Some(p) = load("competitions/EMAV2009.xml") else { return };
    let h = p.header.expect("header").text;
    assert!(h.starts_with("#include \"datalink.h\""), "{h:?}");
    // Three includes: three "\n" + procedure header appended.
    assert!(h.matches('\n').count() >= 3, "{h:?}");
}

#[test]
fn paths_become_go_stages() {
    let Some(p) = load("basic.xml") else { return };
    let gos: Vec<_> = p
        .blocks
        .iter()
        .flat_map(|b| &b.stages)
        .filter(|s| s.from_path)
        .map(|s| match &s.kind {
            StageKind::Go(g) => {
                (g.from.as_ref().map(|f| f.name.clone()), g.wp.as_ref().unwrap().name.clone())
            }
            _ => panic!("a path expands into go stages only"),
        })
        .collect();
    assert!(!gos.is_empty(), "basic.xml has a path");
    // Consecutive segments chain: each segment starts where the previous ended.
    for w in gos.windows(2) {
        if w[1].0.as_deref() == Some(w[0].1.as_str()) {
            return;
        }
    }
    panic!("no chained path segments in {gos:?}");
}

#[test]
fn relative_waypoints_are_prepended_like_upstream() {
    let Some(p) = load("competitions/EMAV2006.xml") else { return };
    // GENERATOR_FACTS section 12: WP_A_0_20 1, WP_HOME_0_50 2, WP_HOME 3.
    let names: Vec<&str> = p.waypoints.iter().take(3).map(|w| w.name.value.as_str()).collect();
    assert_eq!(names, ["A_0_20", "HOME_0_50", "HOME"]);
    assert!(matches!(p.waypoints[0].origin, WaypointOrigin::Relative { .. }));
}
