//! The SVG picture: well-formed XML, one box per block, edges styled by kind, forbidden
//! transitions marked.

mod common;

use std::path::Path;

fn svg_of(p: &Path) -> (vouch_fpl::ast::FlightPlan, String) {
    let plan = vouch_fpl::front::parse_file(p).expect("plan parses");
    let s = vouch_fpl::graph::render_svg(&plan);
    (plan, s)
}

fn count(doc: &roxmltree::Document, tag: &str, attr: &str, value: &str) -> usize {
    doc.descendants().filter(|n| n.has_tag_name(tag) && n.attribute(attr) == Some(value)).count()
}

#[test]
fn crafted_forbidden_plan_marks_forbidden_edges() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans/forbidden.xml");
    let (plan, s) = svg_of(&p);
    let doc = roxmltree::Document::parse(&s).expect("well-formed SVG");
    // one box per block (4 with HOME) with the block fill colours
    let boxes = count(&doc, "rect", "fill", "#f4f6fb") + count(&doc, "rect", "fill", "#eeeeee");
    assert_eq!(boxes, plan.blocks.len());
    // two forbidden deroute stages -> two crosses (one always, one only_when)
    let marks: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.attribute("fill") == Some("#d62728"))
        .filter_map(|n| n.text())
        .collect();
    assert!(marks.contains(&"✕") && marks.contains(&"?"), "{marks:?}");
    // the global exception box exists
    assert!(s.contains("global exceptions"));
}

#[test]
fn every_corpus_plan_renders() {
    let Some(dir) = common::corpus_dir() else { return };
    for p in common::corpus_plans(&dir) {
        let (plan, s) = svg_of(&p);
        let doc = roxmltree::Document::parse(&s).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let boxes = count(&doc, "rect", "fill", "#f4f6fb") + count(&doc, "rect", "fill", "#eeeeee");
        assert_eq!(boxes, plan.blocks.len(), "{}", p.display());
    }
}
