//! Mutation check of the validator: deliberately broken C back ends (the instrumented header
//! text of a crafted plan, edited the way a buggy emitter could produce it) must each be
//! caught, with a short counterexample; the unbroken header must pass.

use std::path::Path;

use vouch_fpl::emit::{compile_plan, EmitOptions, Flavor};
use vouch_fpl::evidence::validate::{validate_header, Options};

fn plan_and_header() -> (vouch_fpl::passes::fp::Fp, String) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans/mutation.xml");
    let plan = vouch_fpl::front::parse_file(&p).expect("crafted plan parses");
    let fp = vouch_fpl::passes::lower::lower(&plan).expect("lowers");
    let h = compile_plan(
        &plan,
        &EmitOptions { flavor: Flavor::Instrumented, ..EmitOptions::default() },
    )
    .expect("compiles");
    (fp, h)
}

fn opts() -> Options {
    Options { depth: 8, random_runs: 2, random_steps: 200, ..Options::default() }
}

/// Replaces the first occurrence of `from` after the start of `auto_nav` (asserting it exists,
/// so a change of the emitter's text shape fails here instead of weakening the test).
fn mutate(h: &str, from: &str, to: &str) -> String {
    let start = h.find("static inline void auto_nav(void)").expect("auto_nav present");
    let i =
        h[start..].find(from).unwrap_or_else(|| panic!("'{from}' not found in auto_nav")) + start;
    format!("{}{}{}", &h[..i], to, &h[i + from.len()..])
}

#[test]
fn unmutated_header_passes() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header();
    let r = validate_header(&fp, &h, &opts()).expect("driver builds");
    assert!(r.passed(), "{:?}", r.counterexample);
    assert!(r.cut.is_none());
    assert!(r.call_paths > 20, "explores the plan ({} paths)", r.call_paths);
}

#[test]
fn every_mutation_is_caught() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header();
    // (name, text in auto_nav, replacement, expected number of calls of the shortest
    // counterexample, derived by hand from the plan)
    let swap = {
        let a = mutate(&h, "Stage(4)", "Stage(@@)");
        let b = mutate(&a, "Stage(5)", "Stage(4)");
        mutate(&b, "Stage(@@)", "Stage(5)")
    };
    let cases: Vec<(&str, String, usize)> = vec![
        // the first go is now labelled Stage(5): after call 1 nav_stage is 5, not 4
        ("swap two stages", swap, 1),
        // Work's deroute falls into the default stage (NextBlock(): Back instead of Start).
        // Shortest way there: call 1 leaves the while and passes A, call 2 passes B, call 3
        // goes to Work, call 4 finishes the circle, call 5 runs the deroute.
        (
            "drop the break after a deroute",
            mutate(&h, "GotoBlock(0);\n        break;", "GotoBlock(0);\n"),
            5,
        ),
        // the global exception fires when its condition is false
        ("invert a condition", mutate(&h, "FP_C(\"too_far()\")", "!FP_C(\"too_far()\")"), 1),
        // the global exception goes to Work instead of Back
        ("wrong exception target", mutate(&h, "GotoBlock(2); return;", "GotoBlock(1); return;"), 1),
        // a set stage loses its code
        ("drop a statement", mutate(&h, "FP_X(\"mode = 1\");", ";"), 1),
        // the while test no longer breaks when entering the body: the body runs in the same call
        (
            "NextStageAndBreak becomes NextStage",
            mutate(&h, "else NextStageAndBreak();", "else { nav_goto_next_stage(); }"),
            1,
        ),
    ];
    for (name, mutated, calls) in cases {
        assert_ne!(mutated, h, "{name}: mutation changed nothing");
        let r = validate_header(&fp, &mutated, &opts())
            .unwrap_or_else(|e| panic!("{name}: driver does not build: {e}"));
        let cx = r
            .counterexample
            .unwrap_or_else(|| panic!("{name}: the validator did not catch the mutation"));
        eprintln!(
            "{name}: caught after {} call(s), answers {:?}: {}",
            cx.calls, cx.answers, cx.what
        );
        assert_eq!(cx.calls, calls, "{name}: shortest counterexample length");
        // the driver's question limit (the static bound) stops looping calls quickly
        assert!(!cx.what.contains("died"), "{name}: {}", cx.what);
    }
}

mod common;

/// Condition texts the semantics asks within `depth` calls (every answer explored).
fn conditions_asked(
    fp: &vouch_fpl::passes::fp::Fp,
    depth: usize,
) -> std::collections::HashSet<String> {
    use vouch_fpl::semantics::explore::{enumerate_call, state_key};
    use vouch_fpl::semantics::trace::Event;
    let mut interp = vouch_fpl::semantics::Interp::new(fp);
    let mut seen = std::collections::HashSet::new();
    let mut asked = std::collections::HashSet::new();
    let mut level = vec![interp.state.clone()];
    for _ in 0..depth {
        let mut next = Vec::new();
        for st in &level {
            let tree = enumerate_call(&mut interp, st, 100_000).expect("interpreter");
            for p in tree.paths {
                for e in &p.events {
                    if let Event::Cond { text, .. } = e {
                        asked.insert(text.clone());
                    }
                }
                if seen.insert(state_key(&interp, &p.state)) {
                    next.push(p.state);
                }
            }
        }
        level = next;
    }
    asked
}

/// On real plans too: inverting the first condition of `auto_nav` (a global exception, or the
/// first condition of a block) is caught on every fourth corpus plan where the semantics asks
/// that condition within the explored depth (elsewhere the mutated code is dead).
#[test]
fn inverted_first_condition_is_caught_on_corpus_plans() {
    use rayon::prelude::*;
    let Some(_cc) = common::c_compiler() else { return };
    let Some(dir) = common::corpus_dir() else { return };
    let plans: Vec<_> = common::corpus_plans(&dir).into_iter().step_by(4).collect();
    let results: Vec<(String, Option<bool>)> = plans
        .par_iter()
        .map(|p| {
            let plan = vouch_fpl::front::parse_file(p).expect("corpus plan parses");
            let fp = vouch_fpl::passes::lower::lower(&plan).expect("lowers");
            let h = compile_plan(
                &plan,
                &EmitOptions { flavor: Flavor::Instrumented, ..EmitOptions::default() },
            )
            .expect("compiles");
            let name = p.display().to_string();
            let Some(start) = h.find("static inline void auto_nav(void)") else {
                return (name, None);
            };
            let Some(i) = h[start..].find("FP_C(\"").map(|i| i + start) else {
                return (name, None);
            };
            let lit_start = i + "FP_C(\"".len();
            let Some(len) = h[lit_start..].find("\")") else { return (name, None) };
            let text = h[lit_start..lit_start + len].replace("\\\"", "\"").replace("\\\\", "\\");
            if !conditions_asked(&fp, 8).contains(&text) {
                return (name, None);
            }
            let mutated = format!("{}!{}", &h[..i], &h[i..]);
            let r = validate_header(
                &fp,
                &mutated,
                &Options { depth: 8, random_runs: 1, random_steps: 200, ..Options::default() },
            )
            .expect("driver builds");
            (name, Some(r.counterexample.is_some()))
        })
        .collect();
    let missed: Vec<&String> =
        results.iter().filter(|r| r.1 == Some(false)).map(|r| &r.0).collect();
    let checked = results.iter().filter(|r| r.1.is_some()).count();
    eprintln!(
        "inverted first condition: caught on {checked} of {} plans (others: condition not reached)",
        results.len()
    );
    assert!(checked >= 20, "only {checked} plans reach their first condition");
    assert!(missed.is_empty(), "mutation not caught on: {missed:?}");
}
