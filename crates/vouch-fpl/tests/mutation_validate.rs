//! Mutation check of the validator: deliberately broken C back ends (the instrumented header
//! text of a crafted plan, edited the way a buggy emitter could produce it) must each be
//! caught, with the shortest counterexample; the unbroken headers must pass.
//!
//! Every expected length is derived by hand from the plans (see the comments), for the full
//! walk (operator jumps, runs repeated from a changed C state) and for natural runs only
//! (neither), where the deep mutants need more than 8 calls.

use std::path::Path;

use vouch_fpl::emit::{EmitOptions, Flavor, compile_plan};
use vouch_fpl::evidence::validate::{Counterexample, Options, validate_header};

fn plan_and_header(name: &str) -> (vouch_fpl::passes::fp::Fp, String) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans").join(name);
    let plan = vouch_fpl::front::parse_file(&p).expect("crafted plan parses");
    let fp = vouch_fpl::passes::lower::lower(&plan).expect("lowers");
    let h = compile_plan(
        &plan,
        &EmitOptions { flavor: Flavor::Instrumented, ..EmitOptions::default() },
    )
    .expect("compiles");
    (fp, h)
}

/// The default walk (fixpoint, operator jumps, changed-state runs), short random runs.
fn full() -> Options {
    Options { random_runs: 2, random_steps: 200, ..Options::default() }
}

/// Natural runs only: no operator jumps, no changed-state runs (hence exact states).
fn natural() -> Options {
    Options { operator_jumps: false, perturb: false, ..full() }
}

/// Replaces the first occurrence of `from` after `after` in `auto_nav` (asserting it exists,
/// so a change of the emitter's text shape fails here instead of weakening the test).
fn mutate_after(h: &str, after: &str, from: &str, to: &str) -> String {
    let start = h.find("static inline void auto_nav(void)").expect("auto_nav present");
    let start = h[start..].find(after).unwrap_or_else(|| panic!("'{after}' not found")) + start;
    let i =
        h[start..].find(from).unwrap_or_else(|| panic!("'{from}' not found in auto_nav")) + start;
    format!("{}{}{}", &h[..i], to, &h[i + from.len()..])
}

fn mutate(h: &str, from: &str, to: &str) -> String {
    mutate_after(h, "auto_nav", from, to)
}

fn caught(name: &str, fp: &vouch_fpl::passes::fp::Fp, h: &str, o: &Options) -> Counterexample {
    let r =
        validate_header(fp, h, o).unwrap_or_else(|e| panic!("{name}: driver does not build: {e}"));
    let cx = r
        .counterexample
        .unwrap_or_else(|| panic!("{name}: the validator did not catch the mutation"));
    eprintln!(
        "{name}: caught after {} call(s) / {} transition(s), answers {:?}, jumps {:?}: {}",
        cx.calls, cx.transitions, cx.answers, cx.jumps, cx.what
    );
    // the driver's question limit (the static bound) stops looping calls quickly
    assert!(!cx.what.contains("died"), "{name}: {}", cx.what);
    if cx.what == "different events or state" {
        replays(fp, &cx);
    }
    cx
}

/// The counterexample's answers and jumps, replayed on the interpreter the way `vouch fpl sim
/// --conditions --jumps` does, end in the state the counterexample gives for the semantics.
fn replays(fp: &vouch_fpl::passes::fp::Fp, cx: &Counterexample) {
    use vouch_fpl::semantics::oracle::Scripted;
    let mut interp = vouch_fpl::semantics::Interp::new(fp);
    let mut oracle = Scripted::new(cx.answers.clone());
    let run = interp.run_with_jumps(&mut oracle, cx.calls, &cx.jumps).expect("replays");
    assert_eq!(oracle.consumed(), cx.answers.len(), "every answer used");
    let last = run.steps.last().expect("at least one call");
    let a = last.after;
    let want = format!("S {} {} {} {}", a.block, a.stage, a.last_block, a.last_stage);
    assert!(cx.expected.contains(&want), "{want} in {:?}", cx.expected);
}

