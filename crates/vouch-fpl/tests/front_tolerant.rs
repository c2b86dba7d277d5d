//! The tolerant reader accepts what upstream's xml-light accepts: duplicate attributes (first
//! wins), raw `<`/`&` in attribute values (kept raw, never entity-decoded), `--`/`<!--` inside
//! comments, upper-case attribute names, and keeps every offset of the original file.

use std::path::PathBuf;

use vouch_fpl::front::tolerant::sanitize;
use vouch_fpl::front::{parse_file, parse_str};

fn corpus() -> Option<PathBuf> {
    vouch_testkit::shared("fpl/corpus", "INDEX.tsv")
}

const HEAD: &str = r#"<flight_plan name="t" lat0="43.46" lon0="1.27" alt="250" ground_alt="185" security_height="25" max_dist_from_home="1000">"#;

fn plan(extra_wp: &str, blocks: &str) -> String {
    format!(
        "{HEAD}\n<waypoints>\n<waypoint name=\"HOME\" x=\"0\" y=\"0\"/>{extra_wp}\n</waypoints>\n<blocks>\n{blocks}\n</blocks>\n</flight_plan>\n"
    )
}

#[test]
fn prepass_preserves_length_and_offsets() {
    let src = "<a k=\"<x> & y\" k=\"2\"><!-- a -- b <!-- c --> t & u</a>";
    let s = sanitize(src);
    assert_eq!(s.text.len(), src.len());
    assert!(roxmltree::Document::parse(&s.text).is_ok(), "{}", s.text);
    assert_eq!(s.fixes.len(), 5);
}

#[test]
fn raw_characters_in_values_are_kept_raw() {
    let text =
        plan("", r#"<block name="b" key="<Control>a" pre_call="f(&amp;x, &y)"><home/></block>"#);
    let p = parse_str("t.xml", &text).expect("parses");
    let b = &p.blocks[0];
    assert_eq!(b.key.as_ref().unwrap().value, "<Control>a");
    assert_eq!(b.pre_call.as_ref().unwrap().value, "f(&amp;x, &y)");
    // The span points at exactly the raw text in the source.
    assert_eq!(p.sources.snippet(b.pre_call.as_ref().unwrap().span), "f(&amp;x, &y)");
}

#[test]
fn duplicate_and_uppercase_attributes_first_wins() {
    let text = plan(
        "",
        r#"<block name="b" NAME="c" group="g1" group="g2"><go WP="HOME" wp="X"/></block>"#,
    );
    let p = parse_str("t.xml", &text).expect("parses");
    assert_eq!(p.blocks[0].name.value, "b");
    assert_eq!(p.blocks[0].group.as_ref().unwrap().value, "g1");
    assert!(!p.warnings.is_empty(), "dropped duplicates are reported as warnings");
    let vouch_fpl::ast::StageKind::Go(g) = &p.blocks[0].stages[0].kind else { panic!("go") };
    assert_eq!(g.wp.as_ref().unwrap().name, "HOME");
}

#[test]
fn comments_with_dashes_and_nested_openers() {
    let text = plan(
        "<!-- old: <waypoint name=\"Z\" -- x=\"1\"/> <!-- nested -->",
        "<block name=\"b\"><home/></block>",
    );
    let p = parse_str("t.xml", &text).expect("parses");
    assert_eq!(p.waypoints.len(), 1);
}

#[test]
fn header_text_is_decoded_and_blank_lines_dropped() {
    let text = format!(
        "{HEAD}\n<header>\n#define A 1 &amp;&amp; 2\n\n   \n  #include &lt;x.h&gt; &unknown;\n</header>\n<waypoints><waypoint name=\"HOME\" x=\"0\" y=\"0\"/></waypoints>\n<blocks><block name=\"b\"/></blocks>\n</flight_plan>"
    );
    let p = parse_str("t.xml", &text).expect("parses");
    assert_eq!(p.header.unwrap().text, "#define A 1 && 2\n  #include <x.h> &unknown;");
}

#[test]
fn corpus_lenient_files_read_like_upstream() {
    let Some(dir) = corpus() else { return };
    let p = parse_file(dir.join("tudelft/rotwing_EHR8.xml")).expect("parses");
    assert_eq!(p.alt.text.value, "70", "first of the duplicated alt attributes wins");
    let p = parse_file(dir.join("OPENUAS/openuas_versatile_unified.xml")).expect("parses");
    let b = p.blocks.iter().find(|b| b.name.value == "Line 1-2").expect("block");
    assert_eq!(b.group.as_ref().unwrap().value, "extra_pattern");
    let p = parse_file(dir.join("OPENUAS/openuas_tuning_a_fresh_fixedwing.xml")).expect("parses");
    let b = p.blocks.iter().find(|b| b.name.value == "Standby").expect("block");
    assert_eq!(b.key.as_ref().unwrap().value, "<Control>a");
    let p = parse_file(dir.join("ENAC/dw1000_basic.xml")).expect("parses");
    let b = p.blocks.iter().find(|b| b.name.value == "Run Shift Tracking").expect("block");
    assert_eq!(b.pre_call.as_ref().unwrap().value, "shift_tracking_run(&nav_shift)");
    let p = parse_file(dir.join("dummy.xml")).expect("upper-case attribute names are accepted");
    assert_eq!(p.name.value, "Dummy");
}

#[test]
fn undeclared_attributes_are_errors_only_in_validated_plans() {
    // No DOCTYPE: upstream does not validate, the attribute is kept and reported as a warning.
    let text = plan("", r#"<block name="b"><go wp="HOME" speed="3"/></block>"#);
    let p = parse_str("t.xml", &text).expect("accepted without DOCTYPE");
    assert_eq!(p.blocks[0].stages[0].attrs.get("speed").map(|a| a.value.as_str()), Some("3"));
    assert!(p.warnings.iter().any(|w| w.message.contains("speed")));
    // With a DOCTYPE it is an error, as upstream's DTD validation makes it.
    let validated = format!("<!DOCTYPE flight_plan SYSTEM \"flight_plan.dtd\">\n{text}");
    let d = parse_str("t.xml", &validated).expect_err("rejected with DOCTYPE");
    let e = d.first().unwrap();
    assert_eq!(e.kind, vouch_fpl::diag::ErrorKind::UnknownAttribute);
    // Lines: DOCTYPE, flight_plan, waypoints, waypoint, /waypoints, blocks, then the block.
    assert_eq!(e.line, Some(7));
}
