//! The bundled demo plan (examples/fpl/demo.xml, README's first command) parses, including the
//! VFPG `forbidden_deroutes` extension, and serialises to JSON (`vouch fpl parse --json`).

use std::path::PathBuf;

use vouch_fpl::ast::StageKind;
use vouch_fpl::diag::ErrorKind;
use vouch_fpl::front::{Options, parse_file, parse_file_with};

fn demo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml")
}

#[test]
fn demo_plan_parses_with_forbidden_deroute() {
    let p = parse_file(demo()).unwrap_or_else(|d| panic!("{}", d.listing()));
    let names: Vec<&str> = p.blocks.iter().map(|b| b.name.value.as_str()).collect();
    assert_eq!(names, ["Wait GPS", "Takeoff", "Standby", "Survey", "Land", "HOME"]);
    assert_eq!(p.forbidden_deroutes.len(), 1);
    let f = &p.forbidden_deroutes[0];
    assert_eq!((f.from.id.0, f.to.id.0), (1, 4));
    assert!(f.only_when.is_none());
    // waypoint numbering: dummy is 0, HOME is 1.
    assert_eq!(p.waypoint_id("HOME").unwrap().upstream_index(), 1);
    let survey = &p.blocks[3];
    assert!(matches!(survey.stages[1].kind, StageKind::While(_)));
    let json = serde_json::to_string(&p).expect("serialisable");
    assert!(json.contains("\"forbidden_deroutes\""));
}

#[test]
fn forbidden_deroutes_can_be_refused_like_upstream() {
    let opts = Options { allow_forbidden_deroutes: false, ..Options::default() };
    let d = parse_file_with(demo(), &opts).expect_err("extension disabled");
    assert_eq!(d.first().unwrap().kind, ErrorKind::UnexpectedElement);
}