#[test]
fn unmutated_headers_pass() {
    let Some(_cc) = common::c_compiler() else { return };
    for name in ["mutation.xml", "deep.xml"] {
        let (fp, h) = plan_and_header(name);
        let r = validate_header(&fp, &h, &full()).expect("driver builds");
        assert!(r.passed(), "{name}: {:?}", r.counterexample);
        assert!(r.cut.is_none() && r.fixpoint, "{name}");
        assert!(r.transitions > 20, "explores the plan ({} transitions)", r.transitions);
        // no call of these plans has paths that join: every path is a run of its own
        assert_eq!((r.joined, r.runs as u128), (0, r.transitions), "{name}");
        assert_eq!(r.second_runs, r.runs, "{name}: every run repeated from a changed state");
    }
}

#[test]
fn every_mutation_is_caught() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header("mutation.xml");
    let swap = {
        let a = mutate(&h, "Stage(4)", "Stage(@@)");
        let b = mutate(&a, "Stage(5)", "Stage(4)");
        mutate(&b, "Stage(@@)", "Stage(5)")
    };
    // (name, mutated header, (calls, transitions) of the full walk, calls of natural runs)
    let cases: Vec<(&str, String, (usize, usize), usize)> = vec![
        // the first go is now labelled Stage(5): after call 1 nav_stage is 5, not 4
        ("swap two stages", swap, (1, 1), 1),
        // Work's deroute falls into the default stage (NextBlock(): Back instead of Start).
        // Natural: call 1 leaves the while and passes A, call 2 passes B, call 3 goes to
        // Work, call 4 finishes the circle, call 5 runs the deroute. With a jump to Work, the
        // circle and the deroute: 2 calls.
        (
            "drop the break after a deroute",
            mutate(&h, "GotoBlock(0);\n        break;", "GotoBlock(0);\n"),
            (2, 3),
            5,
        ),
        // the global exception fires when its condition is false
        (
            "invert a condition",
            mutate(&h, "FP_C(\"too_far()\")", "!FP_C(\"too_far()\")"),
            (1, 1),
            1,
        ),
        // the global exception goes to Work instead of Back
        (
            "wrong exception target",
            mutate(&h, "GotoBlock(2); return;", "GotoBlock(1); return;"),
            (1, 1),
            1,
        ),
        // a set stage loses its code
        ("drop a statement", mutate(&h, "FP_X(\"mode = 1\");", ";"), (1, 1), 1),
        // the while test no longer breaks when entering the body: the body runs in the same call
        (
            "NextStageAndBreak becomes NextStage",
            mutate(&h, "else NextStageAndBreak();", "else { nav_goto_next_stage(); }"),
            (1, 1),
            1,
        ),
    ];
    for (name, mutated, (calls, transitions), natural_calls) in cases {
        assert_ne!(mutated, h, "{name}: mutation changed nothing");
        let cx = caught(name, &fp, &mutated, &full());
        assert_eq!(
            (cx.calls, cx.transitions),
            (calls, transitions),
            "{name}: shortest counterexample"
        );
        let cx = caught(name, &fp, &mutated, &natural());
        assert_eq!(
            (cx.calls, cx.transitions),
            (natural_calls, natural_calls),
            "{name}: natural runs"
        );
    }
}

