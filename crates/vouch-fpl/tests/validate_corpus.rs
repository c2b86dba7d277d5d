//! Translation validation on the corpus: for every plan upstream compiles, the compiled
//! `auto_nav` (instrumented header + stub runtime, built with the system `cc`) and the
//! reference interpreter agree on every call path and operator jump from every reachable state
//! pair (the walk reaches its fixpoint), and on seeded random runs.

mod common;

use std::time::Instant;
use vouch_fpl::evidence::validate::Options;

#[test]
fn every_corpus_plan_validates_to_the_fixpoint() {
    let Some(_cc) = common::c_compiler() else { return };
    let t0 = Instant::now();
    let opts = Options { random_runs: 3, random_steps: 300, ..Options::default() };
    let Some(results) = common::validate_corpus(&opts) else { return };
    let mut failures = Vec::new();
    let (mut states, mut transitions, mut second, mut random) = (0, 0, 0, 0);
    let mut slowest: Vec<(f64, &str, usize, usize)> = Vec::new();
    for (name, r) in &results {
        match r {
            Ok(rep) => {
                states += rep.states;
                transitions += rep.transitions;
                second += rep.second_runs;
                random += rep.random_calls;
                slowest.push((rep.seconds, name, rep.states, rep.transitions));
                if !rep.fixpoint {
                    failures.push(format!("{name}: no fixpoint ({:?})", rep.cut));
                }
                if let Some(cx) = &rep.counterexample {
                    failures.push(format!("{name}: {}", cx.render()));
                }
                assert!(rep.second_runs >= rep.runs - rep.joined, "{name}: every run repeated");
                assert!(rep.max_events_seen <= rep.bound.max_events, "{name}: bound");
                assert!(rep.abstracted.watched_bytes.is_some(), "{name}: data segment watched");
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    slowest.sort_by(|a, b| b.0.total_cmp(&a.0));
    eprintln!(
        "validate: {} plans to the fixpoint, {states} states, {transitions} transitions compared, {second} changed-state runs, {random} random calls, {:.1} s",
        results.len(),
        t0.elapsed().as_secs_f64()
    );
    for (s, name, st, tr) in slowest.iter().take(5) {
        eprintln!("  {name}: {st} states, {tr} transitions, {s:.2} s");
    }
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}
