//! Translation validation of the crafted plans (forbidden deroutes, ping-pong) and the static
//! bound of a plan whose bound is computed by hand.

use std::path::Path;

use vouch_fpl::evidence::validate::{Options, validate};

fn plan(name: &str) -> vouch_fpl::ast::FlightPlan {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans").join(name);
    vouch_fpl::front::parse_file(&p).expect("crafted plan parses")
}

#[test]
fn crafted_plans_validate() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    for name in
        ["pingpong.xml", "forbidden.xml", "mutation.xml", "lint_misc.xml", "wcet.xml", "deep.xml"]
    {
        let r = validate(
            &plan(name),
            &Options { random_runs: 2, random_steps: 300, ..Options::default() },
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(r.passed(), "{name}: {:?}", r.counterexample);
        assert!(r.cut.is_none() && r.fixpoint, "{name}");
        assert!(r.max_events_seen <= r.bound.max_events);
    }
}

#[test]
fn hand_computed_bound() {
    let fp = vouch_fpl::passes::lower::lower(&plan("wcet.xml")).expect("lowers");
    let b = vouch_fpl::evidence::wcet::bound(&fp);
    let seq = &b.blocks[0];
    assert_eq!(seq.name, "Seq");
    // from stage 0: set, set, set, call_once, deroute = 5 stage items in one call;
    // events: 1 global exception condition + 4 statements (the deroute has no hooks)
    assert_eq!((seq.stages, seq.events), (5, 5));
    let lp = &b.blocks[1];
    // Loop: while test (1 cond) exits past the loop-back to the end of block (NextBlock):
    // starting at the loop-back: loop-back, test, default = 3 items; events 1 + 1 (global)
    // or, starting at set: set (1), loop-back, test (1), default = 4 items, 3 events
    assert_eq!((lp.stages, lp.events), (4, 3));
}

#[test]
fn upstreams_exceeding_time_text_is_a_disagreement_with_the_semantics() {
    use vouch_fpl::emit::{EmitOptions, Flavor, compile_plan};
    use vouch_fpl::evidence::validate::validate_header;
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let xml = r#"<flight_plan name="t" lat0="43.46" lon0="1.27" alt="200" ground_alt="150" security_height="25" max_dist_from_home="1000">
<waypoints><waypoint name="HOME" x="0" y="0"/><waypoint name="A" x="10" y="0"/></waypoints>
<blocks><block name="b"><go wp="A" exceeding_time="a+b"/></block></blocks></flight_plan>"#;
    let p = vouch_fpl::front::parse_str("t.xml", xml).expect("parses");
    let fp = vouch_fpl::passes::lower::lower(&p).expect("lowers");
    let opts = Options { random_runs: 1, random_steps: 50, ..Options::default() };
    let header = |upstream_compat| {
        let eo =
            EmitOptions { flavor: Flavor::Instrumented, upstream_compat, ..EmitOptions::default() };
        compile_plan(&p, &eo).expect("compiles")
    };
    // The default output is what the semantics means.
    assert!(validate_header(&fp, &header(false), &opts).expect("runs").passed());
    // Upstream's -a+b is not -(a+b): the validation reports it instead of passing.
    let r = validate_header(&fp, &header(true), &opts).expect("runs");
    assert!(!r.passed(), "the compat header's approach test differs from the semantics");
    let cx = format!("{:?}", r.counterexample.expect("a counterexample"));
    assert!(cx.contains("-a+b"), "{cx}");
}
