//! Model checking on crafted plans; counterexamples are replayed on the interpreter.

use std::path::Path;

use vouch_fpl::model_check::{build, check};
use vouch_fpl::semantics::Interp;
use vouch_fpl::semantics::oracle::Scripted;

fn fp_of(name: &str) -> vouch_fpl::passes::fp::Fp {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans").join(name);
    let plan = vouch_fpl::front::parse_file(&p).expect("crafted plan parses");
    vouch_fpl::passes::lower::lower(&plan).expect("lowers")
}

/// Replays a counterexample's answers on the real plan and returns the final block.
fn replay(fp: &vouch_fpl::passes::fp::Fp, cx: &check::Counterexample) -> usize {
    let answers: Vec<i64> = cx.steps.iter().flat_map(|s| s.answers.iter().copied()).collect();
    let mut interp = Interp::new(fp);
    let mut o = Scripted::new(answers);
    interp.run(&mut o, cx.steps.len()).expect("runs");
    interp.observe().block
}

#[test]
fn forbidden_deroute_blocks_and_deadlocks() {
    let fp = fp_of("forbidden.xml");
    let g = build(&fp, 10_000, false).expect("builds");
    assert!(g.cut.is_none() && g.fixpoint);
    let o = check::check_no_blocked(&g);
    assert!(!o.holds);
    let cx = o.counterexample.expect("counterexample");
    let last = cx.steps.last().expect("at least one call");
    assert!(
        last.blocked.contains(&("Takeoff".to_string(), "Land".to_string())),
        "{:?}",
        last.blocked
    );
    // Takeoff = block 0: the plan never leaves it
    assert_eq!(replay(&fp, &cx), 0);
    let d = check::check_deadlock_free(&g);
    assert!(!d.holds, "the deroute stage of Takeoff is refused on every call");
    assert!(d.counterexample.expect("cx").explanation.contains("Takeoff"));
}

#[test]
fn pingpong_never_lands_but_always_can_refuel() {
    let fp = fp_of("pingpong.xml");
    let g = build(&fp, 10_000, false).expect("builds");
    let never_land = check::check_text(&g, "never block(Land)").expect("parses");
    assert!(
        never_land.holds && never_land.complete,
        "Land is unreachable: Refuel returns to the deroute"
    );
    let safe = check::check_safe_blocks(&g, &[g.block_index("Refuel").expect("block")]);
    assert!(safe.holds);
    let inf = check::check_text(&g, "always eventually block(Refuel)").expect("parses");
    assert!(!inf.holds, "the first go can last forever (its approach condition stays false)");
    let cx = inf.counterexample.expect("lasso");
    assert!(cx.loop_from.is_some());
    assert_eq!(replay(&fp, &cx), 0, "the lasso stays in Patrol");
    let ev = check::check_text(&g, "eventually block(Refuel) || block(Patrol)").expect("parses");
    assert!(ev.holds, "the initial state is in Patrol");
}

#[test]
fn operator_jumps_reach_every_block() {
    let fp = fp_of("pingpong.xml");
    let g = build(&fp, 10_000, true).expect("builds");
    let o = check::check_text(&g, "never block(Land)").expect("parses");
    assert!(!o.holds);
    let cx = o.counterexample.expect("cx");
    assert_eq!(cx.steps.len(), 1);
    assert_eq!(cx.steps[0].operator.as_deref(), Some("Land"));
}

/// A property naming the last block gets a graph that keeps it; the run of the full check says
/// "fixpoint reached".
#[test]
fn last_block_properties_see_the_last_block() {
    use vouch_fpl::model_check::{Spec, run};
    let fp = fp_of("pingpong.xml");
    let spec = Spec {
        properties: vec!["never (block(Refuel) && !last_block(Patrol))".into()],
        ..Spec::default()
    };
    let r = run(&fp, &spec).expect("runs");
    assert!(
        r.fixpoint
            && r.render("pingpong").lines().next().is_some_and(|l| l.ends_with("fixpoint reached"))
    );
    assert!(r.outcomes[0].holds, "Refuel is only entered from Patrol's deroute");
    // with operator jumps, Refuel can be entered from anywhere
    let r = run(&fp, &Spec { operator: true, ..spec }).expect("runs");
    assert!(!r.outcomes[0].holds);
    let cx = r.outcomes[0].counterexample.as_ref().expect("counterexample");
    assert!(cx.steps.iter().any(|s| s.operator.is_some()));
}

#[test]
fn property_errors_are_reported() {
    let fp = fp_of("pingpong.xml");
    let g = build(&fp, 10_000, false).expect("builds");
    assert!(
        check::check_text(&g, "always block(Nowhere)")
            .unwrap_err()
            .message
            .contains("unknown block")
    );
    assert!(check::check_text(&g, "sometimes block(Land)").is_err());
    assert!(check::check_text(&g, "always (block(Land)").is_err());
}
