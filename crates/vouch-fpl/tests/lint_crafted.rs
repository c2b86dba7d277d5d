//! Lint rules on crafted plans (each written to contain exactly the listed mistakes) and a
//! sanity run over the corpus.

mod common;

use std::path::Path;

use vouch_fpl::lint::{Rule, counts, lint, render};

fn lint_plan(name: &str) -> (vouch_fpl::ast::FlightPlan, Vec<vouch_fpl::lint::Warning>) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans").join(name);
    let plan = vouch_fpl::front::parse_file(&p).expect("crafted plan parses");
    let w = lint(&plan);
    (plan, w)
}

fn codes_at(w: &[vouch_fpl::lint::Warning]) -> Vec<(&'static str, u32)> {
    w.iter().map(|w| (w.rule.code(), w.span.line)).collect()
}

#[test]
fn return_after_deroute_is_found() {
    let (plan, w) = lint_plan("pingpong.xml");
    // the <return/> of Refuel is on line 19; the dead <go> after Patrol's deroute on line 15;
    // Land (line 21) is never entered: Refuel only returns, Patrol never reaches its end
    assert_eq!(codes_at(&w), vec![("fpl::W008", 15), ("fpl::W004", 19), ("fpl::W001", 21)]);
    assert_eq!(w[1].notes.len(), 1);
    assert_eq!(w[1].notes[0].span.line, 14, "the note points at the deroute");
    let text = render(&plan, &w);
    assert!(text.contains("pingpong.xml:19:7: warning[fpl::W004]"), "{text}");
}

#[test]
fn blocked_forbidden_deroutes_are_found() {
    let (_, w) = lint_plan("forbidden.xml");
    // line 13: the global exception (always forbidden from Takeoff, under only_when from
    // Survey); line 18: Takeoff's deroute (always); line 22: Survey's deroute (only_when)
    assert_eq!(
        codes_at(&w),
        vec![("fpl::W002", 13), ("fpl::W003", 13), ("fpl::W002", 18), ("fpl::W003", 22)]
    );
    assert_eq!(w[2].notes[0].span.line, 30, "points at the forbidden_deroute declaration");
}

#[test]
fn other_rules_are_found() {
    let (_, w) = lint_plan("lint_misc.xml");
    let mut got = codes_at(&w);
    got.sort();
    let mut want = vec![
        ("fpl::W001", 22),
        ("fpl::W005", 16),
        ("fpl::W006", 15),
        ("fpl::W007", 10),
        ("fpl::W008", 29),
    ];
    want.sort();
    assert_eq!(got, want);
}

#[test]
fn corpus_lint_summary() {
    let Some(dir) = common::corpus_dir() else { return };
    let mut all = Vec::new();
    for p in common::corpus_plans(&dir) {
        let plan = vouch_fpl::front::parse_file(&p).expect("corpus plan parses");
        let w = lint(&plan);
        for x in &w {
            assert!(Rule::ALL.contains(&x.rule));
            assert!(x.span.line > 0, "{}: warning not located", p.display());
            assert!(!plan.sources.snippet(x.span).is_empty(), "{}: empty span", p.display());
        }
        // The corpus has no forbidden deroutes (a VFPG extension), so W002/W003 cannot fire.
        assert!(w.iter().all(|x| !matches!(x.rule, Rule::AlwaysForbidden | Rule::ForbiddenWhen)));
        all.extend(w);
    }
    let summary: Vec<String> =
        counts(&all).iter().map(|(c, n)| format!("{}={n}", c.code())).collect();
    eprintln!("corpus lint: {} warnings: {}", all.len(), summary.join(" "));
}

/// W009: comparisons with a decimal constant that single precision does not hold exactly,
/// located at the constant; exact constants and constants outside comparisons are not reported.
#[test]
fn float_width_dependent_comparisons_are_found() {
    let xml = r#"<flight_plan name="f" lat0="43.46" lon0="1.27" alt="200" ground_alt="150" security_height="25" max_dist_from_home="1000">
<waypoints><waypoint name="HOME" x="0" y="0"/><waypoint name="A" x="10" y="0"/></waypoints>
<exceptions><exception cond="GetPosAlt() @GT ground_alt + 10.3" deroute="HOME"/></exceptions>
<blocks><block name="b">
<go wp="A" until="stage_time > 2.5"/>
<set var="x" value="x + 0.1"/>
<while cond="y == 0.1 || z > 16777217"><call_once fun="f()"/></while>
</block></blocks></flight_plan>"#;
    let plan = vouch_fpl::front::parse_str("f.xml", xml).expect("parses");
    let w: Vec<_> = lint(&plan).into_iter().filter(|w| w.rule == Rule::FloatWidth).collect();
    let at: Vec<(u32, u32, &str)> =
        w.iter().map(|w| (w.span.line, w.span.col, plan.sources.snippet(w.span))).collect();
    // columns: the value of `cond` starts at 30 and 10.3 follows 29 characters; `while cond="` is 13
    assert_eq!(at, [(3, 59, "10.3"), (7, 19, "0.1"), (7, 30, "16777217")]);
    assert!(w[0].message.contains("10.300000190734863"), "{}", w[0].message);
    assert_eq!(Rule::FloatWidth.code(), "fpl::W009");
}