/// Mutants of `deep.xml` that natural runs only show after more than 8 calls: each is caught
/// with its shortest counterexample, and a walk bounded to 8 natural calls misses it.
#[test]
fn deep_mutants_are_caught() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header("deep.xml");
    let visit = "Block(1)";
    // (name, mutated header, full walk: (calls, transitions, kind), natural: (calls, kind))
    type Expect = (usize, usize, &'static str);
    let cases: Vec<(&str, String, Expect, (usize, &str))> = vec![
        // Count's loop of 10 iterations (one call each) stops at 9: call 10 leaves the loop
        // and derouts to Visit instead of running the tenth iteration. Jumps cannot help:
        // they enter a block at stage 0, before the loop's initialisation.
        (
            "for bound of 10 off by one",
            mutate(&h, "if (++_var_i > _var_i_to)", "if (++_var_i >= _var_i_to)"),
            (10, 10, "different events or state"),
            (10, "different events or state"),
        ),
        // The counter is not reset when Count starts again (the bound still is, and the
        // event of the `from` value stays). Natural: 11 calls run the loop and deroute to
        // Visit, call 12 raises Visit's exception back to Count, call 13 initialises the loop
        // again: the C counter is 12 and leaves the loop. The full walk sees it at call 1: the
        // counter is dead for the semantics there (the loop is about to be initialised), and
        // the run repeated with it changed leaves the loop at once.
        (
            "dropped counter reset",
            mutate(&h, "_var_i = FP_V(\"1\") - 1;", "(void)(FP_V(\"1\") - 1);"),
            (1, 1, "reads state the semantics says it cannot"),
            (13, "different events or state"),
        ),
        // Visit's exception also fires on the 12th call spent in Visit (a visit counter the
        // semantics does not have). Natural runs (exact states): Count takes 11 calls, and the
        // exception fires at call 23, the 12th in Visit. The full walk: jump to Visit, one call
        // there (one visit counted), jump to Count: the interpreter is back in its initial
        // state (the loop counters are dead there), the C has counted a visit.
        (
            "exception that fires on the 12th visit",
            mutate_after(
                &h,
                visit,
                "if ((nav_block != 0) && FP_C(\"alarm()\"))",
                "static uint8_t visits; if ((nav_block != 0) && (FP_C(\"alarm()\") || ++visits == 12))",
            ),
            (1, 3, "keeps state the semantics does not"),
            (23, "different events or state"),
        ),
    ];
    for (name, mutated, (calls, transitions, kind), (natural_calls, natural_kind)) in cases {
        assert_ne!(mutated, h, "{name}: mutation changed nothing");
        let cx = caught(name, &fp, &mutated, &full());
        assert_eq!(
            (cx.calls, cx.transitions),
            (calls, transitions),
            "{name}: shortest counterexample"
        );
        assert!(cx.what.contains(kind), "{name}: {}", cx.what);
        let cx = caught(name, &fp, &mutated, &natural());
        assert_eq!(
            (cx.calls, cx.transitions),
            (natural_calls, natural_calls),
            "{name}: natural runs"
        );
        assert!(cx.what.contains(natural_kind), "{name}: {}", cx.what);
        assert!(cx.calls > 8, "{name}: beyond 8 calls");
        let bounded = Options { depth: Some(8), random_runs: 0, ..natural() };
        let r = validate_header(&fp, &mutated, &bounded).expect("driver builds");
        assert!(r.passed() && !r.fixpoint, "{name}: 8 natural calls do not show it");
    }
}

/// A loop bounded by a plan variable: its counters are merged by class, and every run is
/// repeated with the counter and the bound moved within the class, so a test that also leaves
/// the loop when the counter reaches 40 is caught although no explored bound gets there.
#[test]
fn symbolic_bound_mutants_are_caught() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header("symbolic.xml");
    let r = validate_header(&fp, &h, &full()).expect("driver builds");
    assert!(r.passed() && r.fixpoint, "{:?}", r.counterexample);
    assert_eq!(r.abstracted.symbolic_loops.len(), 1);
    let mutated =
        mutate(&h, "if (++_var_n > _var_n_to)", "if (++_var_n > _var_n_to || _var_n == 40)");
    let cx = caught("counter compared with a constant", &fp, &mutated, &full());
    // call 1 enters the loop with laps = 2 (answer 4: the first bound whose body state has
    // another iteration left); call 2, repeated with the pair shifted by 38, leaves the loop
    assert!(cx.what.contains("reads state the semantics says it cannot"), "{}", cx.what);
    assert_eq!((cx.calls, cx.transitions, cx.answers.clone()), (2, 2, vec![4]));
    let mutated = mutate(&h, "_var_n_to = FP_V(\"laps\");", "_var_n_to = FP_V(\"laps\") + 1;");
    let cx = caught("bound off by one", &fp, &mutated, &full());
    assert_eq!((cx.calls, cx.transitions), (1, 1));
}

/// A C call that crashes is a disagreement (the driver is restarted and the walk goes on).
#[test]
fn a_crash_is_reported_on_its_path() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header("mutation.xml");
    let mutated = mutate(&h, "FP_X(\"mode = 1\");", "*(volatile int *)0 = 0;");
    let r = validate_header(&fp, &mutated, &full()).expect("driver builds");
    let cx = r.counterexample.expect("caught");
    // the set stage runs in call 1
    assert!(cx.what.contains("died"), "{}", cx.what);
    assert_eq!(cx.calls, 1);
    assert!(r.abstracted.restarts >= 1);
}

/// A static the declaration scan cannot read (a name in parentheses without `*`, `(seen)`,
/// which it takes for a function declarator) is still seen: the driver watches the whole
/// writable data segment.
#[test]
fn unregistered_static_storage_is_watched() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header("deep.xml");
    let mutated = mutate_after(
        &h,
        "Block(1)",
        "if ((nav_block != 0) && FP_C(\"alarm()\"))",
        "static uint8_t (seen); if ((nav_block != 0) && (FP_C(\"alarm()\") || ++(seen) == 0))",
    );
    let cx = caught("hidden static", &fp, &mutated, &full());
    assert!(cx.what.contains("does not see"), "{}", cx.what);
    // jump to Visit, one call there with alarm() false
    assert_eq!((cx.calls, cx.transitions), (1, 2));
}

mod common;

/// Condition texts the semantics asks in some reachable state (every answer, every operator
/// jump), found with the same walk as the validator's.
fn conditions_asked(fp: &vouch_fpl::passes::fp::Fp) -> std::collections::HashSet<String> {
    use vouch_fpl::semantics::space::{Space, SpaceOptions};
    use vouch_fpl::semantics::trace::Event;
    let mut space = Space::new(fp, SpaceOptions::default());
    let init = space.initial();
    let mut seen = std::collections::HashSet::from([space.key(&init)]);
    let mut asked = std::collections::HashSet::new();
    let mut queue = vec![init];
    while let Some(st) = queue.pop() {
        let (succ, _) = space.successors(&st).expect("interpreter");
        for s in succ {
            for e in &s.events {
                if let Event::Cond { text, .. } = e {
                    asked.insert(text.clone());
                }
            }
            if seen.insert(space.key(&s.state)) {
                queue.push(s.state);
            }
        }
    }
    asked
}

/// On real plans too: inverting the first condition of `auto_nav` (a global exception, or the
/// first condition of a block) is caught on every fourth corpus plan where the semantics asks
/// that condition in some reachable state (elsewhere the mutated code is dead).
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
            if !conditions_asked(&fp).contains(&text) {
                return (name, None);
            }
            let mutated = format!("{}!{}", &h[..i], &h[i..]);
            let r = validate_header(
                &fp,
                &mutated,
                &Options { random_runs: 1, random_steps: 200, ..Options::default() },
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
    // with operator jumps every block is reachable, so every first condition is asked
    assert_eq!(checked, results.len(), "plans that never ask their first condition");
    assert!(missed.is_empty(), "mutation not caught on: {missed:?}");
}

/// A call's paths are joined where the first loop of `wide.xml` is left: a second loop whose
/// initialisation reads the first loop's counter (dead there for the semantics) is caught on
/// the first call. With `rows` = 0 the first loop is left at once; its counter is put back at
/// the second loop's stage start, so the mutant starts the second loop one higher: with
/// `cols` = 1 the semantics enters the loop (stage 6) and the C leaves it (the deroute).
#[test]
fn a_read_of_a_counter_left_in_the_same_call_is_caught() {
    let Some(_cc) = common::c_compiler() else { return };
    let (fp, h) = plan_and_header("wide.xml");
    let mutated =
        mutate(&h, "_var_c = FP_V(\"1\") - 1;", "_var_c = FP_V(\"1\") - 1 + (_var_r != 1);");
    let cx = caught("second loop reads the first loop's counter", &fp, &mutated, &full());
    assert_eq!((cx.calls, cx.transitions, cx.answers.clone()), (1, 1, vec![0, 2]), "{}", cx.what);
}
